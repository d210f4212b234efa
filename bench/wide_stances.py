"""Probe: do policies keep takes walked with the feet wider apart? Each take re-made at wider stances.

Usage: ``python bench/wide_stances.py --policies models/mimic_general_dr runs/wide/checkpoints/step_N.zip
[--clips library:data/library/val] [--extra 0 0.15 0.3] [--episodes 10] [--json [OUT]]``

People walk with their feet anywhere from together to far apart: across the library's training
takes the mean stance width (left minus right hip abduction, ``bench/stance_width.py``) spans
-11° to 47°, the backward walks only -7° to 10°. Here every take of ``--clips`` is also performed
with the feet ``E`` metres further apart for each ``E`` of ``--extra``, the body swaying over the
stance foot so that it keeps its balance as the take had it
(:func:`reference_motion.stance.wider_stance`; the takes at 0 are pinned again all the same, so the
copies differ in the stance alone), and each policy tracks every copy ``--episodes`` times from the
same start frames. Clean takes; policy directories or run checkpoints. Prints ELR and SR90 per
policy and width, and the two takes whose ELR drops most from the narrowest to the widest.
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
from reference_motion.motion import Motion
from reference_motion.stance import wider_stance


def widened(clips: list[Motion], extra_m: float) -> list[Motion]:
    """``clips`` with the feet ``extra_m`` metres further apart (negative: closer)."""
    return [wider_stance(c, extra_m, label=f"{c.name} (stance {extra_m:+g} m)") for c in clips]


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
    p.add_argument("--extra", type=float, nargs="+", default=[0.0, 0.15, 0.3],
                   help="how much further apart the feet are (m; 0: the takes as they are, pinned again)")
    p.add_argument("--episodes", type=int, default=10, help="rollouts per take and width")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    if not all(np.isfinite(w) for w in args.extra) or len(args.extra) < 2:
        p.error(f"--extra must be at least two finite distances (m), got {args.extra}")
    if args.episodes < 1:
        p.error(f"--episodes must be >= 1, got {args.episodes}")
    policies = [load_policy(path) for path in args.policies]
    feet = {policy.foot for policy in policies}
    if len(feet) > 1:
        p.error(f"the policies drive different humanoids ({sorted(feet)}); compare one foot model")
    clips = reference_clips(args.clips, FOOT_MODELS[feet.pop()], MimicConfig(), None, 1.0, 0)
    copies = {w: widened(clips, w) for w in args.extra}
    rows = []
    for path, policy in zip(args.policies, policies):
        row = {"policy": path, "widths": {}}
        for w, takes in copies.items():
            summary, runs = evaluate_tracking(policy, takes, episodes=args.episodes)
            row["widths"][f"{w:g}"] = {"ELR": summary["ELR_mean"], "SR90": summary["SR90"],
                                       "per_clip": per_clip(runs)}
        rows.append(row)
        scores = "  ".join(f"{float(w):+g} m {v['ELR']:.3f} / {v['SR90']:.2f}" for w, v in row["widths"].items())
        drops = largest_drops(row["widths"][f"{min(args.extra):g}"]["per_clip"],
                              row["widths"][f"{max(args.extra):g}"]["per_clip"])
        print(f"{path:<48} ELR / SR90 at each width: {scores}; dropping most: "
              + ", ".join(f"{t} {a:.2f} -> {b:.2f}" for t, a, b in drops), flush=True)
    emit_json({"policies": args.policies, "clips": args.clips, "extra_m": args.extra,
               "episodes": args.episodes, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
