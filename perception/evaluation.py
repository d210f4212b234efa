"""Contact detection and vGRF accuracy on a dataset split (underpressure §5.2–5.4).

Ground truth is Γ of the simulator's cell forces. Compared: VGRFNet followed by Γ, the OT
baseline (thresholds grid-searched on the ``train`` split), and the 3-layer MLP.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from torch import nn

from perception.contacts import (ContactFunction, OptimalThresholds, detection_scores, tolerance_curve,
                                 vgrf_rmse_percent)
from perception.dataset import Sequence
from perception.vgrf import estimate


@dataclass
class ContactModels:
    """What is compared: any of the three may be ``None`` (left out)."""

    vgrf: nn.Module | None = None
    ot: OptimalThresholds | None = None
    mlp: nn.Module | None = None

    def predict(self, name: str, positions: np.ndarray, fps: float, gamma: ContactFunction,
                forces: np.ndarray | None = None) -> np.ndarray:
        """Contacts ``(T, 4)`` (CONTACT_CHANNELS order) of model ``name`` on ``positions (T, 23, 3)``;
        for ``vgrf``, ``forces`` are VGRFNet's estimate when already computed."""
        if name == "vgrf":
            return gamma(estimate(self.vgrf, positions) if forces is None else forces, fps)
        if name == "ot":
            return self.ot.predict(positions, fps)
        return estimate(self.mlp, positions) > 0.5

    @property
    def names(self) -> list[str]:
        return [n for n in ("vgrf", "ot", "mlp") if getattr(self, n) is not None]


def fit_ot(train: list[Sequence], gamma: ContactFunction = ContactFunction()) -> OptimalThresholds:
    """The OT baseline's thresholds, grid-searched for the best F1 on ``train``."""
    return OptimalThresholds.fit([(s.positions, gamma(s.forces, s.fps), s.fps) for s in train])


def evaluate_contacts(sequences: list[Sequence], models: ContactModels,
                      gamma: ContactFunction = ContactFunction(),
                      perturb=None) -> dict:
    """Scores of each model over ``sequences``: ``{name: {channel: {precision, recall, f1}}}``,
    ``f1_by_tolerance_s`` (``{name: {tolerance: F1}}`` over :data:`~perception.contacts.TOLERANCES_S`, the F1 when
    errors that close to a true contact change are forgiven), plus ``vgrf_rmse_percent_bw`` for
    VGRFNet. ``perturb(positions) -> positions`` is applied to the inputs first (robustness
    studies); labels always come from the unperturbed forces."""
    if not sequences:
        raise ValueError("no sequences to evaluate")
    labels = [gamma(s.forces, s.fps) for s in sequences]
    truth = np.concatenate(labels)
    out: dict = {"frames": int(len(truth)), "sequences": len(sequences), "f1_by_tolerance_s": {}}
    inputs = [perturb(s.positions) if perturb else s.positions for s in sequences]
    estimates = [estimate(models.vgrf, x) for x in inputs] if models.vgrf is not None else [None] * len(inputs)
    for name in models.names:
        pred = [models.predict(name, x, s.fps, gamma, f) for x, s, f in zip(inputs, sequences, estimates)]
        out[name] = detection_scores(np.concatenate(pred), truth)
        out["f1_by_tolerance_s"][name] = tolerance_curve(pred, labels, [s.fps for s in sequences])
    if models.vgrf is not None:
        out["vgrf_rmse_percent_bw"] = vgrf_rmse_percent(np.concatenate(estimates),
                                                        np.concatenate([s.forces for s in sequences]))
    return out
