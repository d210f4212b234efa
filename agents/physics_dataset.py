"""Physics-labelled motion: trained mimic policies re-perform the clip library in MuJoCo, and every
frame's 23 joint positions come with the exact insole-cell vGRF the simulator measured.

UnderPressure (§3) captured motion with pressure insoles; here the simulator is the insole. For
each clip of :attr:`DatasetConfig.clips`, :attr:`DatasetConfig.variants` references are made
(every other one mirrored, time-warped by a random speed in ``speed_range``, a random share
IMU-corrupted), a policy re-performs ``episodes`` windows of each, and the simulated frames are
recorded at 60 Hz into shards of the format :mod:`perception.dataset` describes and reads.

One shard per (clip, variant) in ``DIR/{train,val,test}/``; the split goes by *source clip*
(:attr:`DatasetConfig.splits`), so no motion of a test clip is ever trained on. Generation is
seeded and resumable: a shard is written atomically once complete and skipped when it exists.
MuJoCo's soft contacts chatter: the raw per-frame foot load of a walking stance swings by 0.35 BW
RMS from one frame to the next (the sole spheres make and break contact within a few
milliseconds). A pressure insole integrates that away, so ``forces`` models one: the frame means
low-passed with a Gaussian of :attr:`DatasetConfig.insole_smoothing_s`. Frames of the last
``fall_margin_s`` before an episode ends early (a fall or lagging behind) are
dropped, since the body is then no longer performing the clip.

This lives in ``agents/`` because it runs policies in the environments; ``perception`` reads the
result without importing either.
"""

from __future__ import annotations

import json
import re
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from scipy.ndimage import gaussian_filter1d
from tqdm import tqdm

import envs  # noqa: F401  (registers the ids)
from agents.policy import MimicPolicy, load_policy
from agents.rollout import run_episode
from envs.config import FOOT_MODELS, MimicConfig
from perception.dataset import summarize
from perception.skeleton import N_JOINTS, joint_map
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion, warped
from reference_motion.motion import Motion
from reference_motion.transforms import ENV_FPS, mirror

DEFAULT_SPLITS = {
    "val": ("deepmimic:walker/turn_right1",),
    "test": ("deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1"),
}
"""Held-out source clips (the rest of :attr:`DatasetConfig.clips` is ``train``): ADAPT's three
held-out walker clips, which the shipped ``mimic_imu`` policy never trained on either."""


@dataclass(frozen=True)
class DatasetConfig:
    """How a physics-labelled dataset is generated (every field is recorded in ``manifest.json``).

    Attributes:
        policies: policy directories (``agents/train_ppo.py`` output); variants take turns.
            ``mimic_imu`` alone by default: it performs mirrored, warped and corrupted walks, where
            ``mimic_walk`` (trained on walk only) loses its balance within a second.
        clips: SOURCE strings of the clip library. The locomotion clips: the shipped policies lose
            the other DeepMimic clips (dances, spins, kicks, jumps) within about a second, which
            would leave only falls to record.
        splits: ``{"val": clips, "test": clips}``; every other clip is ``train``.
        variants: references made per clip (mirrored, warped, corrupted as below).
        episodes: windows re-performed per variant, start frames spread over the clip.
        speed_range: time-warp speeds drawn uniformly (UnderPressure-style ±20%).
        corrupted_share: probability that a variant's reference gets IMU artefacts.
        strength_range: artefact strength of corrupted variants, drawn uniformly.
        insole_smoothing_s: σ of the insole model's Gaussian low-pass (s).
        fall_margin_s: seconds dropped before an early episode end.
        min_episode_s: shorter kept episodes are discarded.
        seed: everything random derives from it.
    """

    policies: tuple[str, ...] = ("models/mimic_imu",)
    clips: tuple[str, ...] = ("deepmimic:walk", "deepmimic:run", "deepmimic:walker/0walk_forward",
                              "deepmimic:walker/turn_left0", "deepmimic:walker/turn_left1",
                              "deepmimic:walker/turn_right0", "deepmimic:walker/turn_right1")
    splits: dict = field(default_factory=lambda: {k: list(v) for k, v in DEFAULT_SPLITS.items()})
    variants: int = 24
    episodes: int = 6
    speed_range: tuple[float, float] = (0.8, 1.2)
    corrupted_share: float = 0.5
    strength_range: tuple[float, float] = (0.1, 0.6)
    insole_smoothing_s: float = 0.025
    fall_margin_s: float = 0.5
    min_episode_s: float = 1.5
    seed: int = 0

    def split_of(self, clip: str) -> str:
        for split in ("val", "test"):
            if clip in self.splits.get(split, ()):
                return split
        return "train"


@dataclass(frozen=True)
class Variant:
    """One reference made from a library clip: ``mirrored``, played at ``speed``, corrupted at
    ``strength`` with ``artefact_seed`` (``strength`` 0 = clean), performed by ``policy``."""

    clip: str
    index: int
    mirrored: bool
    speed: float
    strength: float
    artefact_seed: int
    policy: str

    @property
    def shard_name(self) -> str:
        slug = re.sub(r"[^A-Za-z0-9]+", "_", self.clip.removeprefix("deepmimic:")).strip("_")
        return f"{slug}_v{self.index:03d}.npz"


def plan(config: DatasetConfig) -> list[Variant]:
    """Every variant of the dataset, in generation order (a pure function of ``config``)."""
    out = []
    for c, clip in enumerate(config.clips):
        for k in range(config.variants):
            rng = np.random.default_rng([config.seed, c, k])
            corrupted = rng.random() < config.corrupted_share
            out.append(Variant(clip=clip, index=k, mirrored=bool(k % 2), speed=float(rng.uniform(*config.speed_range)),
                               strength=float(rng.uniform(*config.strength_range)) if corrupted else 0.0,
                               artefact_seed=int(rng.integers(2**31)),
                               policy=config.policies[(k // 2) % len(config.policies)]))
    return out


def reference_for(variant: Variant, model: str, min_frames: int) -> Motion:
    """The reference motion of ``variant`` (loaded, warped, mirrored, corrupted)."""
    motion = warped(load_motion(variant.clip, model, min_frames=int(min_frames * 1.25) + 2), variant.speed)
    if variant.mirrored:
        motion = mirror(motion)
    if variant.strength > 0:
        motion = corrupt(motion, ArtefactRecipe.imu(variant.strength), variant.artefact_seed)
    return motion


class FrameRecorder:
    """Records joint positions, cell vGRF and qpos per frame: install it as both
    ``env.substep_hook`` (it sums each substep's cell forces) and ``env.frame_hook``."""

    def __init__(self, model_name: str):
        self.humanoid = load_model(model_name)
        self.joints = joint_map(model_name)
        self.frames: dict[str, list] = {"positions": [], "forces": [], "qpos": []}
        self._force_sum, self._substeps = np.zeros((2, 16)), 0

    def substep(self, data) -> None:
        self._force_sum += self.humanoid.cell_forces(data)
        self._substeps += 1

    def __call__(self, data) -> None:
        self.frames["positions"].append(self.joints.positions(data.xpos[1:], data.xquat[1:]))
        self.frames["forces"].append(self._force_sum / max(self._substeps, 1))
        self.frames["qpos"].append(data.qpos.copy())
        self._force_sum, self._substeps = np.zeros((2, 16)), 0

    def take(self, n: int) -> dict[str, np.ndarray]:
        """The first ``n`` recorded frames as arrays; then start afresh."""
        out = {k: np.array(v[:n]) for k, v in self.frames.items()}
        self.frames = {k: [] for k in self.frames}
        return out


def insole(forces: np.ndarray, fps: float, smoothing_s: float) -> np.ndarray:
    """What a pressure insole would read from per-frame cell forces ``(T, 2, 16)``: a Gaussian
    low-pass of ``smoothing_s`` (s) over time (:attr:`DatasetConfig.insole_smoothing_s`)."""
    return gaussian_filter1d(forces, sigma=smoothing_s * fps, axis=0, mode="nearest") if smoothing_s > 0 else forces


def perform(variant: Variant, policy: MimicPolicy, config: DatasetConfig) -> tuple[dict[str, np.ndarray], list[dict]]:
    """Re-perform ``config.episodes`` windows of ``variant`` with ``policy``; the kept frames
    (concatenated, ``episode`` numbering them) and one record per episode."""
    model = FOOT_MODELS[policy.foot]
    longest = MimicConfig().episode_frames
    reference = reference_for(variant, model, 2 * (longest + 1))
    fps = reference.fps
    if reference.n_frames <= config.min_episode_s * fps:
        raise ValueError(f"clip {variant.clip!r} has {reference.n_frames} frames at {fps:g} Hz after a "
                         f"{variant.speed:.2f}x time warp, not more than min_episode_s = {config.min_episode_s} s: "
                         "no episode could be kept")
    episode_frames = min(longest, reference.n_frames - 1)
    env = policy.make_env([reference], artefacts=None, episode_frames=episode_frames)
    base = env.unwrapped
    recorder = FrameRecorder(model)
    base.frame_hook, base.substep_hook = recorder, recorder.substep
    starts = np.linspace(0, reference.n_frames - 1 - episode_frames, config.episodes).astype(int)
    chunks, records = [], []
    rng = np.random.default_rng([config.seed, variant.artefact_seed])
    for e, start in enumerate(starts):
        recorder.take(0)
        episode = run_episode(env, policy, {"start_frame": int(start)}, seed=int(rng.integers(2**31)))
        n = len(recorder.frames["qpos"])
        ended_by = episode.ended_by
        keep = n if ended_by == "time_limit" else max(0, n - int(round(config.fall_margin_s * fps)))
        frames = recorder.take(keep)
        frames["forces_raw"] = frames["forces"]
        frames["forces"] = insole(frames["forces_raw"], fps, config.insole_smoothing_s)
        frames["contacts"] = np.array([recorder.humanoid.foot_contacts(None, c)
                                       for c in frames["forces_raw"]]).reshape(-1, 4)
        records.append({"start_frame": int(start), "frames": int(keep), "ended_by": ended_by})
        if keep >= config.min_episode_s * fps:
            frames["episode"] = np.full(keep, e, dtype=np.int32)
            chunks.append(frames)
    env.close()
    if not chunks:
        return {}, records
    return {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}, records


def generate(out: Path, config: DatasetConfig = DatasetConfig(), progress: bool = True) -> dict:
    """Generate (or finish generating) the dataset in ``out``; returns the manifest."""
    out = Path(out)
    manifest_path = out / "manifest.json"
    wanted = {"config": json.loads(json.dumps(asdict(config)))}
    if manifest_path.exists():
        stored = json.loads(manifest_path.read_text())
        if stored.get("config") != wanted["config"]:
            raise ValueError(f"{manifest_path}: this directory holds a dataset made with other settings; "
                             f"use a new --out or the same settings to resume")
    out.mkdir(parents=True, exist_ok=True)
    manifest_path.write_text(json.dumps(wanted, indent=1))
    for path in config.policies:
        if not Path(path).exists():
            raise FileNotFoundError(f"policy {path}: no such directory (train one with agents/train_ppo.py)")
    policies: dict[str, MimicPolicy] = {}
    variants = plan(config)
    todo = [v for v in variants if not (out / config.split_of(v.clip) / v.shard_name).exists()]
    bar = tqdm(todo, desc="performing clips", unit="variant", disable=not progress)
    for variant in bar:
        if variant.policy not in policies:
            policies[variant.policy] = load_policy(variant.policy)
        frames, records = perform(variant, policies[variant.policy], config)
        split = config.split_of(variant.clip)
        meta = {**asdict(variant), "split": split, "episodes": records, "fps": ENV_FPS}
        shard = out / split / variant.shard_name
        shard.parent.mkdir(parents=True, exist_ok=True)
        tmp = shard.with_suffix(".tmp.npz")
        if not frames:  # every episode too short: an empty shard marks the variant as done
            frames = {"positions": np.zeros((0, N_JOINTS, 3), np.float32), "forces": np.zeros((0, 2, 16), np.float32),
                      "forces_raw": np.zeros((0, 2, 16), np.float32),
                      "contacts": np.zeros((0, 4), bool), "qpos": np.zeros((0, 0), np.float32),
                      "episode": np.zeros(0, np.int32)}
        np.savez_compressed(tmp, positions=frames["positions"].astype(np.float32),
                            forces=frames["forces"].astype(np.float32),
                            forces_raw=frames["forces_raw"].astype(np.float32), contacts=frames["contacts"].astype(bool),
                            qpos=frames["qpos"].astype(np.float32), episode=frames["episode"].astype(np.int32),
                            meta=json.dumps(meta))
        tmp.replace(shard)
        bar.set_postfix(frames=len(frames["episode"]))
    summary = summarize(out)
    manifest_path.write_text(json.dumps({**wanted, "summary": summary}, indent=1))
    return {**wanted, "summary": summary}
