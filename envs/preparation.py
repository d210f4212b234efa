"""What a policy tracks of a take: the take after an IMU denoiser, its legs evened and parted, set on
the floor, then with its backward steps' knees lifted in swing (each step only when asked for).

Evaluation and cleaning prepare a take this way (``evaluate.py``, ``clean.py`` and
``bench/imu_draws.py`` with ``--denoise``, ``--even-legs``, ``--part-legs``, ``--ground``, ``--swing-lift``) and judge
the simulation against the take as given; training can prepare its references the same way
(:class:`envs.config.ArtefactMix`'s ``denoiser``, ``symmetry``, ``legs``, ``grounding`` and ``lift``), so that a policy
learns on what it will be given. The denoiser is imported only when one is given, so that
``import envs`` stays free of torch.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict
from typing import TYPE_CHECKING, TypedDict

from reference_motion.grounding import Grounding, ground, grounding_of
from reference_motion.leg_gap import LegGap, leg_gap_of, part_legs
from reference_motion.leg_symmetry import LegSymmetry, even_legs, leg_symmetry_of
from reference_motion.motion import Motion
from reference_motion.swing_lift import SwingLift, lift_swing, swing_lift_of

if TYPE_CHECKING:  # torch only where a denoiser is given
    from perception.imu_denoiser import DenoiserEnsemble, IMUDenoiser, SlowCorrections

    Denoiser = IMUDenoiser | DenoiserEnsemble | SlowCorrections


def prepared(take: Motion, denoiser: Denoiser | None = None, *, symmetry: LegSymmetry | None = None,
             legs: LegGap | None = None, grounding: Grounding | None = None, lift: SwingLift | None = None) -> Motion:
    """What a policy tracks of ``take``: the take after ``denoiser`` (``--denoise``), then with its
    legs evened (``symmetry``, ``--even-legs``), then parted (``legs``, ``--part-legs``), then set on
    the floor (``grounding``, ``--ground``),
    then with its backward steps' knees lifted in swing (``lift``, ``--swing-lift``); each step only
    when given. Same frames, rate and model."""
    if denoiser is not None:
        from perception.imu_denoiser import denoise
        take = denoise(denoiser, take)
    if symmetry is not None:
        take = even_legs(take, symmetry)
    if legs is not None:
        take = part_legs(take, legs)
    if grounding is not None:
        take = ground(take, grounding)
    return lift_swing(take, lift) if lift is not None else take


class PreparationSteps(TypedDict):
    """The steps of :func:`prepared` after the denoiser, each ``None`` when not asked for: keyword
    arguments of :func:`prepared`, :class:`envs.config.ArtefactMix`, ``agents.evaluate.tracked_and_judged``
    and ``MimicPolicy.preparation_note``."""

    symmetry: LegSymmetry | None
    legs: LegGap | None
    grounding: Grounding | None
    lift: SwingLift | None


def preparation_of(args: argparse.Namespace) -> PreparationSteps:
    """The steps a command line asks for with ``--even-legs``, ``--part-legs``, ``--ground`` and
    ``--swing-lift`` (each added to its parser by ``reference_motion``'s ``add_*_option``)."""
    return PreparationSteps(symmetry=leg_symmetry_of(args), legs=leg_gap_of(args), grounding=grounding_of(args),
                            lift=swing_lift_of(args))


def no_preparation() -> PreparationSteps:
    """Steps that prepare nothing (each ``None``)."""
    return PreparationSteps(symmetry=None, legs=None, grounding=None, lift=None)


def prepares_any(steps: PreparationSteps) -> bool:
    """Whether ``steps`` asks for any step at all."""
    return any(step is not None for step in steps.values())


def preparation_record(steps: PreparationSteps, *, lift_key: str = "swing_lift") -> dict[str, dict | None]:
    """``steps`` as records keep them: ``leg_symmetry``, ``legs``, ``grounding`` and ``lift_key``, each the
    step's settings as a dict or ``None``. The ``--json`` of ``evaluate.py``, ``clean.py`` and
    ``bench/imu_draws.py`` names the lift ``swing_lift``; :class:`agents.sidecar.TrainingRecord` names it ``lift``."""
    names = {"symmetry": "leg_symmetry", "legs": "legs", "grounding": "grounding", "lift": lift_key}
    return {names[step]: asdict(settings) if settings is not None else None for step, settings in steps.items()}
