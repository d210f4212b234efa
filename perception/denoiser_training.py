"""Training the :class:`~perception.imu_denoiser.IMUDenoiser` on clean takes it corrupts itself.

Every training batch cuts random windows out of the training takes (mirrored too, played at each of
``speeds``, with ``postures`` also carried in random postures, and with ``stances`` also walked with
the feet further apart), corrupts each
with every IMU artefact kind (:func:`reference_motion.artefacts.corrupt`) at a strength drawn from
``DenoiserTrainConfig.strength``, a fresh seed each time, or leaves it clean
(``clean_fraction``), and regresses what :func:`~perception.imu_denoiser.denoise` must add back:
the clean hinge angles and pelvis height minus the corrupted ones (mean squared error; rad and m
weigh alike, their errors being of one size: a few degrees, a few centimetres), plus, with
``DenoiserTrainConfig.sole_weight``, the squared error of where the corrected hinge angles put the
soles (:func:`correction_loss`). The validation score is that loss over the whole validation
takes, each clean and corrupted at strengths 0.5 and 1 with fixed seeds: a denoiser must fix
corrupted takes and leave clean ones alone. The loop,
checkpoints, early stopping and shipping are :func:`perception.training.fit`'s.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np
import torch
from torch import nn

from perception.imu_denoiser import IMUDenoiser, motion_features
from perception.kinematics import TorchKinematics, torch_kinematics
from perception.training import fit
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.atomic import write_json
from reference_motion.humanoid.model import load_model
from reference_motion.library import (STANCE_EXTRA_M, augmented, check_stance_extra, expand_clips, load_motion,
                                      posture_copies, stance_copies)
from reference_motion.motion import Motion

DENOISER_TRAIN_CLIPS = ("library:data/library/train", "deepmimic:walk", "deepmimic:run", "deepmimic:walker/turn_left0",
                        "deepmimic:walker/turn_right0")
"""Default training clips: the library's train split and the DeepMimic clips the generalist trains on."""
DENOISER_VAL_CLIPS = ("library:data/library/val",)
"""Default validation clips (early stopping, the shipped epoch): the library's val split."""
VALIDATION_STRENGTHS = (0.0, 0.5, 1.0)
"""Artefact strengths each validation take is scored at (0 = clean)."""
POSTURE_STREAM = 3
"""Stream of ``DenoiserTrainConfig.seed``'s random numbers that draws the posture copies."""
STANCE_STREAM = 4
"""Stream of ``DenoiserTrainConfig.seed``'s random numbers that draws the stance copies' widths."""
VALIDATION_SEED = 77_000
"""Artefact seed of the first validation take (take i, strength j: seed + 10·i + j)."""


@dataclass(frozen=True)
class DenoiserTrainConfig:
    """Training settings.

    Attributes:
        window: longest training window (frames; 240 = 4 s at 60 Hz); each batch draws its length
            uniformly from ``min_window``…``window``, so the take-level branch learns from short
            and long inputs alike.
        min_window: shortest training window (frames; 60 = 1 s, the library's shortest take).
        batch_size: windows per step.
        windows_per_epoch: windows drawn per epoch.
        strength: ``(low, high)`` of the uniform artefact strength of a corrupted window (0–1.5:
            from mild to beyond the poor real take of strength 1).
        clean_fraction: share of windows left clean (0.2), so clean takes come out nearly as given.
        hidden: channels of the network (128: 0.3 M weights, 3 ms per second of motion on one core).
        dilations: dilation of each residual convolution (kernel 3); the default (1…32) sees ±63
            frames (±1 s at 60 Hz) around a frame, about half the hinge drift's 2 s timescale
            (:class:`reference_motion.artefacts.ArtefactScales`); (1…128) sees ±4.25 s, and
            needs ``window`` long enough to use it.
        sole_weight: weight of a second loss term, the mean squared error (m²) of the four sole
            points relative to the pelvis, in the pelvis frame, after the correction (forward
            kinematics of the hinge angles alone, :mod:`perception.kinematics`): errors that move
            the feet, which the policy stands on, count more than those of an elbow. 0: the hinge
            angles and pelvis height alone, each equally. The validation score carries the same term.
        height_weight: weight of a third loss term, the mean squared error (m²) of the pelvis
            height alone. In the first term the height is one channel among 44 (beside 43
            hinges), so a 2.5 cm error weighs as little as a 1.4° error on one hinge, yet on validation's IMU
            draws the pelvis height left by ``imu_denoiser_soles_quint_mirror`` (2.3 cm RMS) costs
            as much ELR as all hip angles' residual errors (README, round 9). 0: no third term.
            The validation score carries it too. Measured: one member at 8 leads the same seed
            without by +0.007 ± 0.009 on validation's IMU draws, five behind takes set on the
            floor (``--ground``) lose 0.020 to five without (README, round 10).
        lr: initial Adam learning rate, halved after ``lr_patience`` epochs without a better
            validation score.
        max_epochs: upper bound on epochs.
        lr_patience: see ``lr``.
        patience: stop after this many epochs without a better validation score.
        mirror: also train on every take performed by the other side of the body.
        speeds: every training take (and its mirror image) is played at each of these speeds
            (:func:`reference_motion.library.augmented`; 1.0 = as recorded, so include it to keep
            the takes as they are), so that a pace the training styles lack (the unseen styles old
            and tired walk slower) does not read as an error: gait cycles, hinge speeds and the
            speed-dependent IMU noise change with it. A slower copy is longer, so windows are cut
            from it more often. Measured: 0.8, 1 and 1.25 cost validation's IMU draws 0.015
            (README, round 8).
        postures: copies of every training take (mirrored ones too) carried with a random posture
            (:func:`reference_motion.library.posture_copies`: a stoop, a crouch, a wider or
            narrower stance, a neck and elbow bend, drawn from ``seed``), so that a way of carrying
            oneself the training styles lack is not taken for a calibration error. Their stance
            changes (−3° to 6° of abduction per hip) roll the ankles back so the soles stay level,
            where an IMU suit's hip adduction offset (8° inwards per hip at strength 1) tilts the
            soles with the legs. 0: none.
        stances: copies of every training take (mirrored ones too) walked with the feet further
            apart, each by its own distance drawn from ``stance_extra_m``, the body swaying as the
            wider steps need (:func:`reference_motion.library.stance_copies`). An IMU suit's hip
            adduction offset narrows the feet's gap by about 0.22 m at strength 1; a denoiser that
            has only seen the training styles' stances (median gap 0.14 m) reads a wide stance as
            less offset than it is and returns it too narrow (README, round 24). 0: none.
        stance_extra_m: (low, high) m, the range of the stance copies' extra width; the policies'
            default (:data:`reference_motion.library.STANCE_EXTRA_M`).
        seed: seeds windows, strengths, artefact seeds, the initial weights and the posture and
            stance copies.
    """

    window: int = 240
    min_window: int = 60
    batch_size: int = 32
    windows_per_epoch: int = 2048
    strength: tuple[float, float] = (0.0, 1.5)
    clean_fraction: float = 0.2
    hidden: int = 128
    dilations: tuple[int, ...] = (1, 2, 4, 8, 16, 32)
    sole_weight: float = 0.0
    height_weight: float = 0.0
    lr: float = 1e-3
    max_epochs: int = 60
    lr_patience: int = 4
    patience: int = 10
    mirror: bool = True
    speeds: tuple[float, ...] = (1.0,)
    postures: int = 0
    stances: int = 0
    stance_extra_m: tuple[float, float] = STANCE_EXTRA_M
    seed: int = 0

    def __post_init__(self) -> None:
        if not 2 <= self.min_window <= self.window:
            raise ValueError(f"DenoiserTrainConfig needs 2 <= min_window <= window, got {self.min_window}, "
                             f"{self.window}")
        lo, hi = self.strength
        if not 0 <= lo <= hi:
            raise ValueError(f"DenoiserTrainConfig.strength must be (low, high) with 0 <= low <= high, "
                             f"got {self.strength}")
        if not self.dilations or not all(isinstance(d, int) and d >= 1 for d in self.dilations):
            raise ValueError(f"DenoiserTrainConfig.dilations must be positive integers, got {self.dilations}")
        if self.sole_weight < 0:
            raise ValueError(f"DenoiserTrainConfig.sole_weight must be >= 0, got {self.sole_weight}")
        if self.height_weight < 0:
            raise ValueError(f"DenoiserTrainConfig.height_weight must be >= 0, got {self.height_weight}")
        if not self.speeds or not all(np.isfinite(v) and v > 0 for v in self.speeds):
            raise ValueError(f"DenoiserTrainConfig.speeds must be one or more speeds > 0, got {self.speeds}")
        if self.postures < 0:
            raise ValueError(f"DenoiserTrainConfig.postures must be >= 0, got {self.postures}")
        if self.stances < 0:
            raise ValueError(f"DenoiserTrainConfig.stances must be >= 0, got {self.stances}")
        check_stance_extra(self.stance_extra_m, "DenoiserTrainConfig.stance_extra_m")
        if not 0 <= self.clean_fraction <= 1:
            raise ValueError(f"DenoiserTrainConfig.clean_fraction must be in [0, 1], got {self.clean_fraction}")


def correction_target(clean: Motion, corrupted: Motion) -> np.ndarray:
    """What the denoiser must add to ``corrupted`` to get ``clean``: ``(T, n_hinge + 1)`` hinge
    angles (rad) and pelvis height (m), float32."""
    diff = clean.qpos - corrupted.qpos
    return np.concatenate([diff[:, 7:], diff[:, 2:3]], axis=1).astype(np.float32)


def sole_points_in_pelvis_frame(kinematics: TorchKinematics, hinges: torch.Tensor) -> torch.Tensor:
    """The four sole points ``(..., 4, 3)`` (m) relative to the pelvis, in its frame, of hinge
    angles ``hinges (..., n_hinge)`` (rad): the forward kinematics of the legs alone, whatever the
    root's placement and orientation. Differentiable."""
    flat = hinges.reshape(-1, hinges.shape[-1])
    root = torch.zeros(len(flat), 7, dtype=flat.dtype, device=flat.device)
    root[:, 3] = 1.0  # the identity quaternion
    _, soles = kinematics.points(torch.cat([root, flat], dim=1))
    return soles.reshape(*hinges.shape[:-1], *soles.shape[1:])


def correction_loss(prediction: torch.Tensor, target: torch.Tensor, given_hinges: torch.Tensor,
                    kinematics: TorchKinematics, sole_weight: float, height_weight: float = 0.0) -> torch.Tensor:
    """The denoiser's loss: the mean squared error of the corrections ``prediction`` against
    ``target`` (both ``(B, T, n_hinge + 1)``: rad and m), plus ``sole_weight`` times the mean
    squared error (m²) of the sole points relative to the pelvis
    (:func:`sole_points_in_pelvis_frame`) that the corrected hinge angles ``given_hinges +
    prediction`` give against those of the clean ones ``given_hinges + target``, plus
    ``height_weight`` times the mean squared error (m²) of the pelvis height's correction alone;
    ``given_hinges`` ``(B, T, n_hinge)`` (rad) are the corrupted take's."""
    loss = ((prediction - target) ** 2).mean()
    if height_weight:
        loss = loss + height_weight * ((prediction[..., -1] - target[..., -1]) ** 2).mean()
    if sole_weight:
        corrected = sole_points_in_pelvis_frame(kinematics, given_hinges + prediction[..., :-1])
        with torch.no_grad():
            clean = sole_points_in_pelvis_frame(kinematics, given_hinges + target[..., :-1])
        loss = loss + sole_weight * ((corrected - clean) ** 2).mean()
    return loss


def _window(motion: Motion, start: int, length: int) -> Motion:
    return Motion(motion.name, motion.fps, motion.qpos[start:start + length], motion.model, source=motion.source)


class DenoiserTask:
    """:class:`perception.training.TrainingTask` of the IMU denoiser on ``train`` / ``val`` clips."""

    def __init__(self, train_clips: Sequence[str], val_clips: Sequence[str], config: DenoiserTrainConfig,
                 model: str = "humanoid_1seg"):
        self.config, self.model = config, model
        self.kinematics = torch_kinematics(model)
        self.n_hinge = len(load_model(model).hinge_names)
        self.train_sources, self.val_sources = expand_clips(list(train_clips)), expand_clips(list(val_clips))
        overlap = sorted(set(self.train_sources) & set(self.val_sources))
        if overlap:
            raise ValueError(f"clip(s) {', '.join(overlap)} are in both the training and the validation clips")
        if not self.train_sources or not self.val_sources:
            raise ValueError("the IMU denoiser needs at least one training and one validation clip")
        takes = augmented([load_motion(s, model) for s in self.train_sources], mirrored=config.mirror,
                          speeds=config.speeds)
        self.train = (takes + posture_copies(takes, config.postures, [config.seed, POSTURE_STREAM])
                      + stance_copies(takes, config.stances, [config.seed, STANCE_STREAM], config.stance_extra_m))
        self.lengths = np.array([m.n_frames for m in self.train])
        if self.lengths.max() < config.min_window:
            raise ValueError(f"no training clip has {config.min_window} frames; lower DenoiserTrainConfig.min_window")
        self.val = []
        for i, source in enumerate(self.val_sources):
            clean = load_motion(source, model)
            for j, strength in enumerate(VALIDATION_STRENGTHS):
                given = corrupt(clean, ArtefactRecipe.imu(strength), VALIDATION_SEED + 10 * i + j) if strength else clean
                self.val.append((torch.from_numpy(motion_features(given))[None],
                                 torch.from_numpy(correction_target(clean, given))[None]))

    def network(self) -> nn.Module:
        net = IMUDenoiser(self.model, fps=self.train[0].fps, hidden=self.config.hidden,
                          dilations=self.config.dilations)
        net.set_statistics(np.concatenate([motion_features(m) for m in self.train]))
        return net

    def training_loss(self, net: nn.Module, rng: np.random.Generator, generator: torch.Generator) -> torch.Tensor:
        c = self.config
        length = int(rng.integers(c.min_window, min(c.window, self.lengths.max()) + 1))
        usable = np.flatnonzero(self.lengths >= length)
        weights = self.lengths[usable] - length + 1
        features, targets = [], []
        for pick in rng.choice(usable, size=c.batch_size, p=weights / weights.sum()):
            clean = _window(self.train[pick], int(rng.integers(self.lengths[pick] - length + 1)), length)
            given = clean
            if rng.random() >= c.clean_fraction:
                given = corrupt(clean, ArtefactRecipe.imu(float(rng.uniform(*c.strength))), int(rng.integers(2**31)))
            features.append(motion_features(given))
            targets.append(correction_target(clean, given))
        return self._loss(net, torch.from_numpy(np.stack(features)), torch.from_numpy(np.stack(targets)))

    def _loss(self, net: nn.Module, features: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
        return correction_loss(net(features), target, features[..., :self.n_hinge], self.kinematics,
                               self.config.sole_weight, self.config.height_weight)

    @torch.no_grad()
    def validation_score(self, net: nn.Module) -> float:
        """The loss (:func:`correction_loss`) left after correction, frame-weighted over the
        validation takes."""
        total = frames = 0
        for features, target in self.val:
            total += float(self._loss(net, features, target)) * features.shape[1]
            frames += features.shape[1]
        return total / frames

    def sidecar(self, net: nn.Module) -> dict:
        return {"kind": "denoiser", "joints": list(net.input_names), "fps": net.fps, "network": dict(net.config),
                "train_clips": self.train_sources, "val_clips": self.val_sources}


def train_denoiser(train_clips: Sequence[str], val_clips: Sequence[str], run_dir: Path,
                   config: DenoiserTrainConfig = DenoiserTrainConfig(), progress: bool = True) -> dict:
    """Train (or resume training) the IMU denoiser in ``run_dir``; returns the sidecar of the best
    epoch. ``run_dir/clips.json`` records the expanded clips, and a resume on other clips is refused."""
    task = DenoiserTask(train_clips, val_clips, config)
    run_dir = Path(run_dir)
    record, clips = run_dir / "clips.json", {"train": task.train_sources, "val": task.val_sources}
    if record.exists() and json.loads(record.read_text()) != clips:
        raise ValueError(f"{record}: {run_dir} holds a run on other clips; use a new run directory")
    run_dir.mkdir(parents=True, exist_ok=True)
    write_json(record, clips)
    return fit(task, run_dir, config, progress)
