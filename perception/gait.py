"""From foot contacts to the toe joint's reference angle and to clinical gait parameters
(contactvision Algorithm 1, Table 2 and §6.5.2).

Contact arrays are ``(T, 4)`` bool in CONTACT_CHANNELS order: (left_toe, right_toe, left_heel,
right_heel) — the (LT, RT, LH, RH) of ContactVision's Table 2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from reference_motion.humanoid.model import FOOT_CHANNELS

TOE_PEAK_RAD = np.deg2rad(42.0)
"""Peak toe-joint flexion at push-off (contactvision §6.4, after Nawoczenski et al.)."""
TOE_RISE_FRAMES = 5
"""Frames over which the target rises from heel-off to the peak."""
TOE_RETURN_FRAMES = 2
"""Frames over which it returns to 0 after toe-off."""

PHASES = ("stand", "heel_strike", "loading_response", "mid_stance", "terminal_stance", "pre_swing",
          "toe_off_mid_swing", "terminal_swing", "undefined")
"""Gait phases of contactvision Table 2 (defined with respect to the right foot), by code."""

_TABLE2 = {(1, 1, 1, 1): "stand", (1, 0, 0, 1): "heel_strike", (1, 1, 0, 1): "loading_response",
           (0, 1, 0, 1): "mid_stance", (0, 1, 1, 0): "terminal_stance", (1, 1, 1, 0): "pre_swing",
           (1, 0, 1, 0): "toe_off_mid_swing", (1, 0, 0, 0): "terminal_swing"}
STANCE = ("heel_strike", "loading_response", "mid_stance", "terminal_stance", "pre_swing")
SWING = ("toe_off_mid_swing", "terminal_swing")
DOUBLE_SUPPORT = ("heel_strike", "pre_swing")
SINGLE_SUPPORT = ("loading_response", "mid_stance", "terminal_stance", "toe_off_mid_swing", "terminal_swing")


def _check(contacts: np.ndarray) -> np.ndarray:
    arr = np.asarray(contacts)
    if arr.ndim != 2 or arr.shape[1] != 4:
        raise ValueError(f"contacts must have shape (frames, 4) in (left_toe, right_toe, left_heel, right_heel) "
                         f"order, got {arr.shape}")
    return arr.astype(bool)


def toe_reference_angles(contacts: np.ndarray) -> np.ndarray:
    """ToeRefEstimator (contactvision Algorithm 1): target toe-joint angles ``(T, 2)`` (rad; left,
    right) from contacts ``(T, 4)``.

    For each heel-off (the heel leaves the ground while the toe stays) the angle rises linearly
    from 0 by 42°/5 per frame until 42° or until toe-off (a heel-off→toe-off interval shorter than
    5 frames gives a proportionally lower peak), holds until toe-off, then returns to 0 over 2
    frames; 0 elsewhere. A toe-off missing at the clip's end holds the angle to the last frame.
    """
    contacts = _check(contacts)
    T = len(contacts)
    out = np.zeros((T, 2))
    for foot, (toe_column, heel_column) in enumerate(FOOT_CHANNELS):
        toe, heel = contacts[:, toe_column], contacts[:, heel_column]
        heel_offs = [t for t in range(1, T) if heel[t - 1] and not heel[t] and toe[t]]
        for start in heel_offs:
            stop = start
            while stop < T and toe[stop]:
                stop += 1                       # first frame with the toe off (T: never)
            t = np.arange(start, stop + 1 if stop < T else T)
            rise = TOE_PEAK_RAD * np.minimum(t - start, TOE_RISE_FRAMES) / TOE_RISE_FRAMES
            out[t, foot] = np.maximum(out[t, foot], rise)
            if stop < T:
                peak = out[stop, foot]
                for k in range(1, TOE_RETURN_FRAMES + 1):
                    if stop + k < T:
                        out[stop + k, foot] = max(out[stop + k, foot], peak * (1 - k / TOE_RETURN_FRAMES))
    return out


def gait_phases(contacts: np.ndarray) -> np.ndarray:
    """Phase code per frame ``(T,)`` (index into :data:`PHASES`) by contactvision Table 2."""
    contacts = _check(contacts)
    codes = {pattern: PHASES.index(name) for pattern, name in _TABLE2.items()}
    undefined = PHASES.index("undefined")
    return np.array([codes.get(tuple(int(v) for v in row), undefined) for row in contacts], dtype=int)


@dataclass(frozen=True)
class GaitParameters:
    """Ratios over the valid frames (every phase but stand and undefined), contactvision §6.5.2."""

    stance: float
    swing: float
    single_support: float
    double_support: float
    valid_frames: int

    def as_dict(self) -> dict:
        return {"stance": self.stance, "swing": self.swing, "single_support": self.single_support,
                "double_support": self.double_support, "valid_frames": self.valid_frames}


def gait_parameters(phases: np.ndarray) -> GaitParameters:
    """Stance, swing, single- and double-support ratios of phase codes ``(T,)``; NaN ratios when
    no frame is valid."""
    names = np.array(PHASES)[np.asarray(phases, dtype=int)]
    count = {group: int(np.isin(names, group).sum()) for group in (STANCE, SWING, SINGLE_SUPPORT, DOUBLE_SUPPORT)}
    valid = count[STANCE] + count[SWING]
    ratio = (lambda n: n / valid) if valid else (lambda n: float("nan"))
    return GaitParameters(ratio(count[STANCE]), ratio(count[SWING]), ratio(count[SINGLE_SUPPORT]),
                          ratio(count[DOUBLE_SUPPORT]), valid)


def gait_cycles(phases: np.ndarray) -> list[tuple[int, int]]:
    """``(start, stop)`` frame ranges of the complete gait cycles: from one onset of heel strike
    to the next."""
    hs = PHASES.index("heel_strike")
    phases = np.asarray(phases, dtype=int)
    onsets = [t for t in range(len(phases)) if phases[t] == hs and (t == 0 or phases[t - 1] != hs)]
    return list(zip(onsets[:-1], onsets[1:]))


def gait_parameters_per_cycle(phases: np.ndarray) -> list[GaitParameters]:
    """:func:`gait_parameters` of each complete cycle of ``phases`` (:func:`gait_cycles`)."""
    return [gait_parameters(phases[a:b]) for a, b in gait_cycles(phases)]


def gait_report(contacts: np.ndarray, fps: float) -> dict:
    """Everything the ``gait`` command reports about contacts ``(T, 4)`` at ``fps``: per-frame
    phase names and toe reference angles (degrees; left, right), the parameters over the whole
    sequence and per complete cycle (with start and stop times in s)."""
    contacts = _check(contacts)
    phases = gait_phases(contacts)
    cycles = [{"start_s": a / fps, "stop_s": b / fps, **gait_parameters(phases[a:b]).as_dict()}
              for a, b in gait_cycles(phases)]
    return {"fps": fps, "frames": len(contacts), "phases": [PHASES[p] for p in phases],
            "toe_reference_deg": np.degrees(toe_reference_angles(contacts)).round(2).tolist(),
            "parameters": gait_parameters(phases).as_dict(), "cycles": cycles}
