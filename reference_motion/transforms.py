"""Whole-clip transforms of a :class:`Motion`: resampling, time warping, time reversal, looping, left/right
mirroring, posture changes.

All are pure: they return a new Motion and never modify their input.
"""

from __future__ import annotations

from dataclasses import dataclass

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


MIRROR_PREFIXES = {"l_": "r_", "r_": "l_", "left_": "right_", "right_": "left_"}
"""Name prefixes of the left and right sides (bodies and hinges ``l_``/``r_``, contact channels
``left_``/``right_``) and each one's twin."""


def mirror_twin(name: str) -> str:
    """The name of a body, hinge or contact channel's mirror twin: ``l_…`` ↔ ``r_…`` and ``left_…`` ↔
    ``right_…``; one on the midline is its own twin."""
    for prefix, twin in MIRROR_PREFIXES.items():
        if name.startswith(prefix):
            return twin + name[len(prefix):]
    return name


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
        perm[i] = hm.qpos_index(mirror_twin(name))
        sign[i] = 1.0 if name.endswith("_y") else -1.0
    return perm, sign


def mirror(motion: Motion) -> Motion:
    """The clip performed by the other side of the body (left ↔ right), mirrored in world y."""
    perm, sign = mirror_map(motion.model)
    qpos = motion.qpos[:, perm] * sign
    name = motion.name[:-len(" (mirrored)")] if motion.name.endswith(" (mirrored)") else motion.name + " (mirrored)"
    return motion.with_qpos(qpos, name=name, source=dict(motion.source, mirrored=not motion.source.get("mirrored", False)))


@dataclass(frozen=True)
class PostureRanges:
    """Ranges (degrees, low and high) of the constant posture changes :func:`random_posture` draws:
    ways people carry themselves that the same steps can be walked with (a stoop, bent knees, a
    wide stance), in the model's hinge conventions (y hinges: + bends the trunk and neck forward
    and the knee; x hinges: + moves the left leg out).

    Attributes:
        trunk_flexion_deg: forward bend of the trunk, spread evenly over the three spine hinges
            (spine_lower_y, spine_mid_y, chest_y); negative leans back.
        neck_flexion_deg: forward bend of the neck (neck_y).
        crouch_deg: hip flexion ``a`` of a crouch: the knees bend ``2a`` and the ankles ``a``, so
            each foot stays under its hip with its sole as it was.
        stance_width_deg: abduction of each hip (the ankle rolls back by as much, sole as it was);
            negative narrows the stance.
        elbow_flexion_deg: extra bend of both elbows.
    """

    trunk_flexion_deg: tuple[float, float] = (-10.0, 30.0)
    neck_flexion_deg: tuple[float, float] = (-10.0, 20.0)
    crouch_deg: tuple[float, float] = (0.0, 12.0)
    stance_width_deg: tuple[float, float] = (-3.0, 6.0)
    elbow_flexion_deg: tuple[float, float] = (0.0, 30.0)

    def __post_init__(self) -> None:
        for name, (low, high) in vars(self).items():
            if not (np.isfinite(low) and np.isfinite(high) and low <= high):
                raise ValueError(f"PostureRanges.{name} must be (low, high) with low <= high (degrees), "
                                 f"got {(low, high)}")


def posture_offsets(model_name: str, trunk_flexion: float = 0.0, neck_flexion: float = 0.0, crouch: float = 0.0,
                    stance_width: float = 0.0, elbow_flexion: float = 0.0) -> np.ndarray:
    """Hinge-angle offsets ``(nq,)`` (rad; zero on the root) of one posture, the angles of
    :class:`PostureRanges`'s fields in radians, symmetric between the sides."""
    hm = load_model(model_name)
    offsets = np.zeros(hm.nq)
    changes = {"spine_lower_y": trunk_flexion / 3, "spine_mid_y": trunk_flexion / 3, "chest_y": trunk_flexion / 3,
               "neck_y": neck_flexion}
    for side, out in (("l", 1.0), ("r", -1.0)):
        changes.update({f"{side}_thigh_y": -crouch, f"{side}_shin_y": 2 * crouch, f"{side}_foot_y": -crouch,
                        f"{side}_thigh_x": out * stance_width, f"{side}_foot_x": -out * stance_width,
                        f"{side}_forearm_y": elbow_flexion})
    for hinge, angle in changes.items():
        offsets[hm.qpos_index(hinge)] += angle
    return offsets


def random_posture(model_name: str, rng: np.random.Generator, ranges: PostureRanges = PostureRanges()) -> np.ndarray:
    """The offsets (:func:`posture_offsets`) of a posture drawn uniformly from ``ranges``."""
    angles = {name.removesuffix("_deg"): np.radians(rng.uniform(*bounds)) for name, bounds in vars(ranges).items()}
    return posture_offsets(model_name, **angles)


def with_posture(motion: Motion, offsets: np.ndarray, label: str = "posture") -> Motion:
    """``motion`` performed with a different carriage: every frame's hinges moved by ``offsets``
    (``(nq,)`` rad, :func:`posture_offsets`; kept within the joint ranges), the pelvis then moved so
    that the body's centre of mass keeps its path over the ground and the lowest point of the body
    keeps its height, frame by frame. The steps, their timing and the support the feet give are
    those of the clip (a stoop puts the hips back, as people do); ``label`` names the copy."""
    hm = load_model(motion.model)
    offsets = np.asarray(offsets, dtype=float)
    if offsets.shape != (hm.nq,) or np.any(offsets[:7] != 0) or not np.all(np.isfinite(offsets)):
        raise ValueError(f"posture offsets must be finite, shape ({hm.nq},) for {motion.model} and zero on the "
                         f"root (qpos 0..6), got shape {offsets.shape}")
    qpos = motion.qpos + offsets
    limited, ranges = hm.hinge_ranges  # a hinge the clip already takes past its range stays where it was
    given = motion.qpos[:, limited]
    qpos[:, limited] = np.clip(qpos[:, limited], np.minimum(ranges[:, 0], given), np.maximum(ranges[:, 1], given))
    before, after = hm.forward_kinematics(motion.qpos), hm.forward_kinematics(qpos)
    qpos[:, :2] -= after.com[:, :2] - before.com[:, :2]
    qpos[:, 2] += before.lowest - after.lowest
    return motion.with_qpos(qpos, name=f"{motion.name} ({label})",
                            source=dict(motion.source, posture_rad=np.round(offsets[7:], 4).tolist()))

