"""Whole-clip transforms of a :class:`Motion`: resampling, time warping, time reversal, looping, left/right
mirroring.

All are pure: they return a new Motion and never modify their input.
"""

from __future__ import annotations

import numpy as np

from reference_motion import rotations as rot
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion, MotionError
from reference_motion.source import sample_poses

ENV_FPS = 60.0
"""Frame rate of reference motion inside the environments (SPEC "Conventions")."""


def resample(motion: Motion, fps: float = ENV_FPS) -> Motion:
    """Motion resampled to ``fps``: pelvis position and hinge angles linearly, pelvis
    orientation by slerp. The new clip spans the same duration (its last frame is the last
    sample at or before the original end)."""
    if fps <= 0:
        raise ValueError(f"fps must be positive, got {fps}")
    if abs(fps - motion.fps) < 1e-9:
        return motion
    times = np.arange(motion.n_frames) / motion.fps
    n = int(np.floor(motion.duration * fps + 1e-6)) + 1
    new_times = np.arange(n) / fps
    # Hinges and root position interpolate linearly: treat them together as "positions".
    values = np.concatenate([motion.root_pos, motion.hinges], axis=1)
    new_values, new_quat = sample_poses(times, values, motion.root_quat, new_times)
    qpos = np.concatenate([new_values[:, :3], new_quat, new_values[:, 3:]], axis=1)
    return motion.with_qpos(qpos, fps=float(fps), source=dict(motion.source, resampled_from_fps=motion.fps))


def time_warp(motion: Motion, speed: float) -> Motion:
    """The clip played ``speed`` times as fast (1.2 = 20% faster, 0.8 = 20% slower), at its own
    frame rate: ``n_frames`` becomes about ``n_frames / speed`` and every velocity (root speed,
    cadence) scales by ``speed``. Poses and the path walked are unchanged."""
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"time-warp speed must be a finite number > 0, got {speed}")
    if speed == 1.0:
        return motion
    played = motion.with_qpos(motion.qpos, fps=motion.fps * speed, name=f"{motion.name} (x{speed:g} speed)",
                              source=dict(motion.source, speed=speed * motion.source.get("speed", 1.0)))
    return resample(played, motion.fps)


def reversed_in_time(motion: Motion) -> Motion:
    """``motion`` played backwards: frame ``t`` becomes frame ``T - 1 - t``, at the same frame rate.

    Every velocity changes sign and every acceleration stays as it was. Rigid-body inverse dynamics,
    ``M(q) q̈ + C(q, q̇) q̇ + g(q) = τ + Jᵀ f``, is quadratic in ``q̇``, so the reversed clip needs the same
    joint torques and the same contact forces at every pose: a clip a body can perform stays one it
    can perform (joint damping, linear in ``q̇``, aside). A forward walk played backwards is a backward
    walk with the walk's posture, stride and timing (human backward walking is close to forward walking
    reversed in time: Thorstensson 1986, Grasso et al. 1998). Applied twice, the clip itself."""
    name = motion.name[:-len(" (reversed)")] if motion.name.endswith(" (reversed)") else motion.name + " (reversed)"
    return motion.with_qpos(motion.qpos[::-1].copy(), name=name,
                            source=dict(motion.source, reversed=not motion.source.get("reversed", False)))


def _cycle_transform(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """Yaw quaternion ``(4,)`` and horizontal translation ``(3,)`` taking the first frame's root
    onto the last frame's (one cycle of a looping clip)."""
    first, last = motion.qpos[0], motion.qpos[-1]
    dyaw = rot.yaw(last[3:7]) - rot.yaw(first[3:7])
    turn = rot.from_axis_angle(np.array([0.0, 0.0, 1.0]), dyaw)
    shift = last[:3] - rot.rotate(turn, first[:3])
    shift[2] = 0.0
    return turn, shift


def moved_roots(qpos: np.ndarray, turn: np.ndarray, shift: np.ndarray) -> np.ndarray:
    """``qpos (T, nq)`` with every frame's root moved by the rigid motion ``x' = turn·x + shift``
    (``turn (4,)`` a unit quaternion, ``shift (3,)`` m, world); the hinges unchanged (a copy)."""
    out = qpos.copy()
    out[:, :3] = rot.rotate(turn, qpos[:, :3]) + shift
    out[:, 3:7] = rot.normalize(rot.multiply(turn, qpos[:, 3:7]))
    return out


def turned(motion: Motion, angle_rad: float) -> Motion:
    """``motion`` turned about the world z axis through the origin by ``angle_rad`` (rad,
    counter-clockwise from above): the same motion walked another way."""
    turn = rot.from_axis_angle(np.array([0.0, 0.0, 1.0]), angle_rad)
    return motion.with_qpos(moved_roots(motion.qpos, turn, np.zeros(3)),
                            name=f"{motion.name} (turned {np.degrees(angle_rad):g}°)")


SEAM_BLEND_S = 0.25
"""Duration (s) over which a cyclic clip's end pose is eased onto its start pose before looping."""


def loop(motion: Motion, n_frames: int) -> Motion:
    """Repeat a cyclic clip to ``n_frames`` frames, carrying the root offset (and heading change)
    of each cycle over to the next, as DeepMimic's ``"wrap"`` clips do.

    The clip's last frame is taken as the cycle's end (so loop before resampling). Mocap cycles do
    not close exactly (DeepMimic's walk ends up to 0.45 rad away from its start pose), so the
    hinge mismatch is eased out linearly over the last :data:`SEAM_BLEND_S` of each cycle.
    """
    if not motion.loop:
        raise MotionError(f"motion {motion.name!r} is not cyclic (Loop != 'wrap'); it cannot be looped")
    if n_frames <= motion.n_frames:
        return motion.with_qpos(motion.qpos[:n_frames])
    template = motion.qpos.copy()
    k = min(motion.n_frames - 1, max(1, int(round(SEAM_BLEND_S * motion.fps))))
    ramp = np.linspace(0.0, 1.0, k + 1)[1:, None]
    template[-k:, 7:] += ramp * (template[0, 7:] - template[-1, 7:])
    turn, shift = _cycle_transform(motion)
    pieces = [template]
    previous = template
    while sum(len(p) for p in pieces) < n_frames:
        # each cycle is the previous one moved by the cycle transform x' = turn·x + shift
        nxt = moved_roots(previous[1:], turn, shift)
        previous = np.concatenate([previous[:1], nxt])
        pieces.append(nxt)
    qpos = np.concatenate(pieces)[:n_frames]
    return motion.with_qpos(qpos, source=dict(motion.source, looped_to_frames=n_frames))


def mirror_map(model_name: str) -> tuple[np.ndarray, np.ndarray]:
    """qpos permutation ``(nq,)`` and sign ``(nq,)`` of left/right mirroring (about the x–z plane).

    A hinge about x or z changes sign under the mirror, one about y does not; each left hinge
    swaps with its right twin.
    """
    hm = load_model(model_name)
    perm = np.arange(hm.nq)
    sign = np.ones(hm.nq)
    sign[[1, 4, 6]] = -1.0  # pelvis y, quaternion x and z
    for name in hm.hinge_names:
        i = hm.qpos_index(name)
        twin = {"l": "r", "r": "l"}.get(name[0]) if name[1] == "_" else None
        if twin is not None:
            perm[i] = hm.qpos_index(twin + name[1:])
        sign[i] = 1.0 if name.endswith("_y") else -1.0
    return perm, sign


def mirror(motion: Motion) -> Motion:
    """The clip performed by the other side of the body (left ↔ right), mirrored in world y."""
    perm, sign = mirror_map(motion.model)
    qpos = motion.qpos[:, perm] * sign
    name = motion.name[:-len(" (mirrored)")] if motion.name.endswith(" (mirrored)") else motion.name + " (mirrored)"
    return motion.with_qpos(qpos, name=name, source=dict(motion.source, mirrored=not motion.source.get("mirrored", False)))
