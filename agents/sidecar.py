"""The sidecar of a trained policy: everything needed to rebuild its environment and its training.

``sidecar.json`` beside ``model.zip`` is a :class:`PolicySidecar` written by ``agents/train_ppo.py``
(and completed by ``agents/ship.py``). It records, typed:

* :class:`EnvSpec` — the environment id and every constructor setting the policy was trained
  under (foot model, episode length, the :class:`~envs.config.MimicConfig` constants), so
  :meth:`EnvSpec.make` rebuilds the same task on any clips;
* :class:`PPOSettings` — the PPO hyper-parameters and network;
* :class:`TrainingRecord` — the data (clips, corruption mix, augmentation), every command that
  trained the run, the seed, steps and wall time;
* the evaluation metrics of the checkpoint.

Sidecars written before this layout (a flat dict with ``env_id``, ``env_kwargs`` and an argparse
``settings`` dump) are read too.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import gymnasium as gym

from envs.config import GaitConfig, MimicConfig
from reference_motion.atomic import atomic_write

SIDECAR_FORMAT = "physmimic.policy/2"

REPOSITORY = Path(__file__).resolve().parents[1]
"""The repository root: a path a sidecar records relative to it names a file from there."""

GAIT_ENV_ID = "MimicGait-v0"
"""The environment whose constructor also takes ``gait`` and ``contacts``."""


def repository_relative(path: str | Path | None) -> str | None:
    """``path`` as a sidecar records it: relative to :data:`REPOSITORY` where it lies inside the
    repository (the bare ``--denoise`` flag gives an absolute path; the README's commands name
    ``models/...`` from the root), otherwise absolute (a path relative to where the command ran
    would name another file from the root); ``None`` stays ``None``."""
    if path is None:
        return None
    resolved = Path(path).resolve()
    return str(resolved.relative_to(REPOSITORY)) if resolved.is_relative_to(REPOSITORY) else str(resolved)


def recorded_path(path: str) -> Path:
    """The file a sidecar's recorded ``path`` names: a relative one from :data:`REPOSITORY`
    (:func:`repository_relative`), resolved."""
    return (REPOSITORY / path).resolve()


def _known(cls: type, values: dict) -> dict:
    """The entries of ``values`` that are fields of dataclass ``cls``."""
    names = {f.name for f in fields(cls)}
    return {k: v for k, v in values.items() if k in names}


@dataclass(frozen=True)
class EnvSpec:
    """The task a policy was trained on.

    Attributes:
        env_id: registered id (``MimicIMU-v0``, ``MimicDReCon-v0``, ``MimicFullAction-v0``,
            ``MimicGait-v0``).
        foot: ``"one"`` or ``"two"`` (humanoid model).
        config: the :class:`~envs.config.MimicConfig` fields (timing, rewards, terminations).
        gait: ``MimicGait-v0`` only: the :class:`~envs.config.GaitConfig` fields (reward weights and
            scales, toe reference on or off).
        contacts: ``MimicGait-v0`` only: where the contact targets came from (``"vgrf"`` or
            ``"keypoints"``); :meth:`make` uses it unless given ``contacts=``.
    """

    env_id: str = "MimicIMU-v0"
    foot: str = "one"
    config: dict = field(default_factory=lambda: asdict(MimicConfig()))
    gait: dict | None = None
    contacts: str = "vgrf"

    def __post_init__(self) -> None:
        # As JSON holds them (tuples as lists), and a config recorded before a MimicConfig field
        # existed with that field's default (the behaviour it was trained with), so that specs compare equal.
        for name in ("config", "gait"):
            object.__setattr__(self, name, json.loads(json.dumps(getattr(self, name))))
        object.__setattr__(self, "config", {**json.loads(json.dumps(asdict(MimicConfig()))), **self.config})

    def mimic_config(self) -> MimicConfig:
        """The :class:`MimicConfig` (fields unknown to this version are dropped)."""
        return MimicConfig(**_known(MimicConfig, self.config))

    def gait_config(self) -> GaitConfig:
        """The :class:`GaitConfig` (defaults where none was recorded)."""
        values = _known(GaitConfig, self.gait or {})
        if "end_effectors" in values:
            values["end_effectors"] = tuple(values["end_effectors"])
        return GaitConfig(**values)

    def make(self, clips: Any, **kwargs: Any) -> gym.Env:
        """``gym.make`` of this task on ``clips`` (any ``clips`` the env takes); ``kwargs`` add or
        override constructor arguments (``artefacts``, ``render_mode``, ``sampling``, ``contacts`` ...).
        The env keeps :class:`MimicConfig`'s default cache sizes (:data:`PROCESS_MEMORY_FIELDS`), not
        the training run's: they are how that process spent its memory, not part of the task."""
        defaults = MimicConfig()
        config = replace(self.mimic_config(), **{f: getattr(defaults, f) for f in PROCESS_MEMORY_FIELDS})
        task = {"foot": self.foot, "config": config}
        if self.env_id == GAIT_ENV_ID:
            task.update(gait=self.gait_config(), contacts=self.contacts)
        return gym.make(self.env_id, clips=clips, **{**task, **kwargs})


PROCESS_MEMORY_FIELDS = ("track_cache_size", "reference_cache_size")
"""The :class:`MimicConfig` fields that say how much a process keeps in memory (:mod:`envs.track_cache`)."""


@dataclass(frozen=True)
class PPOSettings:
    """PPO hyper-parameters (see ``agents/train_ppo.py --help``); ``lr`` is the starting rate when
    ``target_kl`` is set (the rate then follows the KL, :mod:`agents.lr_schedule`)."""

    net: str = "256,256"
    lr: float = 5e-5
    target_kl: float | None = None
    n_envs: int = 8
    n_steps: int = 1024
    batch_size: int = 512
    epochs: int = 6
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip_range: float = 0.2
    action_variance: float = 0.03


@dataclass(frozen=True)
class TrainingRecord:
    """How the policy was trained.

    Attributes:
        clips: the training clips (SOURCE strings, clip sets expanded).
        eval_clips: the clips the checkpoint was selected on.
        corrupted_fraction, strength: the IMU-corruption mix (share of episodes, strength range).
        judge: what the episodes were rewarded against (:attr:`envs.ArtefactMix.judge`).
        denoiser: the IMU denoiser the corrupted references passed through (:attr:`envs.ArtefactMix.denoiser`),
            if any: the policy expects takes denoised the same way (``clean.py --denoise``).
        denoise_slow_s: with it, the seconds its hinge corrections were slowed to
            (:attr:`envs.ArtefactMix.denoise_slow_s`, ``train_ppo.py --denoise-slow``), if they were.
        leg_symmetry, legs, grounding, lift: how every training reference had its legs evened and
            parted, was set on the floor and swing-lifted
            (:class:`reference_motion.leg_symmetry.LegSymmetry`, :class:`reference_motion.leg_gap.LegGap`,
            :class:`reference_motion.grounding.Grounding`, :class:`reference_motion.swing_lift.SwingLift`
            as dicts; ``train_ppo.py --even-legs``, ``--part-legs``, ``--ground``, ``--swing-lift``), if it
            was: the policy expects takes prepared the same way (``evaluate.py --even-legs --part-legs
            --ground --swing-lift``).
        mirror, speeds: augmentation.
        reversed_clips: the clips also trained on played backwards in time (``train_ppo.py --reverse``).
        warps: the clips also trained on at extra time-warp speeds, ``{clip: speeds}`` (``train_ppo.py --warp``).
        postures, posture_seed: random posture copies of each training reference and the seed they
            were drawn with (``train_ppo.py --postures``; :func:`reference_motion.transforms.random_posture`),
            and the ranges they were drawn from (:class:`reference_motion.transforms.PostureRanges` as a
            dict; ``None`` without postures).
        stances, stance_extra_m: copies of each training reference walked with the feet further apart
            and the range of that distance (m; ``train_ppo.py --stances``,
            :func:`reference_motion.library.stance_copies`; drawn with ``posture_seed``).
        pushes: the training envs' random pushes (:class:`envs.config.Pushes` as a dict), if any.
        dynamics: the training envs' randomised physics (:class:`envs.config.Dynamics` as a dict), if any.
        init_from: the policy it was warm-started from, if any.
        symmetric: whether PPO trained the mirror-symmetric actor (``train_ppo.py --symmetric``).
        privileged_critic: whether its critic also read the episodes' hidden corruption and body
            (``train_ppo.py --privileged-critic``); the policy is its actor either way.
        kickstart: the teachers and supervised step that pulled it towards them on their takes between
            PPO updates (:class:`agents.kickstart.KickstartConfig` as a dict; ``train_ppo.py --kickstart``), if any.
        commands: every command that trained the run, in order.
        seed, steps, wall_s: the seed, control steps and training wall time (s) at this checkpoint.
    """

    clips: list[str] = field(default_factory=list)
    eval_clips: list[str] = field(default_factory=list)
    corrupted_fraction: float = 0.0
    strength: tuple[float, float] = (0.5, 1.0)
    judge: str = "corrupted"
    denoiser: str | None = None
    denoise_slow_s: float | None = None
    leg_symmetry: dict | None = None
    legs: dict | None = None
    grounding: dict | None = None
    lift: dict | None = None
    mirror: bool = False
    speeds: list[float] = field(default_factory=lambda: [1.0])
    reversed_clips: list[str] = field(default_factory=list)
    warps: dict[str, list[float]] = field(default_factory=dict)
    postures: int = 0
    posture_seed: int = 0
    posture_ranges: dict | None = None
    stances: int = 0
    stance_extra_m: tuple[float, float] | None = None
    pushes: dict | None = None
    dynamics: dict | None = None
    init_from: str | None = None
    symmetric: bool = False
    privileged_critic: bool = False
    kickstart: dict | None = None
    commands: list[str] = field(default_factory=list)
    seed: int = 0
    steps: int = 0
    wall_s: float = 0.0


@dataclass(frozen=True)
class PolicySidecar:
    """A policy's ``sidecar.json`` (see the module docstring).

    Attributes:
        env, ppo, training: see :class:`EnvSpec`, :class:`PPOSettings`, :class:`TrainingRecord`.
        metrics: the checkpoint's evaluation (``ELR_mean``, ``SR90`` ...); ``score`` ranks checkpoints.
        extra: further entries (``agents/ship.py``'s evaluation, a shipped name ...), kept as they are.
    """

    env: EnvSpec = field(default_factory=EnvSpec)
    ppo: PPOSettings = field(default_factory=PPOSettings)
    training: TrainingRecord = field(default_factory=TrainingRecord)
    metrics: dict = field(default_factory=dict)
    score: float | None = None
    extra: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The JSON form; it also carries ``env_id``, ``env_kwargs``, ``command``, ``seed``,
        ``steps`` and ``wall_s`` at the top level for readers of the earlier layout."""
        t = self.training
        return {"format": SIDECAR_FORMAT, "env": asdict(self.env), "ppo": asdict(self.ppo), "training": asdict(t),
                "metrics": self.metrics, "score": self.score,
                "env_id": self.env.env_id, "env_kwargs": {"clips": t.clips, "foot": self.env.foot},
                "command": t.commands[-1] if t.commands else "", "seed": t.seed, "steps": t.steps,
                "wall_s": t.wall_s, **self.extra}

    @classmethod
    def from_dict(cls, data: dict) -> "PolicySidecar":
        """Read either layout (the earlier one: ``env_id``, ``env_kwargs``, ``settings``)."""
        if data.get("format") == SIDECAR_FORMAT:
            known = {"format", "env", "ppo", "training", "metrics", "score", "env_id", "env_kwargs", "command", "seed",
                     "steps", "wall_s"}
            training = dict(data["training"])
            training["strength"] = tuple(training.get("strength", (0.5, 1.0)))
            if training.get("stance_extra_m") is not None:
                training["stance_extra_m"] = tuple(training["stance_extra_m"])
            return cls(env=EnvSpec(**_known(EnvSpec, data["env"])), ppo=PPOSettings(**_known(PPOSettings, data["ppo"])),
                       training=TrainingRecord(**_known(TrainingRecord, training)), metrics=data.get("metrics", {}),
                       score=data.get("score"), extra={k: v for k, v in data.items() if k not in known})
        settings = data.get("settings", {})
        augmentation = data.get("augmentation", {})
        env = EnvSpec(env_id=data.get("env_id", "MimicIMU-v0"), foot=data.get("env_kwargs", {}).get("foot", "one"))
        training = TrainingRecord(clips=list(data.get("env_kwargs", {}).get("clips", [])),
                                  eval_clips=list(data.get("eval_clips", [])),
                                  corrupted_fraction=data.get("corrupted_fraction", 0.0),
                                  strength=tuple(data.get("strength", (0.5, 1.0))),
                                  mirror=augmentation.get("mirror", False), speeds=augmentation.get("speeds", [1.0]),
                                  commands=data.get("commands", [data["command"]] if "command" in data else []),
                                  seed=data.get("seed", 0), steps=data.get("steps", 0), wall_s=data.get("wall_s", 0.0))
        legacy = {"env_id", "env_kwargs", "eval_clips", "corrupted_fraction", "strength", "augmentation", "command",
                  "commands", "seed", "steps", "wall_s", "score", "metrics", "net", "settings"}
        return cls(env=env, ppo=PPOSettings(**_known(PPOSettings, settings)), training=training,
                   metrics=data.get("metrics", {}), score=data.get("score"),
                   extra={k: v for k, v in data.items() if k not in legacy})

    def save(self, path: str | Path) -> None:
        """Write ``path`` (whole or not at all)."""
        with atomic_write(path) as tmp:
            tmp.write_text(json.dumps(self.to_dict(), indent=1, default=str))

    @classmethod
    def load(cls, path: str | Path) -> "PolicySidecar":
        """Read ``path``; a missing file gives the defaults."""
        path = Path(path)
        if not path.exists():
            return cls()
        try:
            return cls.from_dict(json.loads(path.read_text()))
        except (json.JSONDecodeError, UnicodeDecodeError, TypeError, KeyError) as err:
            raise ValueError(f"{path}: not a policy sidecar ({err})") from None
