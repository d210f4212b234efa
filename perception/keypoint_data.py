"""Keypoint training and test data: the physics dataset's motions filmed by synthetic cameras
(contactvision §4–5).

Every episode of a physics dataset split (:func:`perception.dataset.load_split`) becomes a
:class:`KeypointSequence`: the 25 BODY_25 points of the simulated character in 3D and Γ's
contact labels of its simulated insole forces. Cameras are placed relative to the subject's
heading (:func:`body_heading`): training views come from ContactVision's eight-camera rig (every
45°, :attr:`ViewConfig.train_azimuths_deg`) with jitter, as fixed, random or hand-held cameras
(:func:`draw_train_view`); the test views sit halfway between the rig's cameras
(:func:`held_out_views`), so no training window is ever filmed from them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from perception.contacts import ContactFunction
from perception.dataset import load_split
from perception.keypoints import (FULL_BODY_KEYPOINTS, KEYPOINT_SETS, KEYPOINTS, Camera, follow_camera,
                                  handheld_camera, motion_keypoints, observe, random_camera)
from reference_motion.motion import Motion

CAMERA_KINDS = ("rig", "random", "handheld")


@dataclass(frozen=True)
class ViewConfig:
    """Which cameras film training windows and which film the test.

    Attributes:
        train_azimuths_deg: the training rig's azimuths relative to the subject's heading
            (0 = in front, 90 = on its left): ContactVision's eight cameras, every 45°.
        azimuth_jitter_deg: a training view's azimuth is a rig azimuth ± up to this.
        camera_shares: probabilities of a ``rig`` camera (4 m away, 1 m high, 1000 px focal
            length, as :func:`~perception.keypoints.ring_cameras`), a ``random`` one (random
            distance, height, aim and focal length) and a ``handheld`` one (random, lagging and shaking).
        noise_px_range: per-window pixel noise σ drawn uniformly from this range.
        drop_prob_range: per-window probability that a detector misses a point.
        test_azimuths_deg: test views, halfway between the rig's cameras (never used in training).
        test_distance_m, test_height_m, test_focal_px: the static test cameras.
        test_noise_px, test_drop_prob: detector noise of the test views.
    """

    train_azimuths_deg: tuple[float, ...] = tuple(45.0 * k for k in range(8))
    azimuth_jitter_deg: float = 7.5
    camera_shares: tuple[float, float, float] = (0.4, 0.3, 0.3)
    noise_px_range: tuple[float, float] = (0.5, 4.0)
    drop_prob_range: tuple[float, float] = (0.0, 0.05)
    test_azimuths_deg: tuple[float, ...] = tuple(22.5 + 45.0 * k for k in range(8))
    test_distance_m: float = 4.5
    test_height_m: float = 1.3
    test_focal_px: float = 1100.0
    test_noise_px: float = 2.0
    test_drop_prob: float = 0.02


@dataclass(frozen=True)
class View:
    """One camera view: its ``kind`` (:data:`CAMERA_KINDS`), azimuth relative to the subject's
    heading (rad), detector noise (px) and drop probability."""

    kind: str
    azimuth: float
    noise_px: float
    drop_prob: float

    @property
    def name(self) -> str:
        return f"{self.kind}@{np.degrees(self.azimuth) % 360:.1f}"


@dataclass
class KeypointSequence:
    """One episode: world ``points (T, 25, 3)`` (m, :data:`FULL_BODY_KEYPOINTS`), Γ ``labels
    (T, 4)`` bool (CONTACT_CHANNELS order), ``fps``, source ``clip``."""

    points: np.ndarray
    labels: np.ndarray
    fps: float
    clip: str

    def __len__(self) -> int:
        return len(self.points)


def load_keypoint_split(root: Path, split: str, gamma: ContactFunction = ContactFunction()) -> list[KeypointSequence]:
    """Every episode of ``split`` of the physics dataset at ``root`` as keypoints and labels."""
    out = []
    for s in load_split(root, split):
        if s.qpos is None:
            raise ValueError(f"{root}/{split}: sequence of {s.clip!r} carries no qpos; keypoints need the simulated pose")
        points = motion_keypoints(Motion(s.clip, s.fps, s.qpos, s.model), FULL_BODY_KEYPOINTS)
        out.append(KeypointSequence(points.astype(np.float32), gamma(s.forces, s.fps), s.fps, s.clip))
    return out


def body_heading(points: np.ndarray) -> float:
    """The subject's mean heading (rad, world azimuth of its forward direction) over points
    ``(T, K, 3)`` in :data:`KEYPOINTS` order: forward is perpendicular to the hip line."""
    left, right = KEYPOINTS.index("left_hip"), KEYPOINTS.index("right_hip")
    across = points[:, left, :2] - points[:, right, :2]               # points to the subject's left
    forward = np.stack([across[:, 1], -across[:, 0]], axis=-1)        # (y, -x): a quarter turn clockwise
    mean = forward.sum(0)
    return float(np.arctan2(mean[1], mean[0]))


def draw_train_view(rng: np.random.Generator, config: ViewConfig = ViewConfig()) -> View:
    """A random training view (:class:`ViewConfig`)."""
    kind = CAMERA_KINDS[int(rng.choice(len(CAMERA_KINDS), p=np.asarray(config.camera_shares) / sum(config.camera_shares)))]
    azimuth = np.radians(rng.choice(config.train_azimuths_deg) + rng.uniform(-1, 1) * config.azimuth_jitter_deg)
    return View(kind, float(azimuth), float(rng.uniform(*config.noise_px_range)), float(rng.uniform(*config.drop_prob_range)))


def held_out_views(config: ViewConfig = ViewConfig(), kind: str = "rig") -> list[View]:
    """The held-out views at :attr:`ViewConfig.test_azimuths_deg`, with the test rig's distance,
    height and focal length: ``rig`` = static cameras following the subject, ``handheld`` =
    hand-held ones (lagging, shaking) starting from there."""
    if kind not in ("rig", "handheld"):
        raise ValueError(f"unknown test view kind {kind!r}; expected 'rig' or 'handheld'")
    return [View(kind, float(np.radians(a)), config.test_noise_px, config.test_drop_prob) for a in config.test_azimuths_deg]


def camera_for(view: View, points: np.ndarray, rng: np.random.Generator, fps: float, test: bool = False,
               config: ViewConfig = ViewConfig()) -> Camera:
    """The camera of ``view`` filming points ``(T, K, 3)`` (its azimuth turned by the subject's
    mean heading); ``test`` uses the test rig's distance, height and focal length."""
    pelvis = points[:, 0]
    azimuth = body_heading(points) + view.azimuth
    fixed = {"distance": config.test_distance_m, "height": config.test_height_m, "aim_height": 0.6,
             "focal_px": config.test_focal_px}
    if view.kind == "handheld":
        return handheld_camera(pelvis, rng, azimuth=azimuth, fps=fps, view=fixed if test else None)
    if view.kind == "random":
        return random_camera(pelvis, rng, azimuth=azimuth)
    if test:
        return follow_camera(pelvis, azimuth, **fixed)
    return follow_camera(pelvis, azimuth)


def film(points: np.ndarray, view: View, rng: np.random.Generator, fps: float, keypoints: str = "lower",
         test: bool = False, config: ViewConfig = ViewConfig()) -> np.ndarray:
    """Detector-like keypoints ``(T, K, 3)`` (pixels, confidence) of world points ``(T, 25, 3)``
    seen from ``view``; ``keypoints`` picks the set (``lower``: 13, ``full``: 25)."""
    camera = camera_for(view, points, rng, fps, test, config)
    k = len(KEYPOINT_SETS[keypoints])
    return observe(points[:, :k], camera, rng, noise_px=view.noise_px, drop_prob=view.drop_prob)
