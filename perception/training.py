"""Training the contact networks on a physics-labelled dataset: seeded, resumable, early-stopped.

:func:`fit` is the loop every network here is trained with (a :class:`TrainingTask` supplies the
network, its batches and its validation score); this module's task is the force-side one:

``kind="vgrf"`` trains :class:`~perception.vgrf.VGRFNet` on the cell vGRF with MSLE
(underpressure eq. 1); ``kind="mlp"`` trains the :class:`~perception.vgrf.ContactMLP` baseline on
Γ's contact labels with binary cross-entropy. Each epoch draws fresh random windows from the
``train`` split and augments them (:func:`~perception.vgrf.augment`); the ``val`` loss decides
early stopping, and the best epoch's weights are what gets shipped. A checkpoint is written
after every epoch, so an interrupted run resumes losing at most one epoch.
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import MISSING, asdict, dataclass, fields
from pathlib import Path
from typing import Protocol

import numpy as np
import torch
from torch import nn
from tqdm import tqdm

from perception.contacts import ContactFunction
from perception.dataset import Sequence, load_split
from perception.skeleton import JOINTS
from perception.vgrf import augment, count_parameters, msle
from perception.weights import KINDS, SIDECAR_FILE

FORCE_KINDS = {kind: KINDS[kind] for kind in ("vgrf", "mlp")}
"""The networks :class:`ForceTask` trains (from joint positions)."""


@dataclass(frozen=True)
class TrainConfig:
    """Training settings.

    Attributes:
        kind: ``vgrf`` or ``mlp``.
        window: frames per training window (48 = 0.8 s at 60 Hz; one output sees 25 frames).
        batch_size: windows per step (UnderPressure: 64).
        windows_per_epoch: windows drawn per epoch.
        lr: initial Adam learning rate. UnderPressure used 3e-5 for ~2,500 epochs (10 GPU-days);
            1e-3, halved on plateaus, converges in minutes on 2 CPU cores.
        max_epochs: upper bound on epochs.
        lr_patience: halve the learning rate after this many epochs without a better validation loss.
        patience: stop after this many epochs without a better validation loss.
        augment: apply UnderPressure's augmentations to training windows.
        seed: seeds window sampling, augmentation, initialisation and dropout.
    """

    kind: str = "vgrf"
    window: int = 48
    batch_size: int = 64
    windows_per_epoch: int = 1024
    lr: float = 1e-3
    max_epochs: int = 200
    lr_patience: int = 6
    patience: int = 20
    augment: bool = True
    seed: int = 0


class Tensors:
    """A split as tensors: positions, forces and Γ contacts per sequence."""

    def __init__(self, sequences: list[Sequence], gamma: ContactFunction):
        self.positions = [torch.from_numpy(s.positions) for s in sequences]
        self.forces = [torch.from_numpy(s.forces) for s in sequences]
        self.contacts = [torch.from_numpy(gamma(s.forces, s.fps)) for s in sequences]
        self.lengths = np.array([len(s.positions) for s in sequences])

    def windows(self, n: int, length: int, rng: np.random.Generator) -> tuple[torch.Tensor, ...]:
        """``n`` random windows of ``length`` frames (sequences drawn in proportion to their length)."""
        usable = np.flatnonzero(self.lengths >= length)
        if not len(usable):
            raise ValueError(f"no training sequence has {length} frames; lower TrainConfig.window")
        weights = self.lengths[usable] - length + 1
        picks = rng.choice(usable, size=n, p=weights / weights.sum())
        starts = [int(rng.integers(self.lengths[i] - length + 1)) for i in picks]
        return tuple(torch.stack([arr[i][s:s + length] for i, s in zip(picks, starts)])
                     for arr in (self.positions, self.forces, self.contacts))


def loss_fn(kind: str, net: nn.Module, positions: torch.Tensor, forces: torch.Tensor,
            contacts: torch.Tensor) -> torch.Tensor:
    out = net(positions)
    if kind == "vgrf":
        return msle(out, forces)
    return nn.functional.binary_cross_entropy_with_logits(out, contacts.float())


class TrainingTask(Protocol):
    """What :func:`fit` trains: a network, a loss on one fresh training batch, and a validation
    score (lower is better) that picks the best epoch and stops training."""

    def network(self) -> nn.Module: ...

    def training_loss(self, net: nn.Module, rng: np.random.Generator, generator: torch.Generator) -> torch.Tensor: ...

    def validation_score(self, net: nn.Module) -> float: ...

    def sidecar(self, net: nn.Module) -> dict:
        """Entries of the shipped sidecar: ``kind``, ``joints`` (input point names), ``fps``,
        ``network`` (constructor arguments), ``dataset``."""


class ForceTask:
    """VGRFNet (MSLE on cell vGRF) or the contact MLP (BCE on Γ labels) on a physics dataset;
    validation by the loss over whole ``val`` sequences."""

    def __init__(self, dataset: Path, config: TrainConfig):
        if config.kind not in FORCE_KINDS:
            raise ValueError(f"unknown network kind {config.kind!r}; expected one of {', '.join(FORCE_KINDS)}")
        self.dataset, self.config = dataset, config
        gamma = ContactFunction()
        self.train_data = Tensors(load_split(dataset, "train"), gamma)
        self.val_data = Tensors(load_split(dataset, "val"), gamma)
        for name, data in (("train", self.train_data), ("val", self.val_data)):
            if not data.lengths.sum():
                raise ValueError(f"{dataset}/{name}: no frames (every episode was shorter than the dataset's minimum)")

    def network(self) -> nn.Module:
        return FORCE_KINDS[self.config.kind]()

    def training_loss(self, net: nn.Module, rng: np.random.Generator, generator: torch.Generator) -> torch.Tensor:
        p, f, c = self.train_data.windows(self.config.batch_size, self.config.window, rng)
        if self.config.augment:
            p, f, c = augment(p, f, c, generator)
        return loss_fn(self.config.kind, net, p, f, c)

    @torch.no_grad()
    def validation_score(self, net: nn.Module) -> float:
        """Frame-weighted mean loss over whole validation sequences."""
        total = 0.0
        for p, f, c in zip(self.val_data.positions, self.val_data.forces, self.val_data.contacts):
            total += float(loss_fn(self.config.kind, net, p[None], f[None], c[None])) * len(p)
        return total / float(self.val_data.lengths.sum())

    def sidecar(self, net: nn.Module) -> dict:
        return {"kind": self.config.kind, "joints": list(JOINTS), "fps": net.fps, "network": {"fps": net.fps},
                "dataset": str(self.dataset)}


def fit(task: TrainingTask, run_dir: Path, config, progress: bool = True) -> dict:
    """Train ``task`` (or resume its training) in ``run_dir`` with Adam, the learning rate halved
    after ``config.lr_patience`` epochs without a better validation score and training stopped
    after ``config.patience``; ``config`` is a dataclass with ``lr``, ``max_epochs``,
    ``lr_patience``, ``patience``, ``batch_size``, ``windows_per_epoch`` and ``seed``, all
    recorded. Every epoch ends with an atomic checkpoint; returns the sidecar of the best epoch."""
    run_dir = Path(run_dir)
    run_dir.mkdir(parents=True, exist_ok=True)
    settings = run_dir / "config.json"
    extendable = ("max_epochs", "patience", "lr_patience")  # a resumed run may be given more epochs or patience
    if settings.exists():
        # a setting added after the run began is read as its default, so older runs still resume
        defaults = json.loads(json.dumps({f.name: f.default for f in fields(config) if f.default is not MISSING}))
        recorded = {**defaults, **json.loads(settings.read_text())}
        stored = {k: v for k, v in recorded.items() if k not in extendable}
        if stored != {k: v for k, v in json.loads(json.dumps(asdict(config))).items() if k not in extendable}:
            raise ValueError(f"{settings}: {run_dir} holds a run with other settings; use a new run directory")
    settings.write_text(json.dumps(asdict(config), indent=1))
    torch.manual_seed(config.seed)
    net = task.network()
    optimiser = torch.optim.Adam(net.parameters(), lr=config.lr)
    schedule = torch.optim.lr_scheduler.ReduceLROnPlateau(optimiser, factor=0.5, patience=config.lr_patience)
    state = {"epoch": 0, "best": float("inf"), "best_epoch": 0, "wall_s": 0.0, "history": []}
    rng = np.random.default_rng(config.seed)
    generator = torch.Generator().manual_seed(config.seed)
    checkpoint = run_dir / "last.pt"
    if checkpoint.exists():
        saved = torch.load(checkpoint, weights_only=False)
        net.load_state_dict(saved["net"])
        optimiser.load_state_dict(saved["optimiser"])
        schedule.load_state_dict(saved["schedule"])
        state, rng = saved["state"], saved["rng"]
        generator.set_state(saved["generator"])
        torch.set_rng_state(saved["torch_rng"])
        print(f"resuming {run_dir} after epoch {state['epoch']}", flush=True)
    start = time.time() - state["wall_s"]
    name = task.sidecar(net)["kind"]
    bar = tqdm(total=config.max_epochs, initial=state["epoch"], desc=f"training {name}", unit="epoch",
               disable=not progress)
    while state["epoch"] < config.max_epochs and state["epoch"] - state["best_epoch"] < config.patience:
        net.train()
        losses = []
        for _ in range(config.windows_per_epoch // config.batch_size):
            loss = task.training_loss(net, rng, generator)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            losses.append(loss.item())
        state["epoch"] += 1
        net.eval()
        val = task.validation_score(net)
        schedule.step(val)
        state["history"].append({"epoch": state["epoch"], "train_loss": float(np.mean(losses)), "val": val,
                                 "lr": optimiser.param_groups[0]["lr"]})
        if val < state["best"]:
            state["best"], state["best_epoch"] = val, state["epoch"]
            torch.save(net.state_dict(), run_dir / "best.pt")
        state["wall_s"] = time.time() - start
        tmp = checkpoint.with_suffix(".tmp")  # written whole, then renamed: a kill never leaves half a file
        torch.save({"net": net.state_dict(), "optimiser": optimiser.state_dict(), "schedule": schedule.state_dict(),
                    "state": state, "rng": rng,
                    "generator": generator.get_state(), "torch_rng": torch.get_rng_state()}, tmp)
        tmp.replace(checkpoint)
        bar.update(1)
        bar.set_postfix(train=f"{np.mean(losses):.4f}", val=f"{val:.4f}", best=state["best_epoch"])
    bar.close()
    sidecar = {**task.sidecar(net), "parameters": count_parameters(net), "config": asdict(config),
               "epochs": state["epoch"], "best_epoch": state["best_epoch"], "best_val": state["best"],
               "wall_s": state["wall_s"], "command": "python -m perception " + " ".join(sys.argv[1:]),
               "history": state["history"]}
    (run_dir / SIDECAR_FILE).write_text(json.dumps(sidecar, indent=1))
    return sidecar


def train(dataset: Path, run_dir: Path, config: TrainConfig = TrainConfig(), progress: bool = True) -> dict:
    """Train (or resume training) a VGRFNet or contact MLP in ``run_dir``; returns the sidecar of the best epoch."""
    return fit(ForceTask(Path(dataset), config), run_dir, config, progress)
