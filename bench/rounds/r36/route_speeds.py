"""Probe: the speeds a policy set's rules read, on the training split, clean and IMU-drawn.

Usage: ``python bench/rounds/r36/route_speeds.py OUT.json [--clips library:data/library/train] [--draws 10]
[--first-seed 1830000] [--sideways-speed 0.2]``

For every take (loaded as the policies get them, :func:`agents.evaluate.reference_clips`) the medians the rules of
:class:`agents.policy_set.PolicySet` read (m/s): along the pelvis heading and across it
(:func:`agents.policy_set.heading_frame_velocity`) and on the ground (:func:`agents.policy_set.median_ground_speed`),
clean and over ``--draws`` IMU draws at strength 1 (draw ``j`` of take ``i`` has artefact seed ``first_seed + 100 j +
i``), and how many draws send it across ``--sideways-speed`` each way. Prints the takes by content and the margin of the
sideways rule: the largest across-heading speed of a take that is not a sideways walk, clean and in any draw. Reads
the training split only: the rules' speeds are set from it.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[3]))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # bench/, for json_report

from agents.evaluate import corrupted, reference_clips  # noqa: E402
from agents.policy_set import heading_frame_velocity, median_ground_speed  # noqa: E402
from envs.config import MimicConfig  # noqa: E402
from json_report import emit_json  # noqa: E402
from reference_motion.motion import Motion  # noqa: E402
from reference_motion.motion_library import labels  # noqa: E402

SIDEWAYS = ("walk-left", "walk-right")
"""The contents the sideways expert trains on."""


def speeds(motion: Motion) -> dict[str, float]:
    """The medians (m/s) the rules read: ``along`` and ``across`` the pelvis heading, and ``ground``."""
    along, across = np.median(heading_frame_velocity(motion.qpos, motion.fps), axis=0)
    return {"along": float(along), "across": float(across), "ground": median_ground_speed(motion.qpos, motion.fps)}


def clean_and_drawn(clips: list[str], draws: int, first_seed: int) -> tuple[list[Motion], list[list[Motion]]]:
    """The takes of ``clips`` as the policies get them, and ``draws`` IMU-corrupted copies of them all at strength 1
    (draw ``j`` of take ``i`` has artefact seed ``first_seed + 100 j + i``)."""
    clean = reference_clips(clips, "humanoid_1seg", MimicConfig(), None, 1.0, 0)
    return clean, [corrupted(clean, "imu", 1.0, first_seed + 100 * j) for j in range(draws)]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", help="the JSON to write")
    p.add_argument("--clips", nargs="+", default=["library:data/library/train"])
    p.add_argument("--draws", type=int, default=10)
    p.add_argument("--first-seed", type=int, default=1830000)
    p.add_argument("--sideways-speed", type=float, default=0.2)
    args = p.parse_args()
    clean, drawn = clean_and_drawn(args.clips, args.draws, args.first_seed)
    takes = []
    for i, motion in enumerate(clean):
        content = labels(motion.name.split(":")[-1])[0]
        imu = [speeds(draw[i]) for draw in drawn]
        across = np.array([s["across"] for s in imu])
        takes.append({"take": motion.name, "content": content, "clean": speeds(motion),
                      "imu_across_min": float(across.min()), "imu_across_max": float(across.max()),
                      "draws_sideways": int((np.abs(across) > args.sideways_speed).sum())})
    others = [t for t in takes if t["content"] not in SIDEWAYS and t["clean"]["ground"] <= 2.0
              and t["clean"]["along"] >= 0]
    sideways = [t for t in takes if t["content"] in SIDEWAYS]
    margin = {"others_clean_max_abs_across": max(abs(t["clean"]["across"]) for t in others),
              "others_imu_max_abs_across": max(max(abs(t["imu_across_min"]), abs(t["imu_across_max"])) for t in others),
              "others_routed_sideways_in_draws": sum(t["draws_sideways"] for t in others),
              "sideways_clean_abs_across": [min(abs(t["clean"]["across"]) for t in sideways),
                                            max(abs(t["clean"]["across"]) for t in sideways)],
              "sideways_clean_above": sum(abs(t["clean"]["across"]) > args.sideways_speed for t in sideways),
              "sideways_takes": len(sideways)}
    for t in takes:
        c = t["clean"]
        print(f"{t['take'].split('#')[-1]:<42} along {c['along']:+.2f} across {c['across']:+.2f} ground "
              f"{c['ground']:.2f}  IMU across {t['imu_across_min']:+.2f}..{t['imu_across_max']:+.2f}  "
              f"sideways in {t['draws_sideways']} of {args.draws} draws")
    print("forward and slow takes (not sideways walks): largest |across| clean "
          f"{margin['others_clean_max_abs_across']:.3f}, in any draw {margin['others_imu_max_abs_across']:.3f} m/s; "
          f"routed sideways in {margin['others_routed_sideways_in_draws']} take-draws; sideways walks clean "
          f"{margin['sideways_clean_abs_across'][0]:.2f}-{margin['sideways_clean_abs_across'][1]:.2f} m/s, "
          f"{margin['sideways_clean_above']} of {margin['sideways_takes']} above {args.sideways_speed}")
    emit_json({"clips": args.clips, "draws": args.draws, "first_seed": args.first_seed,
               "sideways_speed_mps": args.sideways_speed, "margin": margin, "takes": takes}, args.out)


if __name__ == "__main__":
    main()
