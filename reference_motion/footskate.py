"""Kinematic footskate cleanup: pin planted foot points with analytic two-bone leg IK.

Mocap often lets a planted foot slide (DeepMimic's run: about 0.2 m/s). For each foot point
(toe, heel) the frames where it is planted form contact windows; within a window the point is
pinned to its mean horizontal position. Per frame the ankle is moved horizontally by the mean
correction of that foot's planted points, and the leg reaches the new ankle position by
two-bone IK: the knee flexion sets the hip–ankle distance (law of cosines), a shortest-arc swing of
the thigh points the leg at the target, and the ankle hinges keep the foot's world orientation
unchanged, so the whole foot translates with the ankle. Corrections fade smoothly (smoothstep) into the
neighbouring swing frames so the motion stays continuous.

This is the kinematic counterpart of UnderPressure §6 (which optimises with a learned contact
model): contacts here come from foot-point heights, so it suits clean-ish mocap whose only fault
is sliding, and it runs as the last step of retargeting.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from reference_motion import rotations as rot
from reference_motion.humanoid.model import CONTACT_CHANNELS, HumanoidModel, Kinematics, load_model
from reference_motion.motion import Motion
from reference_motion.quality import apparent_ground


@dataclass(frozen=True)
class PinningConfig:
    """Settings of :func:`pin_contacts`.

    Attributes:
        contact_height: a foot point within this height (m) of the apparent ground may be planted.
        max_speed: a run of planted frames whose median horizontal speed (m/s) exceeds this is a
            swinging foot skimming the floor, not a contact, and is left alone.
        fade_s: duration (s) over which a window's correction fades out into the swing frames.
        max_correction_m: a window whose pinning would move the foot further than this (m) is a
            foot dragged or stumbling, or several steps of a shuffling foot that never rises above
            ``contact_height`` (slow, tired and backward walks), not one planted foot, and is left
            alone (``None``: no limit). Without it the motion library's import dragged such feet
            by up to 2.4 m (a leg swept from 0.8 m behind the pelvis to 0.8 m before it over one
            backward walk), on 42 of its 113 takes by more than 0.2 m; a planted stance of
            DeepMimic's walk needs 0.23 m (its heel-strike approach and toe-off are held too).
    """

    contact_height: float = 0.03
    max_speed: float = 1.0
    fade_s: float = 0.2
    max_correction_m: float | None = 0.3

    def __post_init__(self) -> None:
        if self.max_correction_m is not None and not self.max_correction_m > 0:
            raise ValueError(f"PinningConfig.max_correction_m must be positive or None, got {self.max_correction_m}")


def contact_windows(planted: np.ndarray) -> list[tuple[int, int]]:
    """Runs of consecutive ``True`` in ``planted (T,)`` as half-open ``(start, stop)`` frame ranges."""
    p = np.concatenate([[False], np.asarray(planted, bool), [False]])
    edges = np.flatnonzero(np.diff(p.astype(np.int8)))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


def drop_fast_windows(low: np.ndarray, speed: np.ndarray, max_speed: float) -> np.ndarray:
    """Planted labels ``(T, P)``: the runs of ``low (T, P)`` whose median ``speed (T, P)`` (m/s) is
    at most ``max_speed``."""
    planted = low.copy()
    for p in range(low.shape[1]):
        for start, stop in contact_windows(low[:, p]):
            if np.median(speed[start:stop, p]) > max_speed:
                planted[start:stop, p] = False
    return planted


def masked_mean(values: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Mean ``(T, D)`` over axis 1 of ``values (T, P, D)``, of the entries where ``mask (T, P)`` is
    True; zero in a row where none is."""
    count = mask.sum(axis=1, keepdims=True)
    return np.where(count > 0, (values * mask[..., None]).sum(axis=1) / np.maximum(count, 1), 0.0)


def pin_corrections(points_xy: np.ndarray, planted: np.ndarray, max_correction: float | None = None) -> np.ndarray:
    """Horizontal correction ``(T, 2)`` (m) of one foot that keeps its planted points still.

    Args:
        points_xy: ``(T, P, 2)`` horizontal positions (m) of the foot's points (heel, toe).
        planted: ``(T, P)`` bool.

    Within each window where any point is planted, the correction cancels the mean frame-to-frame
    motion of the points planted in both frames (``δ_t = δ_{t-1} − mean Δp``), so a heel-strike,
    flat-foot, toe-off roll is pinned through the switch of support point. Each window's
    correction is centred (zero mean), halving the largest offset. Zero outside the windows, and in
    a window whose correction would exceed ``max_correction`` (m) anywhere (``None``: no limit).
    """
    limit = np.inf if max_correction is None else max_correction
    mean_step = masked_mean(np.diff(points_xy, axis=0), planted[1:] & planted[:-1])  # (T-1, 2)
    correction = np.zeros((points_xy.shape[0], 2))
    for start, stop in contact_windows(planted.any(axis=1)):
        delta = -np.concatenate([[[0.0, 0.0]], np.cumsum(mean_step[start:stop - 1], axis=0)])
        delta -= delta.mean(axis=0)
        if np.linalg.norm(delta, axis=-1).max() <= limit:
            correction[start:stop] = delta
    return correction


def smoothstep(t: np.ndarray) -> np.ndarray:
    """``3t² − 2t³`` of ``t`` clipped to [0, 1]: 0 → 0 and 1 → 1 with zero slope at both ends."""
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3 - 2 * t)


def fade_between_windows(values: np.ndarray, defined: np.ndarray, fade_frames: int) -> np.ndarray:
    """Fill the frames of ``values (T, D)`` where ``defined (T,)`` is False.

    A gap between two windows of at most ``2·fade_frames`` frames is bridged between the values
    at its ends; a longer gap (and the ends of the clip) fades each neighbouring value to zero
    over ``fade_frames`` frames. Both use the smoothstep ``3t² − 2t³``, whose zero slope at the
    ends keeps joint velocities continuous.
    """
    out = np.where(defined[:, None], values, 0.0)
    T = len(defined)
    for start, stop in contact_windows(~defined):
        left = out[start - 1] if start > 0 else None
        right = out[stop] if stop < T else None
        gap = stop - start
        frames = np.arange(start, stop)
        if left is not None and right is not None and gap <= 2 * fade_frames:
            t = smoothstep((frames - start + 1) / (gap + 1))
            out[start:stop] = (1 - t)[:, None] * left + t[:, None] * right
            continue
        if left is not None:
            w = smoothstep(1 - (frames - start + 1) / (fade_frames + 1))
            out[start:stop] += w[:, None] * left
        if right is not None:
            w = smoothstep(1 - (stop - frames) / (fade_frames + 1))
            out[start:stop] += w[:, None] * right
    return out


def knee_flexion_for_reach(reach: np.ndarray, thigh: float, shin: float) -> np.ndarray:
    """Knee flexion (rad, ``(T,)``, 0 = straight) giving hip–ankle distance ``reach (T,)`` (m) for
    bone lengths ``thigh`` and ``shin`` (m); out-of-reach targets give the nearest reachable pose."""
    cos = (reach**2 - thigh**2 - shin**2) / (2 * thigh * shin)
    return np.arccos(np.clip(cos, -1.0, 1.0))


class LegIK:
    """Analytic IK for one leg of a humanoid (thigh 3 hinges, knee 1 hinge, ankle 3 hinges)."""

    def __init__(self, model: HumanoidModel, side: str):
        names = model.body_names
        self.pelvis, self.thigh, self.shin, self.foot = (
            names.index(b) for b in ("pelvis", f"{side}_thigh", f"{side}_shin", f"{side}_foot"))
        m = model.model
        self.knee_offset = m.body_pos[self.shin + 1].copy()  # shin origin in the thigh frame
        self.ankle_offset = m.body_pos[self.foot + 1].copy()  # foot origin in the shin frame
        self.thigh_len = float(np.linalg.norm(self.knee_offset))
        self.shin_len = float(np.linalg.norm(self.ankle_offset))
        self.hip_joints = model.body_joints[f"{side}_thigh"]
        self.knee_joint = model.body_joints[f"{side}_shin"]
        self.ankle_joints = model.body_joints[f"{side}_foot"]
        lo, hi = m.jnt_range[m.joint(f"{side}_shin_{self.knee_joint.axes}").id]
        self.knee_limits = (max(float(lo), 0.0), float(hi))

    def reach(self, qpos: np.ndarray, body_pos: np.ndarray, body_quat: np.ndarray,
              ankle_target: np.ndarray) -> None:
        """Set the leg hinges of ``qpos (T, nq)`` in place so the ankle reaches ``ankle_target (T, 3)``
        (world, m) with the foot's world orientation unchanged; ``body_pos``/``body_quat`` are the
        current kinematics ``(T, B, 3|4)``."""
        hip = body_pos[:, self.thigh]
        g_pelvis, g_thigh, g_foot = body_quat[:, self.pelvis], body_quat[:, self.thigh], body_quat[:, self.foot]
        to_target = ankle_target - hip
        flex = np.clip(knee_flexion_for_reach(np.linalg.norm(to_target, axis=-1), self.thigh_len, self.shin_len),
                       *self.knee_limits)
        knee_axis = self.knee_joint.axis_vectors[0]
        q_knee = rot.from_axis_angle(knee_axis, flex)
        ankle_in_thigh = self.knee_offset + rot.rotate(q_knee, self.ankle_offset)
        swing = rot.between_vectors(rot.rotate(g_thigh, ankle_in_thigh), to_target)
        g_thigh_new = rot.normalize(rot.multiply(swing, g_thigh))
        qpos[:, self.hip_joints.qpos_index] = rot.to_hinges(
            rot.multiply(rot.conjugate(g_pelvis), g_thigh_new), self.hip_joints.axes)
        qpos[:, self.knee_joint.qpos_index[0]] = flex
        g_shin_new = rot.multiply(g_thigh_new, q_knee)
        qpos[:, self.ankle_joints.qpos_index] = rot.to_hinges(
            rot.multiply(rot.conjugate(g_shin_new), g_foot), self.ankle_joints.axes)


FOOT_SIDES = ("left", "right")


def foot_channels(side: str) -> list[int]:
    """Indices in :data:`CONTACT_CHANNELS` of the foot points (heel, toe) of ``side`` ("left", "right")."""
    return [i for i, c in enumerate(CONTACT_CHANNELS) if c.startswith(side)]


def planted_points(kin: Kinematics, fps: float, config: PinningConfig = PinningConfig()) -> np.ndarray:
    """``(T, 4)`` bool: whether each foot point of a clip's kinematics ``kin`` (at ``fps``) counts as
    planted in each frame: within ``config.contact_height`` of the apparent ground, in a window not
    faster than ``config.max_speed`` (``config.max_correction_m`` is applied per foot, later)."""
    ground = apparent_ground(kin.lowest, fps)
    speed = np.linalg.norm(np.gradient(kin.foot_points[..., :2], axis=0), axis=-1) * fps
    return drop_fast_windows(kin.foot_points[..., 2] <= ground[:, None] + config.contact_height, speed,
                             config.max_speed)


def pin_contacts(motion: Motion, config: PinningConfig = PinningConfig()) -> Motion:
    """Footskate-cleaned copy of ``motion``.

    Planted means within ``config.contact_height`` of the apparent ground of
    :func:`reference_motion.quality.apparent_ground` (z = 0 for a clip standing on the floor, so
    a clip that floats or sinks is pinned where it stands), in a window not faster than
    ``config.max_speed`` whose pinning moves the foot no further than ``config.max_correction_m``.
    Everything but the leg hinges is kept.
    """
    model = load_model(motion.model)
    kin = model.forward_kinematics(motion.qpos)
    planted = planted_points(kin, motion.fps, config)
    fade = max(1, int(round(config.fade_s * motion.fps)))
    qpos = motion.qpos.copy()
    for side in FOOT_SIDES:
        channels = foot_channels(side)
        foot_planted = planted[:, channels]
        delta = pin_corrections(kin.foot_points[:, channels, :2], foot_planted, config.max_correction_m)
        delta = fade_between_windows(delta, foot_planted.any(axis=1), fade)
        moving = np.linalg.norm(delta, axis=-1) > 1e-6
        if not moving.any():
            continue
        leg = LegIK(model, side[0])
        target = kin.body_pos[moving, leg.foot].copy()
        target[:, :2] += delta[moving]
        part = qpos[moving]
        leg.reach(part, kin.body_pos[moving], kin.body_quat[moving], target)
        qpos[moving] = part
    qpos[:, 7:] = np.unwrap(qpos[:, 7:], axis=0)
    return replace(motion, qpos=qpos, source={**motion.source, "footskate_pinned": True})
