"""A clip walked with the feet further apart (or closer together), its balance kept.

Abducting both hips by a constant (:func:`reference_motion.transforms.with_posture`'s stance
width) places the feet wider but leaves the centre of mass on its old path: in single support it
then hangs up to 0.1 m further inside the stance foot than the take had it, and nothing in the
take's motion pays for that. Here the feet are moved apart by ``extra_m`` (each ``extra_m / 2``
outwards along the line between the hips), so the centre of pressure moves sideways with the foot
that bears the weight (:func:`support_share`, from the feet's contacts); and the whole body is
carried sideways by the centre-of-mass shift that the linear inverted pendulum
(``x'' = g / h (x - p)``, ``h`` the take's mean CoM height) gives for that centre-of-pressure
shift: its one bounded solution, the shift smoothed by the kernel ``(w/2) exp(-w |t|)``,
``w = sqrt(g / h)`` (:func:`pendulum_com_shift`). Added to the take's own sway, which its steps
already balance, the wider walk sways as much more as its wider steps need (about a third of the
feet's shift at walking cadence), no more. The legs then reach the moved feet by two-bone IK with
the feet's orientations unchanged (:class:`reference_motion.footskate.LegIK`); where a leg, straight
in the take, cannot reach that far sideways, the pelvis is lowered by as much as it lacks (spread
over :data:`REACH_SMOOTHING_S` so the body does not jerk down), and the feet are pinned again.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.ndimage import convolve1d, maximum_filter1d, uniform_filter1d

from reference_motion.footskate import FOOT_SIDES, LegIK, foot_channels, pin_contacts, planted_points
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion

GRAVITY = 9.81
"""m/s²."""
HEADING_SMOOTHING_S = 0.5
"""Seconds over which the line between the hips is averaged into the sideways direction."""
REACH_SMOOTHING_S = 0.2
"""Seconds over which a lowering of the pelvis (legs that cannot reach) comes and goes."""


def support_share(left_planted: np.ndarray, right_planted: np.ndarray, fps: float,
                  smoothing_s: float = 0.1) -> np.ndarray:
    """``(T,)`` the share of the weight on the left foot, in [0, 1]: 1 with only the left foot
    planted, 0 with only the right, 1/2 with both; frames with neither (flight, or a foot skimming
    the floor) take the share of the nearest frames that have one (linear between them, 1/2 if no
    frame has a contact); then smoothed with a moving average of ``smoothing_s`` seconds."""
    left, right = np.asarray(left_planted, bool), np.asarray(right_planted, bool)
    if left.shape != right.shape or left.ndim != 1:
        raise ValueError(f"left and right contacts must be (T,) alike, got {left.shape} and {right.shape}")
    share = np.where(left & ~right, 1.0, np.where(right & ~left, 0.0, 0.5))
    known = left | right
    if not known.any():
        return np.full(left.shape, 0.5)
    frames = np.arange(len(share))
    share = np.interp(frames, frames[known], share[known])
    return uniform_filter1d(share, max(1, int(round(smoothing_s * fps))), mode="nearest")


def pendulum_com_shift(cop_shift: np.ndarray, fps: float, com_height_m: float) -> np.ndarray:
    """``(T, ...)`` the bounded centre-of-mass shift ``x`` of the linear inverted pendulum
    ``x'' = g / h · (x - p)`` for the centre-of-pressure shift ``p = cop_shift`` ``(T, ...)``
    (sampled at ``fps``, ``h = com_height_m``): ``p`` convolved along time with ``(w/2) exp(-w |t|)``,
    ``w = sqrt(g / h)``, over ±10 time constants. Before and after the clip ``p`` is taken as its mean
    over the clip (a walk's weight alternating about the middle), not as its first and last value,
    which would have the body lean over the foot a clip starts or ends on as if it stood there."""
    if not com_height_m > 0:
        raise ValueError(f"com_height_m must be > 0, got {com_height_m}")
    rate = np.sqrt(GRAVITY / com_height_m)
    reach = int(np.ceil(10.0 / rate * fps))  # frames in 10 time constants
    lags = np.arange(-reach, reach + 1) / fps
    kernel = np.exp(-rate * np.abs(lags))
    mean = np.mean(cop_shift, axis=0)
    return convolve1d(cop_shift - mean, kernel / kernel.sum(), axis=0, mode="constant") + mean


def pelvis_drop(hip: np.ndarray, ankle_target: np.ndarray, reach_m: np.ndarray, fps: float) -> np.ndarray:
    """``(T,)`` how far (m) to lower the pelvis so that ankles at ``ankle_target`` ``(T, 2, 3)`` (world,
    the two legs) are within ``reach_m`` ``(T, 2)`` of the hips ``hip`` ``(T, 2, 3)``: for each frame
    the larger lack of the two legs (0 where both reach), then the largest within
    ±:data:`REACH_SMOOTHING_S` / 2 averaged over as long, so that every frame is lowered at least by
    its own lack and the drop comes and goes gradually."""
    offset = ankle_target - hip
    sideways = np.sum(offset[..., :2] ** 2, axis=-1)
    below = np.sqrt(np.maximum(reach_m**2 - sideways, 0.0))  # how far below the hip the ankle may be
    lack = np.maximum(-offset[..., 2] - below, 0.0).max(axis=1)
    size = 2 * int(round(0.5 * REACH_SMOOTHING_S * fps)) + 1
    return uniform_filter1d(maximum_filter1d(lack, size, mode="nearest"), size, mode="nearest")


def wider_stance(motion: Motion, extra_m: float, smoothing_s: float = 0.1, label: str | None = None) -> Motion:
    """``motion`` with its feet ``extra_m`` metres further apart (negative: closer) and the body
    swaying as the wider steps need (see the module docstring; the weight's shift between the feet
    smoothed over ``smoothing_s``); named ``"NAME (stance +0.2 m)"`` or ``label``. The feet are
    pinned again afterwards (:func:`reference_motion.footskate.pin_contacts`)."""
    if not (np.isfinite(extra_m) and np.isfinite(smoothing_s) and smoothing_s >= 0):
        raise ValueError(f"extra_m must be finite and smoothing_s >= 0, got {extra_m} and {smoothing_s}")
    model = load_model(motion.model)
    kin = model.forward_kinematics(motion.qpos)
    legs = {side: LegIK(model, side[0]) for side in FOOT_SIDES}
    hips = kin.body_pos[:, legs["left"].thigh, :2] - kin.body_pos[:, legs["right"].thigh, :2]
    size = max(1, int(round(HEADING_SMOOTHING_S * motion.fps)))
    outward = uniform_filter1d(hips, size, axis=0, mode="nearest")  # the pelvis' sway and twist averaged out
    outward /= np.maximum(np.linalg.norm(outward, axis=1, keepdims=True), 1e-9)  # (T, 2) unit, right hip to left
    planted = planted_points(kin, motion.fps)
    left = support_share(planted[:, foot_channels("left")].any(axis=1), planted[:, foot_channels("right")].any(axis=1),
                         motion.fps, smoothing_s)
    half = 0.5 * extra_m
    cop = (half * (2.0 * left - 1.0))[:, None] * outward  # (T, 2) where the weight's support moved
    carried = pendulum_com_shift(cop, motion.fps, float(kin.com[:, 2].mean()))  # (T, 2) the root's sideways shift
    qpos = motion.qpos.copy()
    qpos[:, :2] += carried
    targets, hips_now, reach = [], [], []
    for side, sign in (("left", 1.0), ("right", -1.0)):
        leg = legs[side]
        target = kin.body_pos[:, leg.foot].copy()
        target[:, :2] += sign * half * outward
        targets.append(target)
        hip = kin.body_pos[:, leg.thigh].copy()  # the root only translated: each hip moved with it
        hip[:, :2] += carried
        hips_now.append(hip)
        as_taken = np.linalg.norm(kin.body_pos[:, leg.foot] - kin.body_pos[:, leg.thigh], axis=1)
        reach.append(np.maximum(as_taken, 0.995 * (leg.thigh_len + leg.shin_len)))  # a straight leg stays straight
    qpos[:, 2] -= pelvis_drop(np.stack(hips_now, 1), np.stack(targets, 1), np.stack(reach, 1), motion.fps)
    moved = model.forward_kinematics(qpos)
    for side, target in zip(("left", "right"), targets):
        legs[side].reach(qpos, moved.body_pos, moved.body_quat, target)
    qpos[:, 7:] = np.unwrap(qpos[:, 7:], axis=0)
    name = label or f"{motion.name} (stance {extra_m:+g} m)"
    widened = replace(motion.with_qpos(qpos, name=name), source={**motion.source, "extra_stance_m": float(extra_m)})
    return pin_contacts(widened)
