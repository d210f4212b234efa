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

from typing import TYPE_CHECKING

from reference_motion.grounding import Grounding, ground
from reference_motion.leg_gap import LegGap, part_legs
from reference_motion.leg_symmetry import LegSymmetry, even_legs
from reference_motion.motion import Motion
from reference_motion.swing_lift import SwingLift, lift_swing

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
