"""Contact touch-up of a simulated performance: feet resting on the floor and planted.

A physically simulated clip (:mod:`agents.clean`) keeps the artefacts of its contact model:
MuJoCo's soft contacts let a landing foot sink 2–4 cm into the floor (at 120 Hz physics the
contact time constant is clamped to 17 ms), and the simulated heel and toe points creep and roll
while in contact (0.25 m/s on held-out takes, 0.1 m/s on DeepMimic's walk, the same with elliptic
friction cones and impratio 10: it is not friction slip). :func:`touch_up` removes both
kinematically, by a few millimetres on average:

1. the root is raised in each frame by how far the body's lowest point is below z = 0
   (:func:`floor_lift`: a running maximum, then a moving average over the same short window, so
   the lift is never less than the depth and never pops);
2. planted foot points are pinned with two-bone leg IK (:func:`reference_motion.footskate.pin_contacts`),

each continuous stretch of the performance on its own (a re-anchor is a jump no contact spans).

What it changed is measured and returned (:class:`TouchUpReport`), so a user can tell the
simulation from the touch-up.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Sequence

import numpy as np
from scipy.ndimage import maximum_filter1d, uniform_filter1d

from reference_motion.footskate import PinningConfig, pin_contacts
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion


MIN_PINNED_FRAMES = 4
"""A stretch shorter than this (frames) is only lifted: too short to hold a contact window."""


def floor_lift(lowest: np.ndarray, window: int) -> np.ndarray:
    """Root lift ``(T,)`` (m, ≥ 0) that brings the lowest body point ``lowest (T,)`` (m, world z)
    up to the floor: the depth ``max(0, −lowest)``, its running maximum over ``2·window + 1``
    frames, then averaged over the same window. Each frame's lift is at least its own depth (every
    maximum averaged covers that frame) and changes smoothly."""
    if window < 0:
        raise ValueError(f"window must be >= 0 frames, got {window}")
    depth = np.maximum(-np.asarray(lowest, dtype=float), 0.0)
    size = 2 * window + 1
    return uniform_filter1d(maximum_filter1d(depth, size, mode="nearest"), size, mode="nearest")


@dataclass(frozen=True)
class TouchUpReport:
    """What :func:`touch_up` changed.

    Attributes:
        lift_max_m, lift_mean_m: the root's upward shift (m), largest and mean over frames.
        body_shift_mean_m, body_shift_max_m: how far the bodies moved (m) against the input,
            mean and largest over (frame, body) pairs (lift and pinning together).
    """

    lift_max_m: float
    lift_mean_m: float
    body_shift_mean_m: float
    body_shift_max_m: float

    def as_dict(self) -> dict:
        return asdict(self)


def touch_up(motion: Motion, breaks: Sequence[int] = (), smooth_s: float = 0.0,
             pinning: PinningConfig = PinningConfig()) -> tuple[Motion, TouchUpReport]:
    """``motion`` lifted out of the floor (:func:`floor_lift` over ``smooth_s`` either side) and its
    planted feet pinned (``pinning``), with the report of what moved. ``breaks`` are frames where a
    new continuous stretch starts (a performance's re-anchors): each stretch is touched up on its
    own, so no contact window spans a jump. The result's ``source`` records the report under
    ``touch_up``."""
    if not smooth_s >= 0:
        raise ValueError(f"smooth_s must be >= 0 s, got {smooth_s}")
    edges = sorted({0, motion.n_frames, *(int(b) for b in breaks if 0 < b < motion.n_frames)})
    model = load_model(motion.model)
    before = model.forward_kinematics(motion.qpos)
    window = int(round(smooth_s * motion.fps))
    qpos, lift = motion.qpos.copy(), np.zeros(motion.n_frames)
    for a, b in zip(edges[:-1], edges[1:]):
        lift[a:b] = floor_lift(before.lowest[a:b], window)
        qpos[a:b, 2] += lift[a:b]
        if b - a >= MIN_PINNED_FRAMES:
            qpos[a:b] = pin_contacts(motion.with_qpos(qpos[a:b], loop=False), pinning).qpos
    shift = np.linalg.norm(model.forward_kinematics(qpos).body_pos - before.body_pos, axis=-1)
    report = TouchUpReport(lift_max_m=float(lift.max(initial=0.0)), lift_mean_m=float(lift.mean()),
                           body_shift_mean_m=float(shift.mean()), body_shift_max_m=float(shift.max(initial=0.0)))
    return motion.with_qpos(qpos, source={**motion.source, "touch_up": report.as_dict()}), report

