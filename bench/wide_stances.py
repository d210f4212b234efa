"""Probe: do policies keep takes walked with the feet wider apart? Each take re-posed at wider stances.

Usage: ``python bench/wide_stances.py --policies models/mimic_general_dr runs/wide/checkpoints/step_N.zip
[--clips library:data/library/val] [--widths 0 6 12] [--episodes 10] [--json [OUT]]``

People walk with their feet anywhere from together to far apart: across the library's training
takes the mean stance width (left minus right hip abduction, ``bench/stance_width.py``) spans
-11° to 47°, the backward walks only -7° to 10°. Here every take of ``--clips`` is also performed
with each hip abducted ``W`` degrees more for each ``W`` of ``--widths`` (the stance ``2W`` wider;
:func:`reference_motion.transforms.posture_offsets` ``stance_width``, the ankles rolled back so the
soles stay as they were, the centre of mass kept on its path, the feet pinned again:
:func:`reference_motion.library.postured`), and each policy tracks every copy ``--episodes`` times
from the same start frames (the takes at 0 go through the same re-posing and re-pinning, so the
widths differ in the stance alone). Clean takes; policy directories or run checkpoints. Prints ELR
and SR90 per policy and width, and the two takes whose ELR drops most from the narrowest width of
``--widths`` to the widest.
"""

from __future__ import annotations

import argparse

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate_tracking, per_clip
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.library import postured
from reference_motion.motion import Motion
from reference_motion.transforms import posture_offsets


def widened(clips: list[Motion], width_deg: float) -> list[Motion]:
    """``clips`` with each hip abducted ``width_deg`` degrees more (negative: less)."""
    return [postured(c, posture_offsets(c.model, stance_width=np.radians(width_deg)), f"stance {width_deg:+g}°")
            for c in clips]


def largest_drops(narrow: list[dict], wide: list[dict], n: int = 2) -> list[tuple[str, float, float]]:
    """The ``n`` takes whose ELR falls most from ``narrow`` to ``wide`` (:func:`agents.evaluation.per_clip`
    rows, takes named with their ``(stance ...)`` suffix): ``[(take, ELR narrow, ELR wide), ...]``."""
    def take(row: dict) -> str:
        return row["clip"].rsplit(" (stance ", 1)[0]
    before = {take(r): r["ELR"] for r in narrow}
    drops = sorted(((take(r), before[take(r)], r["ELR"]) for r in wide), key=lambda t: t[2] - t[1])
    return drops[:n]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True, help="policy directories or run checkpoints")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--widths", type=float, nargs="+", default=[0.0, 6.0, 12.0],
                   help="extra abduction of each hip (degrees; 0: the takes as they are)")
    p.add_argument("--episodes", type=int, default=10, help="rollouts per take and width")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    if not all(np.isfinite(w) for w in args.widths) or len(args.widths) < 2:
        p.error(f"--widths must be at least two finite angles (degrees), got {args.widths}")
    if args.episodes < 1:
        p.error(f"--episodes must be >= 1, got {args.episodes}")
    policies = [load_policy(path) for path in args.policies]
    feet = {policy.foot for policy in policies}
    if len(feet) > 1:
        p.error(f"the policies drive different humanoids ({sorted(feet)}); compare one foot model")
    clips = reference_clips(args.clips, FOOT_MODELS[feet.pop()], MimicConfig(), None, 1.0, 0)
    copies = {w: widened(clips, w) for w in args.widths}
    rows = []
    for path, policy in zip(args.policies, policies):
        row = {"policy": path, "widths": {}}
        for w, takes in copies.items():
            summary, runs = evaluate_tracking(policy, takes, episodes=args.episodes)
            row["widths"][f"{w:g}"] = {"ELR": summary["ELR_mean"], "SR90": summary["SR90"],
                                       "per_clip": per_clip(runs)}
        rows.append(row)
        scores = "  ".join(f"{float(w):+g}° {v['ELR']:.3f} / {v['SR90']:.2f}" for w, v in row["widths"].items())
        drops = largest_drops(row["widths"][f"{min(args.widths):g}"]["per_clip"],
                              row["widths"][f"{max(args.widths):g}"]["per_clip"])
        print(f"{path:<48} ELR / SR90 at each width: {scores}; dropping most: "
              + ", ".join(f"{t} {a:.2f} -> {b:.2f}" for t, a, b in drops), flush=True)
    emit_json({"policies": args.policies, "clips": args.clips, "widths_deg": args.widths,
               "episodes": args.episodes, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
