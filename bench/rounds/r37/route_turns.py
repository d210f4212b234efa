"""Probe: the turn rate the policy set's turn rule reads, on the training takes, clean and IMU-drawn.

Usage: ``python bench/rounds/r37/route_turns.py OUT.json [--clips ...] [--draws 10] [--first-seed 1900000]
[--turn-rate 0.3]``

For every take (default: the library's training split and DeepMimic's training clips walk, run, walker/turn_left0 and
walker/turn_right0; loaded as the policies get them, :func:`agents.evaluate.reference_clips`) the rate at which its
pelvis heading turns (:func:`agents.policy_set.turn_rate`, rad/s), clean and over ``--draws`` IMU draws at strength 1
(``bench/rounds/r36/route_speeds.py``'s ``clean_and_drawn``), and
in how many draws it is above ``--turn-rate``. Prints the takes fastest first and the rule's margin: the fastest
turn of a take that is not one of DeepMimic's turns, clean and in any draw. Reads training takes only: the rule's rate
is set from them.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[3]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # bench/, for json_report

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "r36"))  # for route_speeds

from agents.policy_set import turn_rate  # noqa: E402
from json_report import emit_json  # noqa: E402
from route_speeds import clean_and_drawn  # noqa: E402

TRAINING = ["library:data/library/train", "deepmimic:walk", "deepmimic:run", "deepmimic:walker/turn_left0",
            "deepmimic:walker/turn_right0"]
"""The generalist's training takes."""
TURNS = ("deepmimic:walker/turn_left0", "deepmimic:walker/turn_right0")
"""The turns the turning expert trains on."""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", help="the JSON to write")
    p.add_argument("--clips", nargs="+", default=TRAINING)
    p.add_argument("--draws", type=int, default=10)
    p.add_argument("--first-seed", type=int, default=1900000)
    p.add_argument("--turn-rate", type=float, default=0.3)
    args = p.parse_args()
    clean, drawn = clean_and_drawn(args.clips, args.draws, args.first_seed)
    takes = []
    for i, motion in enumerate(clean):
        imu = np.array([turn_rate(draw[i].qpos, draw[i].fps) for draw in drawn])
        takes.append({"take": motion.name, "clean": turn_rate(motion.qpos, motion.fps), "imu_min": float(imu.min()),
                      "imu_max": float(imu.max()), "draws_turning": int((imu > args.turn_rate).sum())})
    others = [t for t in takes if not t["take"].startswith(TURNS)]
    turns = [t for t in takes if t["take"].startswith(TURNS)]
    margin = {"others_clean_max": max(t["clean"] for t in others), "others_imu_max": max(t["imu_max"] for t in others),
              "others_routed_in_draws": sum(t["draws_turning"] for t in others),
              "turns_clean": [t["clean"] for t in turns],
              "turns_imu_min": min((t["imu_min"] for t in turns), default=None)}
    for t in sorted(takes, key=lambda t: -t["imu_max"]):
        print(f"{t['take'].split('#')[-1]:<42} clean {t['clean']:.3f}  IMU {t['imu_min']:.3f}..{t['imu_max']:.3f} rad/s  "
              f"above {args.turn_rate} in {t['draws_turning']} of {args.draws} draws")
    print(f"takes other than the turns: fastest clean {margin['others_clean_max']:.3f}, in any draw "
          f"{margin['others_imu_max']:.3f} rad/s, above {args.turn_rate} in {margin['others_routed_in_draws']} take-draws; "
          + (f"the turns clean {', '.join(f'{r:.3f}' for r in margin['turns_clean'])}, slowest draw "
             f"{margin['turns_imu_min']:.3f}" if turns else "no turn among the takes"))
    emit_json({"clips": args.clips, "draws": args.draws, "first_seed": args.first_seed, "turn_rate_rad_s": args.turn_rate,
               "margin": margin, "takes": takes}, args.out)


if __name__ == "__main__":
    main()
