"""vGRF-guided footskate cleanup (underpressure §6) on IMU-corrupted held-out clips.

Usage: ``python bench/footskate_cleanup.py [--vgrf models/vgrf] [--frames 300] [--json [OUT]]``

Each of ADAPT's three held-out walker clips is corrupted with IMU artefacts (strength 1, seeds
1000, 1001, 1002: the evaluation seeds of the PPO policies), cut to ``--frames`` frames and cleaned.
Reported per clip and on average: contact foot speed before and after (mean horizontal speed of
the sole points under Ψ+Γ contacts, UnderPressure's measure), its reduction (goal ≥ 80%), the
mean joint displacement (goal ≤ 3 cm), and the wall time.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.cleanup import CleanupConfig, cleanup
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.library import load_motion

HELD_OUT = ("deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--iterations", type=int, default=CleanupConfig().iterations)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    net = load_network(args.vgrf, "vgrf")
    rows = []
    for i, clip in enumerate(HELD_OUT):
        motion = corrupt(load_motion(clip, min_frames=args.frames), ArtefactRecipe.imu(args.strength), 1000 + i)
        motion = motion.with_qpos(motion.qpos[:args.frames])
        start = time.perf_counter()
        r = cleanup(motion, net, CleanupConfig(iterations=args.iterations))
        rows.append({"clip": clip, "seed": 1000 + i, "foot_speed_before_mps": r.foot_speed_before,
                     "foot_speed_after_mps": r.foot_speed_after,
                     "reduction": 1 - r.foot_speed_after / r.foot_speed_before if r.foot_speed_before else 0.0,
                     "joint_shift_cm": 100 * r.joint_shift_m, "contact_share": float(r.contacts.mean()),
                     "wall_s": time.perf_counter() - start})
        row = rows[-1]
        print(f"{clip:<32} foot speed {row['foot_speed_before_mps']:.3f} -> {row['foot_speed_after_mps']:.3f} m/s "
              f"({row['reduction']:.0%} less), joints moved {row['joint_shift_cm']:.1f} cm, {row['wall_s']:.0f} s")
    mean = {k: float(np.mean([r[k] for r in rows])) for k in ("foot_speed_before_mps", "foot_speed_after_mps",
                                                               "reduction", "joint_shift_cm", "wall_s")}
    print(f"{'mean':<32} foot speed {mean['foot_speed_before_mps']:.3f} -> {mean['foot_speed_after_mps']:.3f} m/s "
          f"({mean['reduction']:.0%} less), joints moved {mean['joint_shift_cm']:.1f} cm")
    emit_json({"clips": rows, "mean": mean, "strength": args.strength, "frames": args.frames,
               "iterations": args.iterations}, args.json)


if __name__ == "__main__":
    main()
