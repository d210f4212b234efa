"""Can the feet carry a clip? Where the centre of pressure of each reference frame must lie, against its feet.

Usage: ``python bench/support_feasibility.py [--clips library:data/library ...] [--model humanoid_1seg]
[--smooth-frames 2] [--json [OUT]]``

For each frame, MuJoCo's inverse dynamics (contacts off) gives the wrench the ground must apply to
the free root for the clip's accelerations (velocities smoothed by a Gaussian of ``--smooth-frames``
σ before differencing); the centre of pressure (CoP) of that wrench on the floor is where the
ground force must act. A physical character can only press through its soles, so a CoP away from
every foot on the floor (sole box's ground projection, box bottom within 3 cm of the floor) is a
frame the character cannot perform as given. Printed per clip: the median distance of the CoP
outside the supporting feet (0 when inside) and the share of frames with it more than 5 cm out (or
no foot down while the body is carried).
"""

from __future__ import annotations

import argparse
import copy

import mujoco
import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion

FOOT_GEOMS = ("l_foot_geom", "r_foot_geom")
OUT_M = 0.05
"""A CoP further than this outside the feet counts as a frame the feet cannot carry."""
DOWN_M = 0.03
"""A foot supports when its sole box's lowest corner is within this of the floor."""


def smoothed_accelerations(qvel: np.ndarray, fps: float, sigma_frames: float) -> np.ndarray:
    """``(T, nv)`` accelerations: ``qvel`` smoothed by a Gaussian of ``sigma_frames`` σ, then differenced."""
    if sigma_frames > 0:
        half = int(3 * sigma_frames)
        kernel = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma_frames) ** 2)
        kernel /= kernel.sum()
        padded = np.pad(qvel, ((half, half), (0, 0)), mode="edge")
        qvel = np.stack([np.convolve(padded[:, i], kernel, "valid") for i in range(qvel.shape[1])], axis=1)
    return np.gradient(qvel, 1.0 / fps, axis=0)


def centre_of_pressure(force: np.ndarray, torque: np.ndarray, point: np.ndarray) -> np.ndarray:
    """``(2,)`` the point on the floor (z = 0) about which the wrench ``force (3,)``, ``torque (3,)``
    (about ``point (3,)``; world, N and N·m) has no horizontal moment."""
    x = point[0] - (torque[1] + point[2] * force[0]) / force[2]
    y = point[1] + (torque[0] - point[2] * force[1]) / force[2]
    return np.array([x, y])


def distance_outside_box(xy: np.ndarray, centre: np.ndarray, axes: np.ndarray, half: np.ndarray) -> float:
    """Horizontal distance (m) of floor point ``xy (2,)`` from the ground projection of a box
    (``centre (3,)``, ``axes (3, 3)`` columns = box axes in world, ``half (3,)`` half-sizes); 0 inside.
    The box is taken as lying flat (its tilt ignored)."""
    local = axes.T @ np.array([xy[0] - centre[0], xy[1] - centre[1], 0.0])
    return float(np.hypot(*np.maximum(np.abs(local[:2]) - half[:2], 0.0)))


def support_errors(qpos: np.ndarray, qvel: np.ndarray, fps: float, model_name: str, sigma_frames: float) -> np.ndarray:
    """``(T,)`` m: per frame, the CoP's distance outside the supporting feet (inf: no foot down), NaN
    where the body is not carried (vertical ground force under a quarter of its weight: flight)."""
    humanoid = load_model(model_name)
    model = copy.copy(humanoid.model)  # the loaded model is shared: switch contacts off on a copy
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    data = mujoco.MjData(model)
    feet = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name) for name in FOOT_GEOMS]
    weight = float(model.body_subtreemass[1] * -model.opt.gravity[2])
    qacc = smoothed_accelerations(qvel, fps, sigma_frames)
    out = np.full(len(qpos), np.nan)
    for t in range(len(qpos)):
        data.qpos[:], data.qvel[:], data.qacc[:] = qpos[t], qvel[t], qacc[t]
        mujoco.mj_inverse(model, data)
        force = data.qfrc_inverse[0:3]
        if force[2] < 0.25 * weight:
            continue
        torque = data.xmat[1].reshape(3, 3) @ data.qfrc_inverse[3:6]  # the free joint's torque is in the root frame
        cop = centre_of_pressure(force, torque, data.xpos[1])
        gaps = []
        for g in feet:
            axes, half = data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
            lowest = data.geom_xpos[g][2] - np.abs(axes[2]) @ half
            if lowest < DOWN_M:
                gaps.append(distance_outside_box(cop, data.geom_xpos[g], axes, half))
        out[t] = min(gaps, default=np.inf)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", nargs="+", default=["library:data/library"], help="SOURCE strings or clip sets")
    parser.add_argument("--model", default="humanoid_1seg")
    parser.add_argument("--smooth-frames", type=float, default=2.0, help="Gaussian σ (frames) on the velocities")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    rows = []
    for clip in expand_clips(args.clips):
        motion = load_motion(clip, args.model)
        errors = support_errors(motion.qpos, motion.qvel, motion.fps, args.model, args.smooth_frames)
        carried = errors[np.isfinite(errors) | np.isinf(errors)]
        rows.append({"clip": clip, "frames": int(len(carried)),
                     "cop_outside_median_m": float(np.median(np.minimum(carried, 10.0))) if len(carried) else None,
                     "frames_outside": float(np.mean(carried > OUT_M)) if len(carried) else None})
    result = {"clips": args.clips, "model": args.model, "smooth_frames": args.smooth_frames, "outside_m": OUT_M,
              "rows": rows}
    if emit_json(result, args.json):
        return
    print(f"{'clip':<56}{'CoP out, median (cm)':>22}{'frames > 5 cm out':>20}")
    for r in rows:
        if r["frames"] == 0:
            print(f"{r['clip']:<56}{'no frame carried':>42}")
            continue
        print(f"{r['clip']:<56}{100 * r['cop_outside_median_m']:>22.1f}{100 * r['frames_outside']:>19.0f}%")


if __name__ == "__main__":
    main()
