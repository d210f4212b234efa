"""How the contact touch-up's lift window trades floor penetration for floating and root jerk.

Usage: ``python bench/touch_up_settings.py [--policy models/mimic_general] [--clips library:data/library/val]
[--seed 6000] [--smooth 0 0.05] [--pin-limit none 0.05] [--json [OUT]]``

Each take (the validation split by default: settings are chosen there), cut to 10 s and
IMU-corrupted at strength 1 (seed 6000 + i), is performed zero-shot by ``--policy`` as
:func:`agents.clean.clean_motion` does it, then touched up between its re-anchors
(:func:`agents.clean.touched_up`) with each lift window ``--smooth`` (s either side) and each limit ``--pin-limit`` on how far pinning
may move a foot (:attr:`reference_motion.footskate.PinningConfig.max_correction_m`). Reported per
variant, as medians over the takes:
foot skate, floating, penetration (max, mean) and jitter of the input, of the simulation and of
the touched-up clip, how far the bodies moved, and the 99th percentile of the root's vertical
acceleration (m/s², second differences at 60 Hz), which a per-frame lift can raise at footfalls.
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

import envs  # noqa: F401  (registers the ids)
from adapted_cleaning import corrupted_take  # bench/adapted_cleaning.py: the scripts run from bench/
from agents.clean import POLICY_ALONE, clean_motion, reanchor_frames, touched_up
from agents.policy import load_policy
from json_report import emit_json
from reference_motion.library import expand_clips
from reference_motion.motion import Motion
from reference_motion.quality import motion_quality
from reference_motion.cli import or_none, positive_float
from reference_motion.touch_up import TOUCH_UP_PINNING

METRICS = ("foot_skate_mps", "floating_m", "penetration_max_m", "penetration_mean_m", "jitter")


def root_vertical_acceleration(motion: Motion) -> float:
    """99th percentile of the root's vertical acceleration magnitude (m/s², second differences)
    over the frames whose difference does not straddle one of ``motion``'s re-anchors (a jump)."""
    acc = np.abs(np.diff(motion.qpos[:, 2], n=2)) * motion.fps**2  # acc[t] spans frames t..t+2
    keep = np.ones(len(acc), dtype=bool)
    for b in reanchor_frames(motion):
        keep[max(0, b - 2):b] = False
    return float(np.percentile(acc[keep], 99))


def variant(smooth: float, limit: float | None) -> str:
    """The name of a touch-up variant: lift window (s) and pinning limit (m)."""
    return f"touched_smooth{smooth:g}_pin{'none' if limit is None else f'{limit:g}'}"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--smooth", type=float, nargs="+", default=[0.0, 0.05])
    p.add_argument("--pin-limit", type=or_none(positive_float), nargs="+", default=[None, 0.05],
                   help="PinningConfig.max_correction_m of each variant ('none': no limit)")
    p.add_argument("--seed", type=int, default=6000)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    policy = load_policy(args.policy)
    rows = []
    for i, clip in enumerate(expand_clips(args.clips)):
        reference = corrupted_take(clip, policy.foot, 10.0, 1.0, args.seed + i)
        simulated = clean_motion(policy, reference, POLICY_ALONE, progress=False)  # as measured: the policy alone
        row = {"clip": clip, "input": motion_quality(reference).as_dict(),
               "simulated": {**motion_quality(simulated).as_dict(), "root_acc_p99": root_vertical_acceleration(simulated)}}
        for smooth in args.smooth:
            for limit in args.pin_limit:
                pinning = replace(TOUCH_UP_PINNING, max_correction_m=limit)
                touched, report = touched_up(simulated, smooth_s=smooth, pinning=pinning)
                row[variant(smooth, limit)] = {**motion_quality(touched).as_dict(), **report.as_dict(),
                                               "root_acc_p99": root_vertical_acceleration(touched)}
        rows.append(row)
    summary = {}
    for key in ["input", "simulated"] + [variant(s, m) for s in args.smooth for m in args.pin_limit]:
        names = METRICS + (("root_acc_p99",) if key != "input" else ()) + (
            ("lift_mean_m", "body_shift_mean_m", "body_shift_max_m") if key.startswith("touched") else ())
        print(f"{key:<26}", end="")
        summary[key] = {k: float(np.median([r[key][k] for r in rows])) for k in names}
        print("  ".join(f"{k} {v:.4g}" for k, v in summary[key].items()))
    emit_json({"policy": args.policy, "clips": args.clips, "seed": args.seed, "summary": summary, "takes": rows}, args.json)


if __name__ == "__main__":
    main()
