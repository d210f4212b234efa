"""Probe: how two ways of widening a take's stance leave its balance.

Usage: ``python bench/stance_balance.py [--clips library:data/library#dataset-1_walk-back_normal_001 ...]
[--json [OUT]]``

A wider stance made by abducting both hips (:func:`reference_motion.transforms.posture_offsets`
``stance_width``, +6° and +12° per hip, :func:`reference_motion.library.postured`) against one made
by moving the feet apart and carrying the body as the inverted pendulum needs
(:func:`reference_motion.stance.wider_stance`, +0.15 m and +0.3 m). For each copy: the mean
sideways distance between the toes (along the line between the hips) and, in single support (one
foot's points planted, :func:`reference_motion.footskate.planted_points`), the median horizontal
distance from the centre of mass to the stance foot's sole points. A walk keeps its balance where
that distance stays as the take had it; the take's own steps do not pay for a larger one.
"""

from __future__ import annotations

import argparse

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.footskate import foot_channels, planted_points
from reference_motion.humanoid.model import CONTACT_CHANNELS, load_model
from reference_motion.library import load_motion, postured
from reference_motion.motion import Motion
from reference_motion.stance import wider_stance
from reference_motion.transforms import posture_offsets

DEFAULT_CLIPS = [f"library:data/library#dataset-1_{take}_001" for take in
                 ("walk-back_normal", "walk-back_angry", "walk_normal", "walk-left_normal")]


def balance(motion: Motion) -> dict:
    """The toes' mean sideways distance (m), the single-support frames, and the CoM's median
    horizontal distance from the stance foot in them (m)."""
    hm = load_model(motion.model)
    kin = hm.forward_kinematics(motion.qpos)
    hips = kin.body_pos[:, hm.body_names.index("l_thigh"), :2] - kin.body_pos[:, hm.body_names.index("r_thigh"), :2]
    side = hips / np.linalg.norm(hips, axis=1, keepdims=True)
    left, right = foot_channels("left"), foot_channels("right")
    toes = (kin.foot_points[:, CONTACT_CHANNELS.index("left_toe"), :2]
            - kin.foot_points[:, CONTACT_CHANNELS.index("right_toe"), :2])
    planted = planted_points(kin, motion.fps)
    on_left, on_right = planted[:, left].any(axis=1), planted[:, right].any(axis=1)
    distances = []
    for alone, points in ((on_left & ~on_right, left), (on_right & ~on_left, right)):
        foot = kin.foot_points[alone][:, points, :2].mean(axis=1)
        distances.append(np.linalg.norm(kin.com[alone, :2] - foot, axis=1))
    d = np.concatenate(distances)
    return {"toes_apart_m": float(np.abs(np.sum(toes * side, axis=1)).mean()), "single_support_frames": int(len(d)),
            "com_to_stance_foot_m": float(np.median(d)) if len(d) else float("nan")}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", default=DEFAULT_CLIPS)
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    rows = []
    for source in args.clips:
        take = load_motion(source)
        copies = {"as taken": take}
        for degrees in (6.0, 12.0):
            copies[f"hips +{degrees:g} deg"] = postured(
                take, posture_offsets(take.model, stance_width=np.radians(degrees)), f"hips +{degrees:g}")
        for extra in (0.15, 0.3):
            copies[f"pendulum +{extra:g} m"] = wider_stance(take, extra)
        for name, motion in copies.items():
            row = {"clip": source, "copy": name, **balance(motion)}
            rows.append(row)
            print(f"{source.rsplit('#', 1)[-1]:<36} {name:<18} toes apart {row['toes_apart_m']:.3f} m   CoM to the "
                  f"stance foot {row['com_to_stance_foot_m']:.3f} m ({row['single_support_frames']} single-support "
                  f"frames)", flush=True)
    emit_json({"clips": args.clips, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
