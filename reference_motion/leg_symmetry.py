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
training takes of the motion library (``humanoid_1seg``, each take as evaluation loads it), reproduced by ``python
bench/leg_symmetry.py --fit``. The feet's nonzero means are the Bandai Namco rig's: its retargeted
feet are turned a few degrees one way on both sides."""


@dataclass(frozen=True)
class LegSymmetry:
    """How far :func:`even_legs` trusts a take's legs to be alike.

    Attributes:
        suit_offset_deg: spread (degrees) of the constant error the suit adds to each hinge over a
            take: 3.1°, measured on validation's takes at strength 1 (``ArtefactScales``' 2° bias and
            the take mean of its 2° drift, 2.3° over validation's 5.3 s takes on average).
        clean: ``(hinge, mean, spread)`` per left leg hinge to even: the clean takes' asymmetry
            (degrees; default :data:`LIBRARY_ASYMMETRY`). Hinges left out are not evened.
    """

    suit_offset_deg: float = 3.1
    clean: tuple[tuple[str, float, float], ...] = LIBRARY_ASYMMETRY

    def __post_init__(self) -> None:
        if not (np.isfinite(self.suit_offset_deg) and self.suit_offset_deg > 0):
            raise ValueError(f"LegSymmetry.suit_offset_deg must be a finite number > 0, got {self.suit_offset_deg}")
        clean = tuple((str(hinge), float(mean), float(std)) for hinge, mean, std in self.clean)
        object.__setattr__(self, "clean", clean)  # as a sidecar's lists give it back, hashable
        unknown = sorted({hinge for hinge, _, _ in clean} - set(LEG_HINGES))
        if unknown:
            raise ValueError(f"LegSymmetry.clean: {unknown} are not left leg hinges; expected some of {LEG_HINGES}")
        for hinge, mean, std in clean:
            if not (np.isfinite(mean) and np.isfinite(std) and std >= 0):
                raise ValueError(f"LegSymmetry.clean[{hinge!r}] must be a finite (mean, std >= 0), got {(mean, std)}")

    def shrinkage(self, spread_deg: float) -> float:
        """The share ``k`` (0–1) of a hinge's asymmetry beyond the clean mean that is the suit's,
        for clean takes whose asymmetry spreads by ``spread_deg``."""
        suit = 2.0 * self.suit_offset_deg ** 2  # the difference of two independent offsets
        return suit / (suit + spread_deg ** 2)

    @property
    def label(self) -> str:
        """How results name an actor that tracked evened takes (with the settings where they are
        not the defaults)."""
        return "legs evened" + ("" if self == LegSymmetry() else f" ({asdict(self)})")


def leg_asymmetry(motion: Motion, hinges: tuple[str, ...] = LEG_HINGES) -> np.ndarray:
    """``(len(hinges),)`` each left hinge's take mean minus its right twin's, mirrored (rad): the
    right twin's mean with its sign flipped for hinges about x or z (which the mirror turns the
    other way), so a take and its mirror image have opposite asymmetries."""
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
    asymmetry: ``k · (d − μ)`` (:meth:`LegSymmetry.shrinkage`)."""
    asymmetry = leg_asymmetry(motion, tuple(hinge for hinge, _, _ in symmetry.clean))
    return {hinge: symmetry.shrinkage(spread) * (d - np.radians(mean))
            for (hinge, mean, spread), d in zip(symmetry.clean, asymmetry)}


def even_legs(motion: Motion, symmetry: LegSymmetry = LegSymmetry()) -> Motion:
    """``motion`` with :func:`leg_corrections` taken out, half from each leg (the left hinge moves by
    minus half, its right twin by half, mirrored), each kept within its hinge's range; its
    ``source`` records the settings and the corrections (``leg_symmetry``, ``leg_corrections_rad``)."""
    model = load_model(motion.model)
    _, sign = mirror_map(motion.model)
    corrections = leg_corrections(motion, symmetry)
    qpos = motion.qpos.copy()
    for hinge, correction in corrections.items():
        left, right = model.qpos_index(hinge), model.qpos_index(mirror_twin(hinge))
        qpos[:, left] = np.clip(qpos[:, left] - correction / 2, *model.hinge_range(hinge))
        qpos[:, right] = np.clip(qpos[:, right] + sign[left] * correction / 2, *model.hinge_range(mirror_twin(hinge)))
    return motion.with_qpos(qpos, source={**motion.source, "leg_symmetry": asdict(symmetry),
                                          "leg_corrections_rad": {h: float(c) for h, c in corrections.items()}})


def add_leg_symmetry_option(parser: argparse.ArgumentParser, what: str) -> None:
    """``--even-legs`` (read back by :func:`leg_symmetry_of`); ``what`` ends its help."""
    parser.add_argument("--even-legs", action="store_true",
                        help="take out the part of the legs' left-right difference in mean hinge angles that an "
                             "IMU suit's per-hinge offsets most likely added (reference_motion/leg_symmetry.py; "
                             f"after --denoise, before --part-legs): {what}")


def leg_symmetry_of(args: argparse.Namespace) -> LegSymmetry | None:
    """The :class:`LegSymmetry` that :func:`add_leg_symmetry_option`'s argument asks for, or ``None``."""
    return LegSymmetry() if args.even_legs else None
