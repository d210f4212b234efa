"""Do MuJoCo's contact settings cause the sinking and creeping feet of a simulated clip?

Usage: ``python bench/contact_options.py [--json [OUT]]`` (run one variant per process: the
humanoid's compiled model is shared within a process)

For each variant of the ``humanoid_1seg`` contact settings (``base``: the MJCF's own; ``solimp``:
impedance 0.9–0.99 instead of 0.9–0.95, stiffer at depth; ``elliptic``: elliptic friction cones
with ``impratio`` 10, which MuJoCo recommends against slip), performed as :mod:`agents.clean`
performs a clip: ``mimic_walk`` on DeepMimic's walk (10 s) and the generalist on the first four
validation takes (clean), zero-shot. Reported: foot skate and penetration (max) of the walk's
performance and their means over the four takes' performances, and the generalist's ELR on the
validation split (3 rollouts a take).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

import numpy as np

VARIANTS = ("base", "solimp", "elliptic")


def measure(variant: str) -> dict:
    """The figures of one variant (in this process: it changes the shared compiled model)."""
    import mujoco

    from agents.clean import POLICY_ALONE, clean_motion  # as measured: the policy alone
    from agents.evaluation import evaluate
    from agents.policy import load_policy
    from reference_motion.humanoid.model import load_model
    from reference_motion.library import expand_clips, load_motion
    from reference_motion.quality import motion_quality

    model = load_model("humanoid_1seg").model
    if variant == "solimp":
        model.geom_solimp[:, 1] = 0.99
    elif variant == "elliptic":
        model.opt.cone, model.opt.impratio = mujoco.mjtCone.mjCONE_ELLIPTIC, 10.0
    walk = clean_motion(load_policy("models/mimic_walk"), load_motion("deepmimic:walk", min_frames=600),
                        POLICY_ALONE, progress=False)
    general = load_policy("models/mimic_general")
    clips = expand_clips(["library:data/library/val"])
    summary, _ = evaluate(general.make_env(clips, artefacts=None), general, episodes=3, offset_step=30)
    takes = [motion_quality(clean_motion(general, load_motion(c, "humanoid_1seg"), POLICY_ALONE, progress=False)) for c in clips[:4]]
    return {"variant": variant, "walk_skate_mps": motion_quality(walk).foot_skate_mps,
            "walk_penetration_max_m": motion_quality(walk).penetration_max_m,
            "val_skate_mps": float(np.mean([q.foot_skate_mps for q in takes])),
            "val_penetration_max_m": float(np.mean([q.penetration_max_m for q in takes])),
            "val_ELR": summary["ELR_mean"]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--variant", choices=VARIANTS, help="measure one variant and print its JSON (used internally)")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    if args.variant:
        print(json.dumps(measure(args.variant)))
        return
    rows = []
    for v in VARIANTS:
        child = subprocess.run([sys.executable, __file__, "--variant", v], capture_output=True, text=True)
        if child.returncode:
            sys.exit(f"variant {v} failed:\n{child.stderr}")
        rows.append(json.loads(child.stdout.strip().splitlines()[-1]))
    for r in rows:
        print(f"{r['variant']:<9} walk: skate {r['walk_skate_mps']:.3f} m/s, penetration max {r['walk_penetration_max_m'] * 100:.1f} cm;"
              f" validation: skate {r['val_skate_mps']:.3f} m/s, penetration max {r['val_penetration_max_m'] * 100:.1f} cm, "
              f"ELR {r['val_ELR']:.3f}")
    from json_report import emit_json  # bench/json_report.py
    emit_json({"variants": rows}, args.json)


if __name__ == "__main__":
    main()
