"""Artefact metrics for any motion, kinematic or simulated (SPEC "Metrics").

The metric functions are pure functions of arrays; :func:`motion_quality` computes the arrays
(forward kinematics, contacts) for a :class:`Motion` and calls them.

Ground and contacts for a kinematic clip: the floor is z = 0, but a clip that floats or sinks has
its own apparent ground, which we track as a running low percentile of the body's lowest point
over a 1 s window (:func:`apparent_ground`; a percentile, not the minimum, so noise spikes do not
pull it down). A foot point is in contact when it is within
``contact_height`` of that apparent ground; a frame should be in support when the body's lowest
point is (flight phases rise above it). So foot skate is measured on a floating clip too, and
floating is measured on the frames where the character ought to stand.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.ndimage import percentile_filter

from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion


@dataclass(frozen=True)
class QualityConfig:
    """Thresholds of the artefact metrics.

    Attributes:
        contact_height: a foot point within this height (m) of the apparent ground is in contact.
        support_height: a frame is a support frame when the lowest body point is within this
            height (m) of the apparent ground.
        ground_window_s: window (s) of the running percentile that tracks the apparent ground.
        ground_percentile: that percentile (0–100).
        self_penetration_depth: geometry overlap (m) that counts as self-penetration.
    """

    contact_height: float = 0.02
    support_height: float = 0.03
    ground_window_s: float = 1.0
    ground_percentile: float = 10.0
    self_penetration_depth: float = 0.005


ARTEFACT_METRICS = ("foot_skate_mps", "penetration_max_m", "penetration_mean_m", "floating_m", "jitter",
                    "self_penetration_frac")
"""The :class:`QualityReport` fields that measure an artefact (what cleaning should reduce)."""


@dataclass(frozen=True)
class QualityReport:
    """Artefact metrics of one motion (all SI).

    Attributes:
        frames, fps: size and rate of the motion.
        foot_skate_mps: mean horizontal speed (m/s) of heel/toe points while in contact.
        penetration_max_m, penetration_mean_m: depth (m) of the lowest body point below z = 0;
            max over frames, and mean over all frames (0 where not below).
        floating_m: mean height (m) of the lowest body point above z = 0 over support frames.
        jitter: mean absolute joint jerk (rad/s³) over hinges and frames.
        self_penetration_frac: fraction of frames with leg–leg or arm–torso overlap.
        contact_frac: fraction of frames in contact per channel (LT, RT, LH, RH).
    """

    frames: int
    fps: float
    foot_skate_mps: float
    penetration_max_m: float
    penetration_mean_m: float
    floating_m: float
    jitter: float
    self_penetration_frac: float
    contact_frac: list[float]

    def as_dict(self) -> dict:
        return asdict(self)


def apparent_ground(lowest: np.ndarray, fps: float, window_s: float = 1.0, percentile: float = 10.0) -> np.ndarray:
    """Running ``percentile`` ``(T,)`` (m) of the lowest body point ``(T,)`` over a centred window."""
    size = max(1, int(round(window_s * fps)) | 1)
    return percentile_filter(np.asarray(lowest, dtype=float), percentile, size=size, mode="nearest")


def kinematic_contacts(points: np.ndarray, ground: np.ndarray, contact_height: float) -> np.ndarray:
    """Contact labels ``(T, 4)`` bool of foot points ``(T, 4, 3)`` (LT, RT, LH, RH) given the
    apparent ground height ``(T,)``."""
    return points[..., 2] <= ground[:, None] + contact_height


def horizontal_speed(points: np.ndarray, fps: float) -> np.ndarray:
    """Horizontal speed ``(T, P)`` (m/s) of points ``(T, P, 3)`` (or their horizontal ``(T, P, 2)``) by
    central differences."""
    return np.linalg.norm(np.gradient(points[..., :2], axis=0), axis=-1) * fps


def heading_frame_velocity(root_xy: np.ndarray, heading: np.ndarray, fps: float) -> np.ndarray:
    """``(T, 2)`` the horizontal velocity (m/s, central differences) of positions ``root_xy (T, 2)`` (m, world) at
    ``fps``, in the frame of ``heading (T,)`` (rad about +z from world x): along the heading (negative while moving
    backwards), then across it (positive to the left)."""
    velocity = np.gradient(np.asarray(root_xy, dtype=float), axis=0) * fps
    cos, sin = np.cos(heading), np.sin(heading)
    return np.stack([velocity[:, 0] * cos + velocity[:, 1] * sin, velocity[:, 1] * cos - velocity[:, 0] * sin], axis=1)


def held_contact_speeds(points: np.ndarray, contacts: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal speed ``(T-1, 4)`` (m/s) of foot points ``(T, 4, 3)`` from each frame to the next,
    and the ``(T-1, 4)`` bool mask of the (frame, point) pairs in contact ``(T, 4)`` in both frames:
    the pairs :func:`foot_skate` averages."""
    step = np.linalg.norm(np.diff(points[..., :2], axis=0), axis=-1) * fps
    return step, contacts[1:] & contacts[:-1]


def foot_skate(points: np.ndarray, contacts: np.ndarray, fps: float) -> float:
    """Mean horizontal speed (m/s) of foot points ``(T, 4, 3)`` over (frame, point) pairs in
    contact ``(T, 4)``; a pair counts when the point is in contact in two consecutive frames.
    0.0 when nothing is in contact."""
    step, held = held_contact_speeds(points, contacts, fps)
    return float(step[held].mean()) if held.any() else 0.0


def penetration(lowest: np.ndarray) -> tuple[float, float]:
    """(max, mean) depth (m) of the lowest body point ``(T,)`` below z = 0."""
    depth = np.maximum(-np.asarray(lowest, dtype=float), 0.0)
    return float(depth.max()), float(depth.mean())


def floating(lowest: np.ndarray, support: np.ndarray) -> float:
    """Mean height (m) above z = 0 of the lowest body point ``(T,)`` over support frames ``(T,)``."""
    if not np.any(support):
        return 0.0
    return float(np.maximum(lowest[support], 0.0).mean())


def jitter(hinges: np.ndarray, fps: float) -> float:
    """Mean absolute jerk (rad/s³) of hinge angles ``(T, n)`` by third finite differences."""
    if hinges.shape[0] < 4:
        return 0.0
    return float(np.abs(np.diff(hinges, n=3, axis=0)).mean() * fps**3)


def range_excursion(hinges: np.ndarray, ranges: np.ndarray) -> float:
    """Mean over frames of the summed excursion (rad) of hinge angles ``(T, n)`` beyond their
    ``ranges (n, 2)`` (lower, upper); 0 when every angle is in range."""
    below = np.clip(ranges[:, 0] - hinges, 0.0, None)
    above = np.clip(hinges - ranges[:, 1], 0.0, None)
    return float((below + above).sum(axis=1).mean()) if len(hinges) else 0.0


def replay_on_ground(motion: Motion, config: QualityConfig = QualityConfig()):
    """``motion`` replayed kinematically on its model (its ``Kinematics``: world-frame bodies, foot
    points, lowest point per frame) and its apparent ground ``(T,)`` (m)."""
    kin = load_model(motion.model).forward_kinematics(motion.qpos)
    return kin, apparent_ground(kin.lowest, motion.fps, config.ground_window_s, config.ground_percentile)


def motion_contacts(motion: Motion, config: QualityConfig = QualityConfig()) -> np.ndarray:
    """Kinematic contact labels ``(T, 4)`` bool (LT, RT, LH, RH) of ``motion``: foot points within
    ``config.contact_height`` of its apparent ground."""
    kin, ground = replay_on_ground(motion, config)
    return kinematic_contacts(kin.foot_points, ground, config.contact_height)


def motion_quality(motion: Motion, config: QualityConfig = QualityConfig()) -> QualityReport:
    """All artefact metrics of ``motion`` (replayed kinematically on its model)."""
    hm = load_model(motion.model)
    kin, ground = replay_on_ground(motion, config)
    contacts = kinematic_contacts(kin.foot_points, ground, config.contact_height)
    support = kin.lowest <= ground + config.support_height
    pen_max, pen_mean = penetration(kin.lowest)
    overlap = hm.self_penetration(motion.qpos, config.self_penetration_depth)
    return QualityReport(
        frames=motion.n_frames,
        fps=motion.fps,
        foot_skate_mps=foot_skate(kin.foot_points, contacts, motion.fps),
        penetration_max_m=pen_max,
        penetration_mean_m=pen_mean,
        floating_m=floating(kin.lowest, support),
        jitter=jitter(motion.hinges, motion.fps),
        self_penetration_frac=float(overlap.mean()),
        contact_frac=[float(c) for c in contacts.mean(0)],
    )
