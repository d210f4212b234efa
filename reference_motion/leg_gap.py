"""Legs parted: a take whose feet pass too close to each other, or cross, is given back a gap between
them by one constant abduction of both hips.

An IMU suit reads hip ab/adduction worst of the hip's three angles (``reference_motion.artefacts``:
8° toward the midline on both hips at strength 1, with slower drifts on top). That draws the feet
together by about ``2 × 0.9 m × sin 8° ≈ 25 cm``: on validation's takes the feet's median
sideways gap goes from 0.12–0.25 m clean to −0.17 to −0.06 m, legs crossed, and a policy that
tracks them trips over its own feet. It is the raw IMU takes' largest loss (README, round 21: with
every other artefact but this one, ``mimic_general_window`` performs validation's IMU takes 0.852
instead of 0.693).

A clean take never walks with its feet crossed for most of its length: over the library's 84
training takes the feet's median gap is 0.01–0.42 m (mean 0.18 m). :func:`part_legs` measures the
take's median gap (:func:`lateral_foot_gap`: the left foot's centre minus the right's, along the
pelvis' left axis) and, where it is below ``min_gap_m``, abducts both hips by the one constant angle
that brings it there (:func:`leg_abduction`, found by the secant method on the gap, which grows
almost linearly with the angle). A take whose median gap is already ``min_gap_m`` or more is left as
it is. The root, the other hinges and the timing are untouched; set the take on the floor afterwards
(:mod:`reference_motion.grounding`), since parted legs reach a little less far down.

Limits: the gap read is the median over the whole take, so one hip's offset (a take with one foot
crossing under the body and the other where it belongs) is shared between the two hips; a clean
take with its feet closer than ``min_gap_m`` (a catwalk's crossing steps) is widened too.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict, dataclass, fields

import numpy as np

from reference_motion import rotations as rot
from reference_motion.cli import positive_float
from reference_motion.humanoid.model import FOOT_CHANNELS, load_model
from reference_motion.motion import Motion

HIP_ABDUCTION = (("l_thigh_x", 1.0), ("r_thigh_x", -1.0))
"""The hip hinges that part the legs, each with the sign of its abduction (``reference_motion.artefacts``'
adduction turns them the other way)."""
LEG_LENGTH_M = 0.9
"""Hip to sole (m), for the first guess only: abducting a leg by ``a`` moves its foot about
``LEG_LENGTH_M · sin a`` sideways."""
GAP_TOLERANCE_M = 1e-3
"""The search stops once the median gap is this close (m) to ``LegGap.min_gap_m``."""


@dataclass(frozen=True)
class LegGap:
    """How far apart :func:`part_legs` keeps the feet.

    Attributes:
        min_gap_m: the feet's median sideways gap (m, between the centres of the two feet's sole
            points, along the pelvis' left axis) below which both hips are abducted to restore it.
            0.15 m, chosen on validation's IMU takes (probe seeds 670000+) among 0.10, 0.15 and 0.20
            m; below the mean of the library's clean training takes (0.18 m).
        max_abduction_rad: the largest constant abduction added to each hip (0.35 rad, 20°, more than
            twice the suit's 8°), so that a take whose feet cannot be read apart is not bent away.
        iterations: at most this many angles tried after the take as given (each one forward
            kinematics pass): the first guess, then secant steps; fewer once the gap is within
            :data:`GAP_TOLERANCE_M`, or the step would leave ``[0, max_abduction_rad]`` no further.
    """

    min_gap_m: float = 0.15
    max_abduction_rad: float = 0.35
    iterations: int = 3

    def __post_init__(self) -> None:
        for name in ("min_gap_m", "max_abduction_rad"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"LegGap.{name} must be a finite number > 0, got {value}")
        if self.iterations < 1:
            raise ValueError(f"LegGap.iterations must be >= 1, got {self.iterations}")

    @property
    def label(self) -> str:
        """How results name an actor that tracked takes with their legs parted (with the settings
        where they are not the defaults)."""
        default = LegGap()
        changed = [f"{f.name}={getattr(self, f.name)}" for f in fields(self)
                   if getattr(self, f.name) != getattr(default, f.name) and f.name != "min_gap_m"]
        return f"legs parted to {self.min_gap_m * 100:g} cm" + (f" ({', '.join(changed)})" if changed else "")


def lateral_foot_gap(model_name: str, qpos: np.ndarray) -> np.ndarray:
    """``(T,)`` the sideways gap (m) between the feet in each frame of ``qpos (T, nq)`` on the
    humanoid ``model_name``: the centre of the left foot's sole points minus the right's, along the
    left axis of the pelvis' heading (world xy); negative where the legs cross. A ``(nq,)`` pose is one
    frame."""
    qpos = np.atleast_2d(np.asarray(qpos, dtype=float))
    kin = load_model(model_name).forward_kinematics(qpos)  # raises for a qpos of another model
    left, right = (kin.foot_points[:, list(channels), :2].mean(axis=1) for channels in FOOT_CHANNELS)
    heading = rot.yaw(qpos[:, 3:7])
    left_axis = np.stack([-np.sin(heading), np.cos(heading)], axis=1)
    return np.sum((left - right) * left_axis, axis=1)


def median_foot_gap(model_name: str, qpos: np.ndarray) -> float:
    """The median over the frames of ``qpos (T, nq)`` of :func:`lateral_foot_gap` (m): how far apart a
    take walks its feet, whatever its single frames do."""
    return float(np.median(lateral_foot_gap(model_name, qpos)))


def abducted(motion: Motion, angle_rad: float) -> np.ndarray:
    """``motion``'s ``qpos (T, nq)`` with both hips abducted by ``angle_rad`` (negative: adducted),
    each kept within its hinge's range (as given where ``angle_rad`` is 0)."""
    model = load_model(motion.model)
    qpos = motion.qpos.copy()
    if angle_rad == 0.0:
        return qpos
    for joint, sign in HIP_ABDUCTION:
        index = model.qpos_index(joint)
        qpos[:, index] = np.clip(qpos[:, index] + sign * angle_rad, *model.hinge_range(joint))
    return qpos


def leg_abduction(motion: Motion, gap: LegGap = LegGap()) -> float:
    """The constant abduction (rad, ≥ 0, at most ``gap.max_abduction_rad``) of both hips that brings
    ``motion``'s median foot gap (:func:`lateral_foot_gap`) up to ``gap.min_gap_m``; 0 where it is
    there already. The first guess turns each leg by the angle whose sine, over a
    :data:`LEG_LENGTH_M` leg, moves its foot half the lack sideways; then secant steps, each kept
    within ``[0, gap.max_abduction_rad]``. Of the angles tried, the one whose gap came closest to
    ``gap.min_gap_m`` is returned (0 if none came closer than the take as given)."""
    def lack_at(angle: float) -> float:
        return gap.min_gap_m - median_foot_gap(motion.model, abducted(motion, angle))

    lacks = {0.0: lack_at(0.0)}
    if lacks[0.0] <= 0:
        return 0.0
    last = 0.0
    angle = min(float(np.arcsin(min(1.0, lacks[0.0] / (2 * LEG_LENGTH_M)))), gap.max_abduction_rad)
    for _ in range(gap.iterations):
        lacks[angle] = lack_at(angle)
        slope = (lacks[last] - lacks[angle]) / (angle - last)  # d gap / d angle
        if abs(lacks[angle]) < GAP_TOLERANCE_M or slope <= 0:
            break
        step = float(np.clip(angle + lacks[angle] / slope, 0.0, gap.max_abduction_rad))
        if step in lacks:  # at a bound it has tried: it can get no nearer
            break
        last, angle = angle, step
    return min(lacks, key=lambda tried: abs(lacks[tried]))


def part_legs(motion: Motion, gap: LegGap = LegGap()) -> Motion:
    """``motion`` with both hips abducted by :func:`leg_abduction` (itself where that is 0); its
    ``source`` records the settings and the angle (``leg_gap``, ``hip_abduction_rad``)."""
    angle = leg_abduction(motion, gap)
    if angle == 0.0:
        return motion
    return motion.with_qpos(abducted(motion, angle),
                            source={**motion.source, "leg_gap": asdict(gap), "hip_abduction_rad": angle})


def add_leg_gap_option(parser: argparse.ArgumentParser, what: str) -> None:
    """``--part-legs [M]`` (read back by :func:`leg_gap_of`); ``what`` ends its help."""
    parser.add_argument("--part-legs", type=positive_float, nargs="?", const=LegGap.min_gap_m, default=None,
                        metavar="M",
                        help=f"abduct both hips of a take whose feet's median sideways gap is below M metres "
                             f"(default {LegGap.min_gap_m}) by the constant that restores it, as an IMU suit's "
                             f"hip adduction crosses the legs (reference_motion/leg_gap.py; after --denoise, "
                             f"before --ground): {what}")


def leg_gap_of(args: argparse.Namespace) -> LegGap | None:
    """The :class:`LegGap` that :func:`add_leg_gap_option`'s argument asks for, or ``None``."""
    return LegGap(min_gap_m=args.part_legs) if args.part_legs is not None else None
