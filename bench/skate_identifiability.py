"""Can a take show its own stance skate? Planted soles' velocity in IMU takes against the skate's.

Usage: ``python bench/skate_identifiability.py [--clips library:data/library/val] [--draws 3]
[--first-seed 780000] [--denoise models/imu_denoiser_soles_quint_mirror] [--json [OUT]]``

An IMU suit's stance skate (:func:`reference_motion.artefacts.corrupt`, ``skate``) slides the whole
body, planted feet included, out and back within each step. A cleaner can only take it out of the
pelvis path if the take shows it, and the clearest sign is a planted sole that moves. For every
frame where a sole point is planted in the *clean* take (an oracle: below 3 cm and slower than
0.2 m/s there), this compares that point's horizontal velocity in the corrupted take (central
differences) with the skate's own velocity (the time derivative of the corrupted minus the clean
pelvis path), and over each plant (a planted run of 10 frames or more) the point's displacement
with the skate's: if the first tracks the second, the skate can be read off the take; if the other
artefacts (the hinge angles' noise and drift moving the feet relative to the pelvis) swamp it, no
cleaner can. Rows: the skate alone, every IMU artefact kind, and every kind after the IMU denoiser
(which corrects the hinge angles, not the path). Draw ``d`` of clip ``i`` has artefact seed
``first_seed + d * len(clips) + i``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from agents.evaluate import reference_clips
from envs.config import MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.humanoid.model import load_model

PLANTED_HEIGHT_M = 0.03
"""A sole point of the clean take is planted below this height ..."""
PLANTED_SPEED_MPS = 0.2
"""... and slower than this over the floor."""


MIN_PLANT_FRAMES = 10
"""A planted run of a sole point this long or longer (1/6 s at 60 Hz) counts as one plant."""


def planted_motion(clean, given, model) -> dict[str, np.ndarray]:
    """Where the clean take plants a sole point: ``given``'s sole velocity ``sole_v`` and the skate's
    (the path error's) velocity ``skate_v`` on those frames, ``(N, 2)`` m/s; and over each plant of
    at least :data:`MIN_PLANT_FRAMES` frames, from its first frame to its last, the sole's
    displacement ``sole_d`` and the skate's ``skate_d``, ``(P, 2)`` m."""
    sole_clean = model.forward_kinematics(clean.qpos).foot_points[..., :2]  # (T, 4, 2)
    heights = model.forward_kinematics(clean.qpos).foot_points[..., 2]
    sole_given = model.forward_kinematics(given.qpos).foot_points[..., :2]
    skate = given.qpos[:, :2] - clean.qpos[:, :2]
    v_clean = np.gradient(sole_clean, axis=0) * clean.fps
    planted = (heights < PLANTED_HEIGHT_M) & (np.linalg.norm(v_clean, axis=-1) < PLANTED_SPEED_MPS)
    frames, points = np.nonzero(planted)
    out = {"sole_v": (np.gradient(sole_given, axis=0) * clean.fps)[frames, points],
           "skate_v": (np.gradient(skate, axis=0) * clean.fps)[frames]}
    sole_d, skate_d = [], []
    for k in range(planted.shape[1]):
        edges = np.diff(np.concatenate([[0], planted[:, k].astype(int), [0]]))
        for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)):
            if b - a >= MIN_PLANT_FRAMES:
                sole_d.append(sole_given[b - 1, k] - sole_given[a, k])
                skate_d.append(skate[b - 1] - skate[a])
    out["sole_d"], out["skate_d"] = np.reshape(sole_d, (-1, 2)), np.reshape(skate_d, (-1, 2))
    return out


def rms(v: np.ndarray) -> float:
    """RMS length of the vectors ``v (N, 2)``."""
    return float(np.sqrt((v ** 2).sum(-1).mean()))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--draws", type=int, default=3)
    p.add_argument("--first-seed", type=int, default=780000)
    p.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_soles_quint_mirror"))
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    model, config = load_model("humanoid_1seg"), MimicConfig()
    net = load_network(args.denoise, "denoiser")
    clean = reference_clips(args.clips, model.name, config, None, 1.0, 0)
    rows = {"skate alone": ("skate", False), "every IMU artefact": ("imu", False),
            f"every IMU artefact, after {args.denoise.name}": ("imu", True)}
    table = []
    for name, (kind, denoised) in rows.items():
        parts: dict[str, list[np.ndarray]] = {}
        for d in range(args.draws):
            given = reference_clips(args.clips, model.name, config, kind, 1.0, args.first_seed + d * len(clean))
            for c, g in zip(clean, given):
                for key, value in planted_motion(c, denoise(net, g) if denoised else g, model).items():
                    parts.setdefault(key, []).append(value)
        m = {key: np.concatenate(values) for key, values in parts.items()}
        row = {"takes": name, "planted_frames": len(m["sole_v"]), "plants": len(m["sole_d"]),
               "skate_velocity_rms_mps": rms(m["skate_v"]), "sole_velocity_rms_mps": rms(m["sole_v"]),
               "velocity_error_rms_mps": rms(m["sole_v"] - m["skate_v"]),
               "skate_displacement_rms_m": rms(m["skate_d"]), "sole_displacement_rms_m": rms(m["sole_d"]),
               "displacement_error_rms_m": rms(m["sole_d"] - m["skate_d"])}
        table.append(row)
        print(f"{name:<58} per frame: skate {row['skate_velocity_rms_mps']:.3f}, planted soles "
              f"{row['sole_velocity_rms_mps']:.3f}, soles minus skate {row['velocity_error_rms_mps']:.3f} m/s; "
              f"per plant: skate {100 * row['skate_displacement_rms_m']:.1f}, soles "
              f"{100 * row['sole_displacement_rms_m']:.1f}, soles minus skate "
              f"{100 * row['displacement_error_rms_m']:.1f} cm (RMS; {row['planted_frames']} point-frames, "
              f"{row['plants']} plants)", flush=True)
    emit_json({"clips": args.clips, "draws": args.draws, "first_seed": args.first_seed,
               "denoiser": str(args.denoise), "rows": table}, args.json)


if __name__ == "__main__":
    main()
