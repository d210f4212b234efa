"""Training the ContactTransformer on a physics dataset filmed by synthetic cameras
(contactvision §5.2): BCE on random 128-frame subsequences, Adam, early stopping on validation F1.

Each training window is cut from a ``train`` episode and filmed afresh from a random training view
(:func:`~perception.keypoint_data.draw_train_view`), so the network sees each motion from many
cameras (contactvision §6.2). Validation films the ``val`` episodes from ``val_views`` fixed
training-rig views; :func:`~perception.training.fit` runs the seeded, resumable loop.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch
from torch import nn

from perception.contact_transformer import ContactTransformer, keypoint_features
from perception.keypoint_data import KeypointSequence, ViewConfig, draw_train_view, film, load_keypoint_split
from perception.keypoint_evaluation import evaluate_keypoint_contacts, film_split
from perception.training import fit
from perception.weights import load_network

SAMPLINGS = ("random", "sliding")


@dataclass(frozen=True)
class KeypointTrainConfig:
    """Training settings (ContactVision's where it gives them).

    Attributes:
        keypoints: ``lower`` (13 keypoints) or ``full`` (25; ablation).
        positional: ``learnable`` or ``sinusoidal`` (ablation).
        sampling: ``random`` — a window starts at a random frame, running past the episode's end
            is zero-padded (contactvision eq. 2) — or ``sliding`` (ablation): windows drawn from
            every stride-1 window lying inside an episode.
        window: L, frames per window.
        batch_size: windows per step. 32 rather than ContactVision's 8: on 2 CPU cores a step
            of 32 takes 2.5× as long as one of 8 for 4× the windows.
        windows_per_epoch: windows drawn per epoch.
        lr: Adam learning rate (ContactVision: 4e-4).
        max_epochs, patience: early stopping after ``patience`` epochs without a better
            validation F1 (ContactVision: 10).
        lr_patience: halve the learning rate after this many epochs without improvement.
        val_views: training-rig views the ``val`` episodes are filmed from.
        views: the camera distributions (:class:`~perception.keypoint_data.ViewConfig`).
        init_from: a shipped ContactTransformer (directory or ``model.pt``) to start from instead
            of random weights (fine-tuning, e.g. on a larger dataset); ``None``: from scratch.
        seed: seeds windows, views, noise, initialisation and dropout.
    """

    keypoints: str = "lower"
    positional: str = "learnable"
    sampling: str = "random"
    window: int = 128
    batch_size: int = 32
    windows_per_epoch: int = 2048
    lr: float = 4e-4
    max_epochs: int = 40
    patience: int = 10
    lr_patience: int = 5
    val_views: int = 4
    views: ViewConfig = field(default_factory=ViewConfig)
    init_from: str | None = None
    seed: int = 0


class KeypointTask:
    """:class:`~perception.training.TrainingTask` of the ContactTransformer."""

    def __init__(self, dataset: Path, config: KeypointTrainConfig):
        if config.sampling not in SAMPLINGS:
            raise ValueError(f"unknown sampling {config.sampling!r}; expected one of {', '.join(SAMPLINGS)}")
        self.dataset, self.config = Path(dataset), config
        self.train = load_keypoint_split(dataset, "train")
        val = load_keypoint_split(dataset, "val")
        if not self.train or not val:
            raise ValueError(f"{dataset}: the train and val splits need episodes")
        rng = np.random.default_rng([config.seed, 1])
        views = [draw_train_view(rng, config.views) for _ in range(config.val_views)]
        self.val = film_split(val, views, config.keypoints, seed=config.seed, config=config.views)
        self.lengths = np.array([len(s) for s in self.train])
        L = config.window
        if config.sampling == "sliding":
            self.slides = np.array([(i, s) for i, n in enumerate(self.lengths) for s in range(max(1, n - L + 1))])

    def network(self) -> nn.Module:
        c = self.config
        net = ContactTransformer(keypoints=c.keypoints, positional=c.positional, window=c.window)
        if c.init_from is not None:
            start = load_network(Path(c.init_from), "keypoints")
            if start.config != net.config:
                raise ValueError(f"{c.init_from}: a ContactTransformer with {start.config}, not {net.config}; "
                                 "start from a network of the same shape")
            net.load_state_dict(start.state_dict())
        return net

    def _starts(self, rng: np.random.Generator) -> list[tuple[int, int]]:
        c = self.config
        if c.sampling == "sliding":
            return [tuple(w) for w in self.slides[rng.choice(len(self.slides), c.batch_size, replace=False)]]
        picks = rng.choice(len(self.train), c.batch_size, p=self.lengths / self.lengths.sum())
        return [(int(i), int(rng.integers(max(1, self.lengths[i] - c.window // 2)))) for i in picks]

    def _film(self, points: np.ndarray, fps: float, rng: np.random.Generator, tries: int = 20) -> np.ndarray:
        """Features of ``points`` filmed from a random training view that shows a whole leg at
        least once (a close, low camera can crop the legs out of a whole window)."""
        c = self.config
        for _ in range(tries):
            try:
                return keypoint_features(film(points, draw_train_view(rng, c.views), rng, fps, c.keypoints,
                                              config=c.views))
            except ValueError:
                continue
        raise ValueError(f"no training view out of {tries} showed a whole leg; check ViewConfig")

    def batch(self, rng: np.random.Generator) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Features ``(B, L, 3K)``, labels ``(B, L, 4)`` and padding ``(B, L)`` of fresh windows."""
        c = self.config
        feats, labels, pads = [], [], []
        for i, s in self._starts(rng):
            seq: KeypointSequence = self.train[i]
            points = seq.points[s:s + c.window]
            f = self._film(points, seq.fps, rng)
            n = len(f)
            feats.append(np.pad(f, ((0, c.window - n), (0, 0))))
            labels.append(np.pad(seq.labels[s:s + c.window], ((0, c.window - n), (0, 0))))
            pads.append(np.arange(c.window) >= n)
        return (torch.from_numpy(np.stack(feats)), torch.from_numpy(np.stack(labels)).float(),
                torch.from_numpy(np.stack(pads)))

    def training_loss(self, net: nn.Module, rng: np.random.Generator, generator: torch.Generator) -> torch.Tensor:
        x, y, pad = self.batch(rng)
        loss = nn.functional.binary_cross_entropy_with_logits(net(x, pad), y, reduction="none")
        keep = (~pad).float()[..., None]
        return (loss * keep).sum() / (4.0 * keep.sum())

    def validation_score(self, net: nn.Module) -> float:
        """1 − F1 (all channels pooled) on the filmed ``val`` episodes."""
        return 1.0 - evaluate_keypoint_contacts(net, self.val)["scores"]["overall"]["f1"]

    def sidecar(self, net: nn.Module) -> dict:
        return {"kind": "keypoints", "joints": list(net.input_names), "fps": net.fps, "network": net.config,
                "dataset": str(self.dataset)}


def train_keypoints(dataset: Path, run_dir: Path, config: KeypointTrainConfig = KeypointTrainConfig(),
                    progress: bool = True) -> dict:
    """Train (or resume training) a ContactTransformer in ``run_dir``; the best epoch's sidecar."""
    return fit(KeypointTask(dataset, config), run_dir, config, progress)
