"""vGRF-guided footskate cleanup (underpressure §6) on IMU-corrupted held-out clips.

Usage: ``python bench/footskate_cleanup.py [--vgrf models/vgrf] [--frames 300] [--strength 1]
[--takes 1] [--ablate] [--plot OUT.png] [--json [OUT]]``

Each of ADAPT's three held-out walker clips is looped to ``--frames`` frames and corrupted with IMU
artefacts ``--takes`` times (seeds 1000, 1001, 1002 — the evaluation seeds of the PPO policies —
then 1010, 1011, 1012, and so on), and each take is cleaned. Reported
per clip and on average: contact foot speed before and after (mean horizontal speed of the sole
points under Ψ+Γ contacts, UnderPressure's measure), its reduction (goal ≥ 80%), the mean joint
displacement (goal ≤ 3 cm), hinge jitter after/before (mean absolute jerk,
:func:`~reference_motion.quality.jitter`), the hinges' excursion beyond their ranges before and
after (:func:`~reference_motion.quality.range_excursion`), and the wall time.

``--ablate`` also runs the cleanup with each of our departures from the paper switched off in turn
(:class:`~perception.cleanup.CleanupConfig`) and prints one line per variant.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.cleanup import CleanupConfig, CleanupResult, cleanup
from perception.plots import plot_cleanup
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion
from reference_motion.motion import Motion
from reference_motion.quality import jitter, range_excursion

HELD_OUT = ("deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1")
ABLATIONS = {
    "without L_pose": dict(w_pose=0.0),
    "without targets between contacts": dict(swing_weight=0.0),
    "without L_limit": dict(w_limit=0.0),
    "without L_smooth": dict(w_smooth=0.0, w_smooth_legs=0.0),
    "100 iterations (UnderPressure's N)": dict(iterations=100),
}
"""Variants run by ``--ablate``: CleanupConfig overrides."""
AVERAGED = ("foot_speed_before_mps", "foot_speed_after_mps", "reduction", "joint_shift_cm", "jitter_ratio",
            "range_excursion_before_rad", "range_excursion_after_rad", "wall_s")


def clean_clip(motion: Motion, net, config: CleanupConfig) -> tuple[dict, CleanupResult]:
    """Cleans ``motion``; returns its row of measurements and the result."""
    start = time.perf_counter()
    r = cleanup(motion, net, config)
    wall = time.perf_counter() - start
    columns, ranges = load_model(motion.model).hinge_ranges
    return {"foot_speed_before_mps": r.foot_speed_before, "foot_speed_after_mps": r.foot_speed_after,
            "reduction": 1 - r.foot_speed_after / r.foot_speed_before if r.foot_speed_before else 0.0,
            "joint_shift_cm": 100 * r.joint_shift_m, "contact_share": float(r.contacts.mean()),
            "jitter_ratio": jitter(r.motion.qpos[:, 7:], motion.fps) / jitter(motion.qpos[:, 7:], motion.fps),
            "range_excursion_before_rad": range_excursion(motion.qpos[:, columns], ranges),
            "range_excursion_after_rad": range_excursion(r.motion.qpos[:, columns], ranges), "wall_s": wall}, r


def summary(label: str, row: dict) -> str:
    return (f"{label:<36} foot speed {row['foot_speed_before_mps']:.3f} -> {row['foot_speed_after_mps']:.3f} m/s "
            f"({row['reduction']:.1%} less), joints moved {row['joint_shift_cm']:.2f} cm, jitter x{row['jitter_ratio']:.2f}, "
            f"out of range {row['range_excursion_before_rad']:.3f} -> {row['range_excursion_after_rad']:.3f} rad, "
            f"{row['wall_s']:.0f} s")


def run(takes: list[tuple[str, int, Motion]], net, config: CleanupConfig,
        verbose: bool) -> tuple[list[dict], dict, CleanupResult]:
    """Rows of :func:`clean_clip` for ``(clip, seed, motion)`` takes, their means, and the first
    take's result."""
    rows, results = [], []
    for clip, seed, motion in takes:
        row, result = clean_clip(motion, net, config)
        rows.append({"clip": clip, "seed": seed, **row})
        results.append(result)
        if verbose:
            print(summary(f"{clip} ({seed})", rows[-1]))
    return rows, {k: float(np.mean([r[k] for r in rows])) for k in AVERAGED}, results[0]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    p.add_argument("--frames", type=int, default=300)
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--takes", type=int, default=1, help="corrupted takes (artefact seeds) per clip")
    p.add_argument("--ablate", action="store_true", help="also run each departure from the paper switched off")
    p.add_argument("--plot", type=Path, help="PNG of the first take's foot speeds before and after")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    net = load_network(args.vgrf, "vgrf")
    takes = []
    for i, clip in enumerate(HELD_OUT):
        motion = load_motion(clip, min_frames=args.frames)
        motion = motion.with_qpos(motion.qpos[:args.frames])
        for k in range(args.takes):
            seed = 1000 + i + 10 * k
            takes.append((clip, seed, corrupt(motion, ArtefactRecipe.imu(args.strength), seed)))
    config = CleanupConfig()
    rows, mean, first = run(takes, net, config, verbose=True)
    print(summary("mean", mean))
    if args.plot:
        clip, seed, motion = takes[0]
        plot_cleanup(args.plot, first.soles_before, first.soles_after, first.contacts, motion.fps,
                     f"{clip}, IMU strength {args.strength:g} (seed {seed}): foot speed before and after cleanup")
    worst = {"reduction": min(r["reduction"] for r in rows), "joint_shift_cm": max(r["joint_shift_cm"] for r in rows)}
    print(f"worst take: {worst['reduction']:.1%} less, {worst['joint_shift_cm']:.2f} cm")
    ablations = {}
    for label, overrides in ABLATIONS.items() if args.ablate else ():
        ablations[label] = run(takes, net, dataclasses.replace(config, **overrides), verbose=False)[1]
        print(summary(label, ablations[label]))
    emit_json({"takes": rows, "mean": mean, "worst": worst, "ablations": ablations, "strength": args.strength,
               "frames": args.frames, "config": dataclasses.asdict(config)}, args.json)


if __name__ == "__main__":
    main()
