"""How well the reference itself agrees with its contact targets ĉ: the ceiling of the gait
reconstruction's contact F1.

Usage: ``python bench/gait_contact_ceiling.py [--policy models/mimic_gait] [--clips SOURCE ...]
[--heights 0.02 0.03] [--json [OUT]]``

``bench/gait_reconstruction.py`` scores the simulated contacts against ĉ, which perception
(the policy's ``contacts`` source: VGRFNet + Γ on the reference's joints) infers from the
reference. A simulation that reproduced the gait reference exactly (the reference with its toes
bent by the ToeRef targets, what the policy tracks and the RMSE is scored against) would have that
reference's own contacts, so their F1 against ĉ bounds what a policy can score, up to how contacts
are read off a pose. Here they are read kinematically, as :mod:`reference_motion.quality` does: a sole point
(LT, RT, LH, RH) within ``h`` of the apparent ground, for each ``--heights`` ``h`` (2 cm is the
project's default). Printed per clip and pooled: F1 against ĉ (all channels and per channel) and
the stance share of each.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.gait_metrics import contact_f1
from agents.policy import load_policy
from agents.reconstruct_gait import gait_targets
from envs.config import FOOT_MODELS
from gait_reconstruction import CLIPS  # bench/gait_reconstruction.py: the six test walks
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.gait import gait_parameters, gait_phases
from reference_motion.humanoid.model import CONTACT_CHANNELS
from reference_motion.library import expand_clips, load_motion
from reference_motion.quality import QualityConfig, motion_contacts


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_gait", help="a MimicGait-v0 policy: its perception source makes ĉ")
    p.add_argument("--clips", nargs="+", default=list(CLIPS), help="walks (SOURCE strings or clip sets)")
    p.add_argument("--heights", nargs="+", type=float, default=[0.02, 0.03], help="contact heights (m)")
    p.add_argument("--json", nargs="?", const="-", default=None, help="write the results as JSON (to OUT, or print)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    rows = []
    for clip in expand_clips(args.clips):
        reference = load_motion(clip, FOOT_MODELS[policy.foot])
        targets, _, gait_reference = gait_targets(policy, reference)  # the reference with the ToeRef toe bend
        row = {"clip": clip, "frames": reference.n_frames,
               "stance_targets": gait_parameters(gait_phases(targets)).as_dict()["stance"]}
        for h in args.heights:
            contacts = motion_contacts(gait_reference, replace(QualityConfig(), contact_height=h))
            row[f"{h:g}"] = {"f1": contact_f1(contacts, targets),
                             "f1_per_channel": {c: contact_f1(contacts[:, i:i + 1], targets[:, i:i + 1])
                                                for i, c in enumerate(CONTACT_CHANNELS)},
                             "stance": gait_parameters(gait_phases(contacts)).as_dict()["stance"]}
        rows.append(row)
        print(f"{clip.split('#')[-1]:<28} ĉ stance {row['stance_targets']:.2f}  " + "  ".join(
            f"{h * 100:g} cm: F1 {row[f'{h:g}']['f1']:.3f} stance {row[f'{h:g}']['stance']:.2f}" for h in args.heights),
            flush=True)
    mean = {f"{h:g}": float(np.mean([r[f"{h:g}"]["f1"] for r in rows])) for h in args.heights}
    print("mean F1 of the reference's own contacts against ĉ: " + ", ".join(
        f"{float(h) * 100:g} cm {v:.3f}" for h, v in mean.items()))
    emit_json({"policy": args.policy, "clips": rows, "mean_f1": mean}, args.json)


if __name__ == "__main__":
    main()
