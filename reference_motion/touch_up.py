"""Contact touch-up of a simulated performance: feet resting on the floor and planted.

A physically simulated clip (:mod:`agents.clean`) keeps the artefacts of its contact model:
MuJoCo's soft contacts let a landing foot sink into the floor (2–4 cm on held-out takes, about
1 cm on DeepMimic's walk; at 120 Hz physics the contact time constant is clamped to 17 ms), and
the simulated heel and toe points creep and roll while in contact (0.25 m/s on held-out takes,
0.1 m/s on DeepMimic's walk, the same with elliptic friction cones and impratio 10: it is not
friction slip). :func:`touch_up` removes both kinematically, by about a centimetre on average:

1. the root is raised in each frame by how far the body's lowest point is below z = 0
   (:func:`floor_lift`; by default spread over ±0.05 s, :data:`TOUCH_UP_SMOOTH_S`);
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
    up to the floor: the depth ``max(0, −lowest)``; with ``window`` > 0 its running maximum over
    ``2·window + 1`` frames, then averaged over the same window, so each frame's lift is still at
    least its own depth (every maximum averaged covers that frame) but changes gradually
    (``window`` 0: exactly the depth, no smoothing)."""
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


TOUCH_UP_PINNING = PinningConfig(max_correction_m=0.1)
"""How :func:`touch_up` pins: as retargeting does, but a window whose pinning would move the foot
more than 10 cm is left alone (a foot dragged through a stumble or a fall, not a planted one).
Chosen on the validation takes (``bench/touch_up_settings.py``): 10 cm leaves the median foot skate
where no limit has it (0.038 m/s) and cut the largest body shift on a walk-back from 14.7 to 8.9
cm; 5 cm left 0.074 m/s."""


TOUCH_UP_SMOOTH_S = 0.05
"""The lift's window either side (s): chosen on the validation takes (``bench/touch_up_settings.py``).
Lifting each frame by exactly its depth (0) more than doubles the root's vertical acceleration at
footfalls (99th percentile 29 → 79 m/s²); 0.05 s leaves it at 24 m/s², floating 7.5 mm (median;
1.0 mm at 0)."""


def touch_up(motion: Motion, breaks: Sequence[int] = (), smooth_s: float = TOUCH_UP_SMOOTH_S,
             pinning: PinningConfig = TOUCH_UP_PINNING) -> tuple[Motion, TouchUpReport]:
    """``motion`` lifted out of the floor (:func:`floor_lift`, ``smooth_s`` (s) either side: 0 lifts
    each frame by exactly its depth, as a rigid floor would stop the foot, with a jolt at each
    footfall; :data:`TOUCH_UP_SMOOTH_S` spreads it over the neighbouring frames, floating a few
    millimetres) and its planted feet pinned (``pinning``), with the report of what moved.

    ``breaks`` are 0-based frame indices where a new continuous stretch starts (a performance's
    re-anchors, :attr:`agents.clean.Reanchor.frame`; 0 and ``n_frames`` add nothing): each stretch
    is touched up on its own, so no contact window spans a jump. A stretch shorter than
    :data:`MIN_PINNED_FRAMES` is only lifted. After pinning, any frame the leg IK left below the
    floor is lifted again, so the result never reaches below z = 0. A looping clip is treated as
    one stretch from its first frame to its last (the seam is not joined). The result's ``source``
    records the report under ``touch_up``."""
    if not (np.isfinite(smooth_s) and smooth_s >= 0):
        raise ValueError(f"smooth_s must be a finite number of seconds >= 0, got {smooth_s}")
    n = motion.n_frames
    bad = [b for b in breaks if not (float(b).is_integer() and 0 <= b <= n)]
    if bad:
        raise ValueError(f"{motion.name}: breaks must be whole frame indices in 0..{n}, got {bad}")
    edges = sorted({0, n, *(int(b) for b in breaks)})
    model = load_model(motion.model)
    before = model.forward_kinematics(motion.qpos)
    window = int(round(smooth_s * motion.fps))
    qpos, lift = motion.qpos.copy(), np.zeros(n)
    for a, b in zip(edges[:-1], edges[1:]):
        lift[a:b] = floor_lift(before.lowest[a:b], window)
        qpos[a:b, 2] += lift[a:b]
        if b - a >= MIN_PINNED_FRAMES:
            qpos[a:b] = pin_contacts(motion.with_qpos(qpos[a:b], loop=False), pinning).qpos
    after = model.forward_kinematics(qpos)
    residual = floor_lift(after.lowest, 0)  # what the IK moved below the floor (normally nothing)
    qpos[:, 2] += residual
    lift += residual
    shift = np.linalg.norm(after.body_pos + residual[:, None, None] * _UP - before.body_pos, axis=-1)
    report = TouchUpReport(lift_max_m=float(lift.max(initial=0.0)), lift_mean_m=float(lift.mean()),
                           body_shift_mean_m=float(shift.mean()), body_shift_max_m=float(shift.max(initial=0.0)))
    return motion.with_qpos(qpos, source={**motion.source, "touch_up": report.as_dict()}), report


_UP = np.array([0.0, 0.0, 1.0])
