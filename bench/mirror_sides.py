"""Probe: does a policy perform both sides of a clip? Each policy's plain actor on each clip and on
its mirror image, and its symmetric actor.

Usage: ``python bench/mirror_sides.py --policies models/mimic_general_robust models/mimic_general_480
models/mimic_general_dashes models/mimic_general_stance_avg [--clips deepmimic:walker/turn_right0]
[--episodes 8] [--ground] [--swing-lift [DEG]] [--json [OUT]]``

A policy trained on every clip and its mirror image (``train_ppo.py --mirror``) may still perform
one side and not the other. The environment is mirror symmetric (``tests/test_mirror.py``), so the
plain actor on the mirror image is what the policy's mirror image (``agents/mirror_policy.py``) does
on the clip, and the symmetric actor (``--mirror-average``, the mean of the two actions) scores the
same on either side: it is printed once. Clips as evaluation loads them, clean; ``--episodes``
rollouts per clip and side from the same start frames (``evaluate.py``'s offsets). With ``--ground``
and ``--swing-lift`` every side is tracked as evaluation prepares a take (set on the floor, lifted in
backward swing) and judged against it as given, as ``evaluate.py`` does with them.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.grounding import add_grounding_option, grounding_of
from reference_motion.swing_lift import add_swing_lift_options, swing_lift_of
from reference_motion.transforms import mirror


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True, help="policy directories or run checkpoints")
    p.add_argument("--clips", nargs="+", default=["deepmimic:walker/turn_right0"])
    p.add_argument("--episodes", type=int, default=8, help="rollouts per clip and side")
    add_grounding_option(p, "every side is tracked set on the floor and judged against it as given")
    add_swing_lift_options(p, "every side is tracked lifted and judged against it as given")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    lift, grounding = swing_lift_of(args), grounding_of(args)
    rows = []
    for path in args.policies:
        policy = load_policy(path)
        for clip in reference_clips(args.clips, FOOT_MODELS[policy.foot], MimicConfig(), None, 1.0, 0):
            def elr(motion, symmetric=False):
                tracked, judged = tracked_and_judged([motion], None, grounding=grounding, lift=lift)
                return evaluate_tracking(policy, tracked, judged, episodes=args.episodes,
                                         mirror_average=symmetric)[0]["ELR_mean"]
            row = {"policy": path, "clip": clip.name, "plain": elr(clip), "plain_on_mirror_image": elr(mirror(clip)),
                   "symmetric": elr(clip, symmetric=True)}
            rows.append(row)
            print(f"{path:<40} {clip.name:<36} plain {row['plain']:.3f}  on its mirror image "
                  f"{row['plain_on_mirror_image']:.3f}  symmetric actor {row['symmetric']:.3f}", flush=True)
    emit_json({"clips": args.clips, "episodes": args.episodes, "grounding": asdict(grounding) if grounding else None,
               "swing_lift": asdict(lift) if lift else None, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
