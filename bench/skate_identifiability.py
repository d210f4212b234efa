"""Can a take show its own stance skate? Planted soles' motion in IMU takes against the skate's.

Usage: ``python bench/skate_identifiability.py [--clips library:data/library/val] [--draws 3]
[--first-seed 780000] [--strength 1] [--denoise models/imu_denoiser_soles_quint_mirror] [--json [OUT]]``

An IMU suit's stance skate (:func:`reference_motion.artefacts.corrupt`, ``skate``) slides the whole
body, planted feet included, out and back within each step. A cleaner can only take it out of the
pelvis path if the take shows it, and the clearest sign is a planted sole that moves. Wherever a
sole point is planted in the *clean* take (an oracle: below :data:`PLANTED_HEIGHT_M` and slower
than :data:`PLANTED_SPEED_MPS` there), this compares that point's horizontal velocity in the
corrupted take (central differences) with the velocity of the pelvis path's error (the corrupted
minus the clean pelvis position: the skate, plus with every artefact kind the slow root drift and
the path bent by the heading drift), and over each plant of a sole point (a planted run of
:data:`MIN_PLANT_S` or longer; a foot's toe and heel each count) the point's displacement with the
path error's. If the first tracks the second, the skate can be read off the take; if the other
artefacts (the hinge angles' noise and drift moving the feet relative to the pelvis) swamp it, no
cleaner of the take alone can. Rows: the skate alone, every IMU artefact kind, and every kind after
the IMU denoiser (which corrects the hinge angles, not the path), at ``--strength``; the clean
soles' own speed on those frames is the measure's floor. Draw ``d`` of clip ``i`` has artefact
seed ``first_seed + d * len(clips) + i``.
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
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.cli import non_negative_float, positive_int
from reference_motion.footskate import contact_windows
from reference_motion.humanoid.model import HumanoidModel, load_model
from reference_motion.motion import Motion

PLANTED_HEIGHT_M = 0.03
"""A sole point of the clean take is planted below this height (the library's takes stand on z = 0) ..."""
PLANTED_SPEED_MPS = 0.2
"""... and slower than this over the floor."""
MIN_PLANT_S = 1 / 6
"""A planted run of a sole point this long or longer counts as one plant (10 frames at 60 Hz)."""


def planted_motion(clean: Motion, given: Motion, model: HumanoidModel) -> dict[str, np.ndarray]:
    """Where ``clean`` plants a sole point: ``given``'s sole velocity ``sole_v``, the pelvis path
    error's velocity ``path_v`` and the clean sole's own velocity ``clean_v`` on those frames,
    ``(N, 2)`` m/s; and over each plant (:data:`MIN_PLANT_S`), from its first frame to its last,
    the sole's displacement ``sole_d`` and the path error's ``path_d``, ``(P, 2)`` m."""
    points = model.forward_kinematics(clean.qpos).foot_points  # (T, 4, 3)
    sole_clean, heights = points[..., :2], points[..., 2]
    sole_given = model.forward_kinematics(given.qpos).foot_points[..., :2]
    path_error = given.qpos[:, :2] - clean.qpos[:, :2]
    v_clean = np.gradient(sole_clean, axis=0) * clean.fps
    planted = (heights < PLANTED_HEIGHT_M) & (np.linalg.norm(v_clean, axis=-1) < PLANTED_SPEED_MPS)
    frames, point = np.nonzero(planted)
    out = {"sole_v": (np.gradient(sole_given, axis=0) * clean.fps)[frames, point],
           "path_v": (np.gradient(path_error, axis=0) * clean.fps)[frames], "clean_v": v_clean[frames, point]}
    sole_d, path_d = [], []
    for k in range(planted.shape[1]):
        for a, b in contact_windows(planted[:, k]):
            if b - a >= MIN_PLANT_S * clean.fps:
                sole_d.append(sole_given[b - 1, k] - sole_given[a, k])
                path_d.append(path_error[b - 1] - path_error[a])
    out["sole_d"], out["path_d"] = np.reshape(sole_d, (-1, 2)), np.reshape(path_d, (-1, 2))
    return out


def rms(v: np.ndarray) -> float:
    """RMS length of the vectors ``v (N, 2)``."""
    return float(np.sqrt((v ** 2).sum(-1).mean()))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--draws", type=positive_int, default=3)
    p.add_argument("--first-seed", type=int, default=780000)
    p.add_argument("--strength", type=non_negative_float, default=1.0, help="artefact strength")
    p.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_soles_quint_mirror"))
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    net = load_network(args.denoise, "denoiser")
    model = load_model(net.model)
    clean = reference_clips(args.clips, model.name, MimicConfig(), None, args.strength, 0)
    seeds = [args.first_seed + d * len(clean) + i for d in range(args.draws) for i in range(len(clean))]
    takes = [c for _ in range(args.draws) for c in clean]
    skated = [corrupt(c, ArtefactRecipe.named("skate", args.strength), s) for c, s in zip(takes, seeds)]
    imu = [corrupt(c, ArtefactRecipe.named("imu", args.strength), s) for c, s in zip(takes, seeds)]
    rows = {"skate alone": skated, "every IMU artefact": imu,
            f"every IMU artefact, after {args.denoise.name}": [denoise(net, g) for g in imu]}
    table = []
    for name, given in rows.items():
        parts = [planted_motion(c, g, model) for c, g in zip(takes, given)]
        m = {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}
        row = {"takes": name, "planted_point_frames": len(m["sole_v"]), "sole_point_plants": len(m["sole_d"]),
               "clean_sole_velocity_rms_mps": rms(m["clean_v"]),
               "path_error_velocity_rms_mps": rms(m["path_v"]), "sole_velocity_rms_mps": rms(m["sole_v"]),
               "velocity_difference_rms_mps": rms(m["sole_v"] - m["path_v"]),
               "path_error_per_plant_rms_m": rms(m["path_d"]), "sole_per_plant_rms_m": rms(m["sole_d"]),
               "difference_per_plant_rms_m": rms(m["sole_d"] - m["path_d"])}
        table.append(row)
        print(f"{name:<58} per frame: path error {row['path_error_velocity_rms_mps']:.3f}, planted soles "
              f"{row['sole_velocity_rms_mps']:.3f}, difference {row['velocity_difference_rms_mps']:.3f} m/s "
              f"(clean soles {row['clean_sole_velocity_rms_mps']:.3f}); per plant: path error "
              f"{100 * row['path_error_per_plant_rms_m']:.1f}, soles {100 * row['sole_per_plant_rms_m']:.1f}, "
              f"difference {100 * row['difference_per_plant_rms_m']:.1f} cm (RMS; {row['planted_point_frames']} "
              f"point-frames, {row['sole_point_plants']} sole-point plants)", flush=True)
    emit_json({"clips": args.clips, "draws": args.draws, "first_seed": args.first_seed, "strength": args.strength,
               "denoiser": str(args.denoise), "rows": table}, args.json)


if __name__ == "__main__":
    main()
