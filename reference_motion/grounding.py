"""A take set on the floor: its pelvis moved up or down so that its apparent ground is at z = 0.

An IMU suit reads the pelvis height badly (``reference_motion.artefacts``: 4 cm offsets and a 1 cm
wobble at strength 1), and the IMU denoiser (:mod:`perception.imu_denoiser`) leaves 2.3 cm RMS of it
on validation's takes: in its loss the height is one channel among 44 (43 hinges on
``humanoid_1seg``), so a 2.5 cm error weighs as much as a 1.4° error on one hinge. Yet every take
stands on the floor somewhere in each second, and a clean take's apparent ground
(:func:`reference_motion.quality.apparent_ground`, the running 10th percentile of the body's lowest
point over 1 s) is close to z = 0: on validation's takes its smoothed offset averages 0.1–1.4 mm per
take. :func:`ground` moves the pelvis by minus that apparent ground, smoothed by a Gaussian of
``smooth_s`` so the correction cannot add a bounce of its own; the hinge angles and the horizontal
path are untouched. On validation's IMU takes after the denoiser the pelvis height's error against
the clean take goes from 2.32 to 1.51 cm RMS (README, round 9).

Limits: the window's edges repeat the first and last frames, so a take that starts (or ends) with
its body in the air for a large part of a second is lowered there (walk_happy_001 starts 4.9 cm
above the floor and first touches it after a quarter of a second: it is lowered 1.5 cm at its start,
and its first footfall reaches 7 mm into the floor instead of 0.2 mm); and a body off the floor for
most of a second or longer (a long jump's flight) is pulled down in mid-air.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict, dataclass, field, fields

import numpy as np
from scipy.ndimage import gaussian_filter1d

from reference_motion.motion import Motion
from reference_motion.quality import QualityConfig, replay_on_ground


@dataclass(frozen=True)
class Grounding:
    """How :func:`ground` reads the floor.

    Attributes:
        smooth_s: std (s) of the Gaussian that smooths the apparent ground before it is taken out
            (0.25 s: a quarter of its 1 s window).
        quality: the apparent ground's window and percentile (``ground_window_s``,
            ``ground_percentile``: 1 s and the 10th percentile, the artefact metrics' own).
    """

    smooth_s: float = 0.25
    quality: QualityConfig = field(default_factory=QualityConfig)

    def __post_init__(self) -> None:
        if not np.isfinite(self.smooth_s) or self.smooth_s < 0:
            raise ValueError(f"Grounding.smooth_s must be a finite number of seconds >= 0, got {self.smooth_s}")

    @property
    def label(self) -> str:
        """How results name an actor that tracked grounded takes (with the settings where they are
        not the defaults, so two groundings are told apart)."""
        default = Grounding()
        changed = [f"{f.name}={getattr(self, f.name)}" for f in fields(self)
                   if getattr(self, f.name) != getattr(default, f.name)]
        return "grounded" + (f" ({', '.join(changed)})" if changed else "")


def ground_offset(motion: Motion, grounding: Grounding = Grounding()) -> np.ndarray:
    """The smoothed apparent ground ``(T,)`` (m, world z) of ``motion``: what :func:`ground`
    takes off its pelvis height."""
    _, apparent = replay_on_ground(motion, grounding.quality)
    if grounding.smooth_s == 0:
        return apparent
    return gaussian_filter1d(apparent, grounding.smooth_s * motion.fps, mode="nearest")


def ground(motion: Motion, grounding: Grounding = Grounding()) -> Motion:
    """``motion`` with its pelvis height lowered by :func:`ground_offset` (raised where that is
    below the floor), everything else as it is; its ``source`` records the grounding."""
    qpos = motion.qpos.copy()
    qpos[:, 2] -= ground_offset(motion, grounding)
    return motion.with_qpos(qpos, source={**motion.source, "grounding": asdict(grounding)})


def add_grounding_option(parser: argparse.ArgumentParser, what: str) -> None:
    """``--ground`` (read back by :func:`grounding_of`); ``what`` ends its help: what the grounded
    takes are for."""
    parser.add_argument("--ground", action="store_true",
                        help="set the take on the floor: move its pelvis so its apparent ground is at z = 0 "
                             f"(reference_motion/grounding.py; after --denoise, before --swing-lift): {what}")


def grounding_of(args: argparse.Namespace) -> Grounding | None:
    """The :class:`Grounding` that :func:`add_grounding_option`'s argument asks for, or ``None``."""
    return Grounding() if args.ground else None
