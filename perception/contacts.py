"""Foot contacts from vGRF (UnderPressure's contact function Γ), the optimal-thresholds (OT)
baseline, and contact-detection scores (underpressure §3.3, §5.2; SPEC "Perception").

Contact arrays are ``(T, 4)`` bool in CONTACT_CHANNELS order: (left_toe, right_toe, left_heel,
right_heel). Forces are ``(T, 2, 16)`` insole-cell vGRF, left foot then right, in body weights.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from perception.skeleton import FOOT_JOINTS
from reference_motion.footskate import contact_windows
from reference_motion.humanoid.builder import HEEL_CELLS, TOE_CELLS
from reference_motion.humanoid.model import CONTACT_CHANNELS

CONTACT_NAMES = CONTACT_CHANNELS
"""(left_toe, right_toe, left_heel, right_heel): the order of every contact array here."""


@dataclass(frozen=True)
class ContactFunction:
    """Γ: vGRF → contact labels (underpressure §3.3).

    Attributes:
        smooth_s: standard deviation of the Gaussian smoothing of each cell over time (s);
            UnderPressure's 1.667 frames at 100 Hz.
        foot_threshold_bw: a foot whose total vGRF is below this has no contact.
        region_threshold_bw: a heel or toe region is in contact from this rescaled vGRF on.
        min_phase_s: contact phases shorter than this are dropped.
    """

    smooth_s: float = 1.667 / 100
    foot_threshold_bw: float = 0.10
    region_threshold_bw: float = 0.05
    min_phase_s: float = 0.1

    def __call__(self, forces: np.ndarray, fps: float) -> np.ndarray:
        """Contacts ``(T, 4)`` of cell forces ``(T, 2, 16)`` sampled at ``fps``."""
        forces = np.asarray(forces, dtype=float)
        if forces.ndim != 3 or forces.shape[1:] != (2, 16):
            raise ValueError(f"forces must have shape (frames, 2, 16), got {forces.shape}")
        if len(forces) == 0:
            return np.zeros((0, 4), bool)
        sigma = self.smooth_s * fps
        smooth = gaussian_filter1d(forces, sigma=sigma, axis=0, mode="nearest") if sigma > 0 else forces
        foot = smooth.sum(axis=2)                                   # (T, 2)
        toe = smooth[:, :, list(TOE_CELLS)].sum(axis=2)
        heel = smooth[:, :, list(HEEL_CELLS)].sum(axis=2)
        # Rescale heel + toe to the foot total: the midfoot cells count for whichever is loaded.
        scale = np.divide(foot, toe + heel, out=np.zeros_like(foot), where=(toe + heel) > 0)
        regions = np.concatenate([toe * scale, heel * scale], axis=1)   # (T, 4): LT, RT, LH, RH
        feet = np.concatenate([foot, foot], axis=1)
        contacts = (regions >= self.region_threshold_bw) & (feet >= self.foot_threshold_bw)
        return drop_short_phases(contacts, int(round(self.min_phase_s * fps)))


def drop_short_phases(contacts: np.ndarray, min_frames: int) -> np.ndarray:
    """``contacts (T, C)`` with every run of ``True`` shorter than ``min_frames`` set to ``False``."""
    out = np.array(contacts, dtype=bool)
    for c in range(out.shape[1]):
        for start, stop in contact_windows(out[:, c]):
            if stop - start < min_frames:
                out[start:stop, c] = False
    return out


def foot_totals(forces: np.ndarray) -> np.ndarray:
    """Per-foot total vGRF ``(T, 2)`` (left, right) of cell forces ``(T, 2, 16)``."""
    return np.asarray(forces).sum(axis=-1)


def vgrf_rmse_percent(predicted: np.ndarray, true: np.ndarray) -> float:
    """RMSE of the per-foot total vGRF in % body weight (underpressure §5.3); forces ``(T, 2, 16)``."""
    return float(100.0 * np.sqrt(np.mean((foot_totals(predicted) - foot_totals(true)) ** 2)))


def detection_scores(predicted: np.ndarray, true: np.ndarray, channels: tuple[str, ...] = CONTACT_NAMES) -> dict:
    """Precision, recall and F1 per channel and ``overall`` (all labels pooled) of contacts ``(N, C)``."""
    predicted, true = np.asarray(predicted, bool), np.asarray(true, bool)
    if predicted.shape != true.shape:
        raise ValueError(f"predicted contacts {predicted.shape} and true contacts {true.shape} differ in shape")

    def score(p: np.ndarray, t: np.ndarray) -> dict:
        tp, fp, fn = int((p & t).sum()), int((p & ~t).sum()), int((~p & t).sum())
        precision = tp / (tp + fp) if tp + fp else 0.0
        recall = tp / (tp + fn) if tp + fn else 0.0
        f1 = 2 * precision * recall / (precision + recall) if precision + recall else 0.0
        return {"precision": precision, "recall": recall, "f1": f1}

    out = {name: score(predicted[:, i], true[:, i]) for i, name in enumerate(channels)}
    out["overall"] = score(predicted.ravel(), true.ravel())
    return out


def transition_distance(contacts: np.ndarray) -> np.ndarray:
    """Frames ``(T, C)`` from each frame of ``contacts (T, C)`` to the nearest change of its
    channel's label: 1 for the two frames on either side of a change, 2 for the next ones, and so
    on; ``T + 1`` in a channel that never changes."""
    contacts = np.asarray(contacts, bool)
    T = len(contacts)
    out = np.full(contacts.shape, T + 1, dtype=int)
    frames = np.arange(T)
    for c in range(contacts.shape[1]):
        changes = np.flatnonzero(contacts[1:, c] != contacts[:-1, c]) + 1   # label[b - 1] != label[b]
        if changes.size:
            after = np.abs(frames[:, None] - changes[None, :] + 0.5).min(axis=1)
            out[:, c] = (after + 0.5).astype(int)
    return out


def f1_with_tolerance(predicted: np.ndarray, true: np.ndarray, distance_s: np.ndarray, tolerance_s: float) -> float:
    """Overall F1 of contacts ``(N, C)`` where a wrong label counts as right when it lies within
    ``tolerance_s`` of a change of the true label (``distance_s (N, C)``: :func:`transition_distance`
    over the frame rate): underpressure Fig. 4's F1 against temporal tolerance."""
    predicted, true = np.asarray(predicted, bool), np.asarray(true, bool)
    forgiven = (predicted != true) & (distance_s <= tolerance_s + 1e-9)
    return detection_scores(np.where(forgiven, true, predicted), true, channels=())["overall"]["f1"]


TOLERANCES_S = (0.0, 0.02, 0.05, 0.1, 0.2)
"""Temporal tolerances (s) of :func:`tolerance_curve` (underpressure Fig. 4)."""


def tolerance_curve(predicted: list[np.ndarray], true: list[np.ndarray], fps: list[float],
                    tolerances_s: tuple[float, ...] = TOLERANCES_S) -> dict[str, float]:
    """``{tolerance: overall F1}`` (:func:`f1_with_tolerance`) of sequences of contacts ``(T_i, C)``,
    each with its frame rate; distances to a label change are taken within each sequence."""
    distance_s = np.concatenate([transition_distance(t) / f for t, f in zip(true, fps)])
    p, t = np.concatenate(predicted), np.concatenate(true)
    return {f"{tol:g}": f1_with_tolerance(p, t, distance_s, tol) for tol in tolerances_s}


def foot_height_speed(positions: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """Height (m) and speed (m/s) ``(T, 4)`` of the joints above the four contact regions
    (feet balls for toes, ankles for heels) of joint positions ``(T, 23, 3)``."""
    feet = np.asarray(positions)[:, list(FOOT_JOINTS)]
    speed = np.linalg.norm(np.gradient(feet, axis=0), axis=-1) * fps if len(feet) > 1 else np.zeros(feet.shape[:2])
    return feet[..., 2], speed


@dataclass(frozen=True)
class OptimalThresholds:
    """The OT baseline (underpressure §5.2): contact where the foot joint is lower than
    ``height_m`` and slower than ``speed_mps``; :meth:`fit` picks both for the best F1."""

    height_m: float = 0.1
    speed_mps: float = 0.5

    def predict(self, positions: np.ndarray, fps: float) -> np.ndarray:
        """Contacts ``(T, 4)`` of joint positions ``(T, 23, 3)``."""
        height, speed = foot_height_speed(positions, fps)
        return (height < self.height_m) & (speed < self.speed_mps)

    @classmethod
    def fit(cls, sequences: list[tuple[np.ndarray, np.ndarray, float]], rounds: int = 4,
            grid: int = 11) -> "OptimalThresholds":
        """Recursive grid search over (height, speed) for the best overall F1 on ``sequences`` of
        ``(positions (T, 23, 3), true contacts (T, 4), fps)``: each round searches a ``grid`` ×
        ``grid`` lattice around the previous best with a quarter of its spacing."""
        if not sequences:
            raise ValueError("OptimalThresholds.fit needs at least one sequence")
        hs, ss, ts = [], [], []
        for positions, contacts, fps in sequences:
            h, s = foot_height_speed(positions, fps)
            hs.append(h.ravel()), ss.append(s.ravel()), ts.append(np.asarray(contacts, bool).ravel())
        height, speed, true = np.concatenate(hs), np.concatenate(ss), np.concatenate(ts)

        def f1(h: float, v: float) -> float:
            p = (height < h) & (speed < v)
            tp = np.sum(p & true)
            return 2 * tp / (p.sum() + true.sum()) if p.sum() + true.sum() else 0.0

        h_lo, h_hi, v_lo, v_hi = 0.0, 0.4, 0.0, 4.0
        best = (0.0, h_hi / 2, v_hi / 2)
        for _ in range(rounds):
            for h in np.linspace(h_lo, h_hi, grid):
                for v in np.linspace(v_lo, v_hi, grid):
                    score = f1(h, v)
                    if score > best[0]:
                        best = (score, h, v)
            dh, dv = (h_hi - h_lo) / (grid - 1), (v_hi - v_lo) / (grid - 1)
            h_lo, h_hi = max(0.0, best[1] - 2 * dh), best[1] + 2 * dh
            v_lo, v_hi = max(0.0, best[2] - 2 * dv), best[2] + 2 * dv
        return cls(height_m=float(best[1]), speed_mps=float(best[2]))
