"""Legs evened: the part of a take's left–right difference in mean leg angles that an IMU suit
most likely added, taken out, half from each leg.

An IMU suit reads every hinge with its own constant offset and slow drift
(``reference_motion.artefacts``: 2° of bias and 2° of drift with a 2 s timescale at strength 1, so
over a 5 s take each hinge is off by a nearly constant ≈ 3°). The two legs of a walk or a run do the
same thing half a stride apart, so over a take the mean angle of each left leg hinge is close to its
right twin's, mirrored: over the library's 84 clean training takes the difference
(:func:`leg_asymmetry`) has a spread of 2.5–4.5° for the hinges that bend the legs (against the
suit's √2 × 3° ≈ 4.4° for the difference of two offsets), and 10° only for the thigh's twist.
Knowing both spreads, the suit's share of a take's difference is estimated by shrinkage (the
posterior mean for Gaussian clean differences and offsets): ``k · (d − μ)`` with
``k = σ_suit² / (σ_suit² + σ_clean²)``, where ``μ`` and ``σ_clean`` are the clean takes' mean and
spread of the difference (:data:`LIBRARY_ASYMMETRY`). :func:`even_legs` takes it out, half from
each leg, as one constant per hinge over the take; the sum of the two legs' means, the timing and
everything else are untouched.

This reads only the difference between the legs: the offset both legs share is as large, and stays.
It needs no training. It assumes a take that is symmetric on average (walking, running, turning
both ways, not limping): a take whose legs differ for real (a limp, a long turn one way) is evened a
little too (by ``k``, 0.16–0.76 of the difference beyond the library's mean).
"""

from __future__ import annotations

import argparse
from dataclasses import asdict, dataclass

import numpy as np

from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion
from reference_motion.transforms import mirror_map, mirror_twin

LEG_HINGES = ("l_thigh_x", "l_thigh_y", "l_thigh_z", "l_shin_y", "l_foot_x", "l_foot_y", "l_foot_z")
"""The left leg's hinges; each is evened with its right twin (:func:`reference_motion.transforms.mirror_twin`)."""

LIBRARY_ASYMMETRY = (("l_thigh_x", 1.52, 3.52), ("l_thigh_y", -0.51, 3.90), ("l_thigh_z", -1.87, 9.92),
                     ("l_shin_y", 1.09, 2.49), ("l_foot_x", -4.33, 3.50), ("l_foot_y", -0.53, 3.75),
                     ("l_foot_z", -5.65, 4.50))
"""Per left leg hinge, the mean and spread (degrees) of :func:`leg_asymmetry` over the 84 clean
training takes of the motion library (``humanoid_1seg``, each take as evaluation loads it),
reproduced by ``python bench/leg_symmetry.py``. 75 of the 84 are Bandai Namco's, and the feet's
nonzero means are that rig's: its retargeted feet are turned a few degrees one way on both sides
(foot x and z −4.7° and −6.0° on its takes, −0.8° and −2.3° on CMU's, +2.0° and +2.5° on
DeepMimic's clips), so a take from another rig has its feet evened toward Bandai Namco's turn by up
to ``k`` (0.61, 0.49) of the difference; a prior fitted on that rig's clean takes
(``LegSymmetry(clean=...)``) avoids it."""


@dataclass(frozen=True)
class LegSymmetry:
    """How far :func:`even_legs` trusts a take's legs to be alike.

    Attributes:
        suit_offset_deg: spread (degrees) of the constant error the suit adds to each hinge over a
            take: 3.1°, measured on validation's takes at strength 1 (``ArtefactScales``' 2° bias and
            the take mean of its 2° drift, 2.3° over validation's 5.3 s takes on average). A take with
            smaller offsets (a better suit, a weaker corruption, a take behind the IMU denoiser, a
            clean take) is evened more than its offsets call for.
        clean: ``(hinge, mean, spread)`` per left leg hinge to even: the clean takes' asymmetry
            (degrees; default :data:`LIBRARY_ASYMMETRY`), as the takes were recorded (a mirrored
            take, ``source["mirrored"]``, is read against the mirrored mean). Hinges left out are not
            evened.
    """

    suit_offset_deg: float = 3.1
    clean: tuple[tuple[str, float, float], ...] = LIBRARY_ASYMMETRY

    def __post_init__(self) -> None:
        try:
            offset = float(self.suit_offset_deg)
        except (TypeError, ValueError):
            offset = float("nan")
        if not (np.isfinite(offset) and offset > 0):
            raise ValueError(f"LegSymmetry.suit_offset_deg must be a finite number > 0, got {self.suit_offset_deg!r}")
        object.__setattr__(self, "suit_offset_deg", offset)
        clean = []
        for entry in self.clean:
            try:
                hinge, mean, std = entry
                row = (str(hinge), float(mean), float(std))
            except (TypeError, ValueError):
                raise ValueError(f"LegSymmetry.clean: each entry must be (hinge, mean_deg, spread_deg), got {entry!r}")
            if row[0] not in LEG_HINGES:
                raise ValueError(f"LegSymmetry.clean: {row[0]!r} is not a left leg hinge; expected one of {LEG_HINGES}")
            if not (np.isfinite(row[1]) and np.isfinite(row[2]) and row[2] >= 0):
                raise ValueError(f"LegSymmetry.clean[{row[0]!r}] must be a finite (mean, spread >= 0), got {row[1:]}")
            if any(row[0] == other for other, _, _ in clean):
                raise ValueError(f"LegSymmetry.clean: {row[0]!r} is given twice")
            clean.append(row)
        object.__setattr__(self, "clean", tuple(clean))  # as a sidecar's lists give it back, hashable

    def shrinkage(self, spread_deg: float) -> float:
        """The share ``k`` (0–1) of a hinge's asymmetry beyond the clean mean that is the suit's,
        for clean takes whose asymmetry spreads by ``spread_deg``."""
        suit = 2.0 * self.suit_offset_deg ** 2  # the difference of two independent offsets
        return suit / (suit + spread_deg ** 2)

    @property
    def label(self) -> str:
        """How results name an actor that tracked evened takes (with the settings where they are
        not the defaults; another prior as ``clean=custom``)."""
        default = LegSymmetry()
        changed = ([f"suit_offset_deg={self.suit_offset_deg:g}"] if self.suit_offset_deg != default.suit_offset_deg
                   else []) + (["clean=custom"] if self.clean != default.clean else [])
        return "legs evened" + (f" ({', '.join(changed)})" if changed else "")


def leg_asymmetry(motion: Motion, hinges: tuple[str, ...] = LEG_HINGES) -> np.ndarray:
    """``(len(hinges),)`` each left hinge's take mean minus its right twin's, mirrored (rad): the
    right twin's mean with its sign flipped for hinges about x or z (which the mirror turns the
    other way), so a take and its mirror image have opposite asymmetries."""
    outside = sorted(set(hinges) - set(LEG_HINGES))
    if outside:
        raise ValueError(f"leg_asymmetry: {outside} are not left leg hinges; expected some of {LEG_HINGES}")
    model = load_model(motion.model)
    _, sign = mirror_map(motion.model)
    mean = motion.qpos.mean(axis=0)
    out = []
    for hinge in hinges:
        left, right = model.qpos_index(hinge), model.qpos_index(mirror_twin(hinge))
        out.append(mean[left] - sign[left] * mean[right])
    return np.array(out)


def leg_corrections(motion: Motion, symmetry: LegSymmetry = LegSymmetry()) -> dict[str, float]:
    """Per left leg hinge of ``symmetry.clean``, the suit's estimated share (rad) of the take's
    asymmetry: ``k · (d − μ)`` (:meth:`LegSymmetry.shrinkage`), with ``−μ`` for a mirrored take
    (``source["mirrored"]``), so a take and its mirror image get opposite corrections."""
    asymmetry = leg_asymmetry(motion, tuple(hinge for hinge, _, _ in symmetry.clean))
    side = -1.0 if motion.source.get("mirrored", False) else 1.0
    return {hinge: symmetry.shrinkage(spread) * (d - side * np.radians(mean))
            for (hinge, mean, spread), d in zip(symmetry.clean, asymmetry)}


def even_legs(motion: Motion, symmetry: LegSymmetry = LegSymmetry()) -> Motion:
    """``motion`` with :func:`leg_corrections` taken out, half from each leg (the left hinge moves by
    minus half, its right twin by half, mirrored), and each evened hinge kept within its hinge's
    range at every frame (as :func:`reference_motion.leg_gap.abducted` keeps the hips): a frame the
    move takes beyond the range stops at its end, so there the correction made is smaller than
    recorded, and a frame the take itself has beyond the range is brought to its end. The hinges not
    evened are as given. Its ``source`` records the settings and the corrections (``leg_symmetry``,
    ``leg_corrections_rad``)."""
    model = load_model(motion.model)
    _, sign = mirror_map(motion.model)
    corrections = leg_corrections(motion, symmetry)
    qpos = motion.qpos.copy()
    for hinge, correction in corrections.items():
        right_move = sign[model.qpos_index(hinge)] * correction / 2
        for joint, move in ((hinge, -correction / 2), (mirror_twin(hinge), right_move)):
            column = model.qpos_index(joint)
            qpos[:, column] = np.clip(qpos[:, column] + move, *model.hinge_range(joint))
    return motion.with_qpos(qpos, source={**motion.source, "leg_symmetry": asdict(symmetry),
                                          "leg_corrections_rad": {h: float(c) for h, c in corrections.items()}})


def add_leg_symmetry_option(parser: argparse.ArgumentParser, what: str) -> None:
    """``--even-legs`` (read back by :func:`leg_symmetry_of`); ``what`` ends its help."""
    parser.add_argument("--even-legs", action="store_true",
                        help="take out the part of the legs' left-right difference in mean hinge angles that an "
                             "IMU suit's per-hinge offsets most likely added (reference_motion/leg_symmetry.py; "
                             "after --denoise, before --part-legs; set for a raw take of an IMU suit at strength 1, "
                             f"it evens takes with smaller offsets more than they need): {what}")


def leg_symmetry_of(args: argparse.Namespace) -> LegSymmetry | None:
    """The :class:`LegSymmetry` that :func:`add_leg_symmetry_option`'s argument asks for, or ``None``."""
    return LegSymmetry() if args.even_legs else None
