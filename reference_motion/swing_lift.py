"""Feet lifted in the swing of backward steps: more knee flexion while a foot is off the floor and
the take walks backward, so that a simulated foot tracking the take with a few degrees of error
clears the floor instead of scuffing it.

A take's swing foot may pass a centimetre or two above the floor. A policy tracks every hinge with
several degrees of error (the shipped actor 7–15° RMS on the sagittal leg hinges of validation's
walks, clean), so its swing foot touches the floor and drags: on validation's backward walk 4.9% of
the simulated foot points are within 2 cm of the floor and moving faster than 0.3 m/s, against 0.1%
in the take, and the body gets only 0.815 of the take's way (``bench/walking_speed.py``) until the
lag termination ends it. The policy tracks a copy of the take whose knees bend ``knee_deg`` more at
the height of each swing (:func:`lift_swing`), judged against the take as given
(``--swing-lift`` on ``evaluate.py``, ``clean.py`` and ``bench/imu_draws.py``).

Swing, per foot, read from height (the default): the lower of its toe and heel points is more than
``clearance_m`` above that foot's own low (the 5th percentile of its height over the take, so a take
that floats or sinks a little as a whole is read alike); or read from speed: both points move faster
than ``swing_speed_mps`` over the floor. The 0/1 indicator is smoothed by a Gaussian of ``smoothing_frames``
so the added flexion rises and falls with the swing instead of jumping. Backward steps only: the
lift is weighted by how fast the take's root walks against the pelvis's heading
(:func:`backward_weights`), since a forward step's extra knee flexion makes the body outpace the
take. A denoised IMU take's stance foot wanders a centimetre or two in height, so some of its stance reads
as swing from height; less of it from speed (README, "Walking as far as the take").
"""

from __future__ import annotations

import argparse
import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from reference_motion import rotations as rot
from reference_motion.cli import positive_float
from reference_motion.humanoid.model import FOOT_CHANNELS, load_model
from reference_motion.motion import Motion
from reference_motion.quality import heading_frame_velocity, horizontal_speed

SWING_READS = ("height", "speed")
"""What :attr:`SwingLift.swing_from` may read swing from."""

KNEES = ("l_shin_y", "r_shin_y")
"""The knee hinge of each foot of :data:`~reference_motion.humanoid.model.FOOT_CHANNELS` (left,
right); positive is flexion on both humanoids."""


@dataclass(frozen=True)
class SwingLift:
    """How far a swing foot's knee bends more.

    Attributes:
        knee_deg: added knee flexion at the height of a swing (degrees, > 0).
        clearance_m: a foot is in swing when its lowest point is more than this above its own low (m).
            3 cm, not 1: a denoised IMU take's stance foot wanders a centimetre or two with the
            joint errors left in it, and a stance knee bent 15° more costs the backward walk more
            than the lift gains (validation's rule: 1 cm took its IMU draws 0.950 → 0.919).
        smoothing_frames: σ of the Gaussian that smooths the swing indicator (frames, > 0).
        swing_from: what swing is read from: ``"height"`` (the foot's lowest point more than
            ``clearance_m`` above its own low, :func:`swing_weights`) or ``"speed"`` (every point of
            the foot moving faster than ``swing_speed_mps`` over the floor, :func:`speed_swing_weights`).
            A denoised IMU take's stance foot wanders in height more than it slides (kinematic probe on
            validation's backward walk: read from height above 3 cm its stance knees get 1.6–3.3° of
            the lift, from speed 0.4–1.4°).
        swing_speed_mps: the horizontal speed above which a foot is in swing when ``swing_from`` is
            ``"speed"`` (m/s, > 0).
        backward_speed_mps: the lift is in full where the take walks backward (its root against the
            pelvis's heading, on the ground) at this speed or faster (m/s, > 0), in proportion below
            it, and none where it walks forward or sideways: bending a forward or side step's knee
            more makes the body walk faster than the take (probe: validation's forward walks get
            1.02–1.07 of the take's way at 15°, 1.07–1.42 at 25°, and lose the lag termination).
        backward_window_s: σ of the Gaussian that averages that velocity (s).
    """

    knee_deg: float = 15.0
    clearance_m: float = 0.03
    smoothing_frames: float = 3.0
    swing_from: str = "height"
    swing_speed_mps: float = 1.0
    backward_speed_mps: float = 0.5
    backward_window_s: float = 0.5

    def __post_init__(self) -> None:
        for name in ("knee_deg", "clearance_m", "smoothing_frames", "swing_speed_mps", "backward_speed_mps",
                     "backward_window_s"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"SwingLift.{name} must be finite and > 0, got {value!r}")
        if self.swing_from not in SWING_READS:
            raise ValueError(f"SwingLift.swing_from must be one of {SWING_READS}, got {self.swing_from!r}")

    @property
    def label(self) -> str:
        """How results name the lift, e.g. ``"swing lift 15 deg above 3 cm"``."""
        read = (f"above {100 * self.clearance_m:g} cm" if self.swing_from == "height"
                else f"faster than {self.swing_speed_mps:g} m/s")
        return f"swing lift {self.knee_deg:g} deg {read}"


def swing_weights(foot_height: np.ndarray, clearance_m: float, smoothing_frames: float) -> np.ndarray:
    """How much in swing a foot is at each frame, ``(T,)`` in [0, 1], from the height ``(T,)`` (m)
    of its lowest point: 1 well inside a swing (higher than its 5th percentile + ``clearance_m``), 0
    well inside a stance, the step between smoothed by a Gaussian of σ ``smoothing_frames``."""
    height = np.asarray(foot_height, dtype=float)
    if height.ndim != 1 or len(height) == 0 or not np.all(np.isfinite(height)):
        raise ValueError(f"foot_height must be a finite (T,) array with T > 0, got shape {height.shape}")
    swing = (height > np.percentile(height, 5) + clearance_m).astype(float)
    return np.clip(gaussian_filter1d(swing, smoothing_frames, mode="nearest"), 0.0, 1.0)


def speed_swing_weights(foot_xy: np.ndarray, fps: float, swing_speed_mps: float,
                        smoothing_frames: float) -> np.ndarray:
    """How much in swing a foot is at each frame, ``(T,)`` in [0, 1], from the horizontal positions
    ``foot_xy (T, P, 2)`` (m, at ``fps``) of its ``P`` points: 1 where every point moves faster than
    ``swing_speed_mps`` over the floor (a heel or toe still on it is stance), 0 where one is slower,
    the step between smoothed by a Gaussian of σ ``smoothing_frames``."""
    xy = np.asarray(foot_xy, dtype=float)
    if xy.ndim != 3 or xy.shape[-1] != 2 or len(xy) < 2 or not np.all(np.isfinite(xy)):
        raise ValueError(f"foot_xy must be a finite (T, P, 2) array with T > 1, got shape {xy.shape}")
    swing = (horizontal_speed(xy, fps).min(axis=1) > swing_speed_mps).astype(float)
    return np.clip(gaussian_filter1d(swing, smoothing_frames, mode="nearest"), 0.0, 1.0)


def backward_weights(root_xy: np.ndarray, heading: np.ndarray, fps: float, full_speed_mps: float,
                     window_s: float) -> np.ndarray:
    """How much the take walks backward at each frame, ``(T,)`` in [0, 1]: the root's horizontal
    velocity (from positions ``root_xy (T, 2)``, m, at ``fps``) against the pelvis's heading
    ``heading (T,)`` (rad about +z), averaged by a Gaussian of σ ``window_s`` (s, a step or two),
    over ``full_speed_mps``, clipped to [0, 1]."""
    backward = -heading_frame_velocity(root_xy, heading, fps)[:, 0]
    return np.clip(gaussian_filter1d(backward, window_s * fps, mode="nearest") / full_speed_mps, 0.0, 1.0)


def lift_swing(motion: Motion, lift: SwingLift = SwingLift()) -> Motion:
    """``motion`` with each knee bent ``lift.knee_deg`` more in proportion to its foot's swing weights
    (:func:`swing_weights` or :func:`speed_swing_weights`, as ``lift.swing_from`` says) times its
    :func:`backward_weights`, held inside the knee's range. Everything else (root, other hinges,
    rate) is unchanged; ``source["swing_lift"]`` records the settings."""
    if motion.n_frames < 2:
        raise ValueError(f"{motion.name}: the swing lift needs at least 2 frames, got {motion.n_frames}")
    model = load_model(motion.model)
    points = model.forward_kinematics(motion.qpos).foot_points  # (T, 4, 3), CONTACT_CHANNELS order
    backward = backward_weights(motion.root_pos[:, :2], rot.yaw(motion.root_quat), motion.fps,
                                lift.backward_speed_mps, lift.backward_window_s)
    qpos = motion.qpos.copy()
    for knee, columns in zip(KNEES, FOOT_CHANNELS):
        index = model.qpos_index(knee)
        low, high = model.hinge_range(knee)
        foot = points[:, list(columns)]
        if lift.swing_from == "height":
            swing = swing_weights(foot[..., 2].min(axis=1), lift.clearance_m, lift.smoothing_frames)
        else:
            swing = speed_swing_weights(foot[..., :2], motion.fps, lift.swing_speed_mps,
                                        lift.smoothing_frames)
        weights = swing * backward
        qpos[:, index] = np.clip(qpos[:, index] + math.radians(lift.knee_deg) * weights, low, high)
    return motion.with_qpos(qpos, source={**motion.source, "swing_lift": asdict(lift)})


def add_swing_lift_options(parser: argparse.ArgumentParser, what: str) -> None:
    """``--swing-lift [DEG]`` and ``--swing-from {height,speed}`` (read back by
    :func:`swing_lift_of`); ``what`` ends the help of ``--swing-lift``: what the lifted takes are for."""
    parser.add_argument("--swing-lift", nargs="?", const=SwingLift.knee_deg, type=positive_float, metavar="DEG",
                        help="bend the knees of backward steps DEG more in swing "
                             f"(reference_motion/swing_lift.py; after --denoise): {what}")
    parser.add_argument("--swing-from", choices=SWING_READS, default=None,
                        help="with --swing-lift: read swing from the foot's height above its low "
                             f"({100 * SwingLift.clearance_m:g} cm) or its speed over the floor "
                             f"({SwingLift.swing_speed_mps:g} m/s) (default: {SwingLift.swing_from})")


def swing_lift_of(args: argparse.Namespace) -> SwingLift | None:
    """The :class:`SwingLift` that :func:`add_swing_lift_options`' arguments ask for, or ``None``; a
    ``ValueError`` for ``--swing-from`` without ``--swing-lift``."""
    if not args.swing_lift:
        if args.swing_from is not None:
            raise ValueError("--swing-from goes with --swing-lift")
        return None
    return SwingLift(knee_deg=args.swing_lift, swing_from=args.swing_from or SwingLift.swing_from)
