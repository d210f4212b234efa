"""Round 52 probe (stop 92), not shipped: feet levelled in stance, the tilt that an IMU suit's leg hinges give a planted foot, taken out.

A foot planted on a level floor stands flat in the middle of its stance. Over the motion library's
clean training takes (whose feet the retargeter levels once per rig, ``reference_motion/retarget.py``
step 5) a planted sole's mean pitch over the middle half of a stance is within about 1° of level,
stance after stance (:data:`LIBRARY_STANCE_TILT`). An IMU suit reads every leg hinge with its own
offset and slow drift (``reference_motion.artefacts``: 2° of bias and 2° of drift with a 2 s
timescale at strength 1); summed down the leg they tilt the planted foot by several degrees, and
the tilt wanders with the drift. Unlike the drift of one hinge, which the take cannot show, the sum
down the leg shows at every stance as a foot that is not flat on the floor.

:func:`level_feet` reads each stance's mean sole pitch and roll over the middle of the stance,
takes the suit's most likely share of its departure from the clean stances' mean by shrinkage
(the posterior mean for Gaussian clean tilts and suit errors, ``k · (tilt − μ)`` with
``k = σ_suit² / (σ_suit² + σ_clean²)``, as :mod:`reference_motion.leg_symmetry` does for the legs'
difference), interpolates it linearly between the stances of that foot (held before the first and
after the last), and turns the foot's ankle hinges (``foot_y`` for pitch, ``foot_x`` for roll) back
by it on every frame. The sole's orientation is then corrected in swing too, where the same hinge
errors tilt it; the hips and knees keep theirs. It needs no training.

Measured (docs/results.md, "Round 52"): it takes the suit's stance pitch from 3.6° to 1.3° RMS on the training split
and leaves validation's raw ELR where it was (0.941 → 0.941), so it stays a probe.

It assumes a level floor and feet flat in mid-stance (walking, running, turning, standing): a take
walked on tiptoe or on slopes is levelled toward a flat foot by ``k`` of its tilt.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from reference_motion.footskate import contact_windows
from reference_motion.humanoid.model import Kinematics, load_model
from reference_motion.motion import Motion
from reference_motion.quality import apparent_ground, horizontal_speed

FOOT_BODIES = ("l_foot", "r_foot")
"""The feet's bodies, left then right."""

LIBRARY_STANCE_TILT = ((-0.3, 1.1), (0.0, 0.7), (-1.5, 4.5), (-1.2, 3.9))
"""Mean and spread (degrees) of a stance's mean sole tilt over the clean training takes of the motion
library (``humanoid_1seg``, stances found by :func:`stance_windows`; ``foot_stats.py train``): left pitch, right pitch,
left roll, right roll (as :func:`sole_tilt` reads them on both feet alike: positive pitch lifts the toe,
positive roll lifts the foot's left edge)."""


@dataclass(frozen=True)
class FootLevel:
    """How :func:`level_feet` finds the stances and how far it trusts their tilt.

    Attributes:
        suit_pitch_deg: spread (degrees) of the pitch the suit's leg hinges add to a planted sole at
            strength 1: 3.6°, measured on the training split's takes with bias and drift only, after
            ``--even-legs --part-legs`` (``foot_stats.py train 1780000``; every kind: 3.5°).
        suit_roll_deg: the same for the sole's roll: 3.9° (every kind: 4.2°).
        clean: ``((mean, spread), ...)`` of the clean stances' tilt, in
            :data:`LIBRARY_STANCE_TILT`'s order (degrees).
        contact_height_m: a foot whose toe and heel are both within this height (m) of the take's
            apparent ground may be planted flat.
        max_speed_mps: ... and whose sole moves horizontally slower than this (m/s).
        min_stance_s: a stance shorter than this (s) is not read.
        middle: the share of each stance, centred, over which its tilt is averaged (heel strike and
            push-off tilt the foot for real).
    """

    suit_pitch_deg: float = 3.6
    suit_roll_deg: float = 3.9
    clean: tuple[tuple[float, float], ...] = LIBRARY_STANCE_TILT
    contact_height_m: float = 0.03
    max_speed_mps: float = 1.0
    min_stance_s: float = 0.15
    middle: float = 0.5

    def __post_init__(self) -> None:
        for name in ("suit_pitch_deg", "suit_roll_deg", "contact_height_m", "max_speed_mps", "min_stance_s"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
                raise ValueError(f"FootLevel.{name} must be a finite number > 0, got {value!r}")
        if not 0 < self.middle <= 1:
            raise ValueError(f"FootLevel.middle must be in (0, 1], got {self.middle!r}")
        if np.shape(self.clean) != (4, 2) or not np.all(np.isfinite(self.clean)) or min(s for _, s in self.clean) <= 0:
            raise ValueError(f"FootLevel.clean must be four (mean, spread > 0) pairs in degrees, got {self.clean!r}")

    def shrinkage(self) -> np.ndarray:
        """``(4,)`` the share ``k`` of a stance's departure from the clean mean taken as the suit's, in
        :data:`LIBRARY_STANCE_TILT`'s order."""
        suit = np.array([self.suit_pitch_deg] * 2 + [self.suit_roll_deg] * 2) ** 2
        return suit / (suit + np.asarray(self.clean)[:, 1] ** 2)


def sole_tilt(kin: Kinematics, model_name: str, side: int) -> np.ndarray:
    """``(T, 2)`` pitch and roll (rad) of foot ``side`` (0 left, 1 right) in the world: the angle of the
    foot's forward axis above the horizontal (positive lifts the toe) and of its left axis (positive
    lifts the foot's left edge). A sole flat on the floor has both 0 (the model's rest pose)."""
    body = load_model(model_name).body_id(FOOT_BODIES[side]) - 1
    w, x, y, z = np.moveaxis(kin.body_quat[:, body], -1, 0)
    forward_z, left_z = 2 * (x * z - w * y), 2 * (y * z + w * x)
    return np.arcsin(np.clip(np.stack([forward_z, left_z], axis=-1), -1.0, 1.0))


def stance_windows(kin: Kinematics, fps: float, level: FootLevel = FootLevel()) -> list[list[tuple[int, int]]]:
    """Per side (left, right), the half-open frame ranges ``(start, stop)`` of the middle of each stance:
    runs of at least ``min_stance_s`` where the foot's toe and heel are both within ``contact_height_m``
    of the apparent ground and the sole moves slower than ``max_speed_mps``, cut to their central
    ``middle`` share."""
    ground = apparent_ground(kin.lowest, fps)
    out = []
    for toe, heel in ((0, 2), (1, 3)):
        sole = kin.foot_points[:, [toe, heel]]
        low = sole[..., 2].max(axis=1) - ground <= level.contact_height_m
        centre = sole[..., :2].mean(axis=1)
        speed = horizontal_speed(centre[:, None], fps)[:, 0] if len(centre) > 1 else np.zeros(len(centre))
        windows = []
        for start, stop in contact_windows(low & (speed < level.max_speed_mps)):
            if stop - start < level.min_stance_s * fps:
                continue
            cut = int(round((stop - start) * (1 - level.middle) / 2))
            windows.append((int(start + cut), int(max(stop - cut, start + cut + 1))))
        out.append(windows)
    return out


def level_corrections(motion: Motion, level: FootLevel = FootLevel()) -> np.ndarray:
    """``(T, 2, 2)`` the tilt (rad) the suit most likely added to each sole, per frame, side (left,
    right) and axis (pitch, roll): each stance's shrunk departure from the clean mean, interpolated
    linearly between that foot's stances and held beyond the first and last; zero for a foot with no
    stance."""
    kin = load_model(motion.model).forward_kinematics(motion.qpos)
    k = level.shrinkage().reshape(2, 2).T  # (side, axis)
    mean = np.radians(np.asarray(level.clean)[:, 0]).reshape(2, 2).T
    frames = np.arange(motion.n_frames)
    out = np.zeros((motion.n_frames, 2, 2))
    for side, windows in enumerate(stance_windows(kin, motion.fps, level)):
        if not windows:
            continue
        tilt = sole_tilt(kin, motion.model, side)
        centres = np.array([(a + b - 1) / 2 for a, b in windows])
        departures = np.array([tilt[a:b].mean(axis=0) for a, b in windows]) - mean[side]
        for axis in range(2):
            out[:, side, axis] = np.interp(frames, centres, k[side, axis] * departures[:, axis])
    return out


def level_feet(motion: Motion, level: FootLevel = FootLevel()) -> Motion:
    """``motion`` with each foot's ankle turned back by :func:`level_corrections`: ``foot_y`` by the
    pitch, ``foot_x`` by the roll (to first order the sole's world tilt, the shin's own pitch aside).
    Same frames, rate, model and root; every other hinge untouched."""
    hm = load_model(motion.model)
    corrections = level_corrections(motion, level)
    qpos = motion.qpos.copy()
    for side, prefix in enumerate(("l_", "r_")):
        qpos[:, hm.qpos_index(prefix + "foot_y")] += corrections[:, side, 0]
        qpos[:, hm.qpos_index(prefix + "foot_x")] -= corrections[:, side, 1]
    return motion.with_qpos(qpos)
