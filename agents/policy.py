"""Loading a trained mimic policy (SB3 PPO + observation statistics + sidecar) with clear errors.

A policy is stored as a directory holding ``model.zip`` (stable-baselines3 PPO),
``model_vecnormalize.pkl`` (the running observation statistics it was trained with) and
``sidecar.json`` (how it was made: command, seed, steps, wall time, metrics, and the environment
id and arguments it expects). ``agents/train_ppo.py`` writes such a directory as ``RUN/best``;
shipped policies live in ``models/NAME/``.
"""

from __future__ import annotations

import json
import math
import os
import pickle
import shutil
import tempfile
import zipfile
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.running_mean_std import RunningMeanStd
from stable_baselines3.common.torch_layers import FlattenExtractor
from stable_baselines3.common.vec_env import VecNormalize

from agents.mirror import MirrorAveraged, MirrorMaps
from agents.sidecar import GAIT_ENV_ID, PolicySidecar, recorded_path
from agents.symmetric_policy import SymmetricActorCriticPolicy
from envs.config import GAIT_ABLATIONS
from envs.observations import SAME_LAYOUT_FRAMES, same_layout

if TYPE_CHECKING:
    from reference_motion.grounding import Grounding
    from reference_motion.leg_gap import LegGap
    from reference_motion.leg_symmetry import LegSymmetry
    from reference_motion.swing_lift import SwingLift

MODEL_FILE, STATS_FILE, SIDECAR_FILE = "model.zip", "model_vecnormalize.pkl", "sidecar.json"
CHECKPOINTS_DIR = "checkpoints"
"""A training run's folder of ``step_N.zip`` checkpoints, each with ``step_N_vecnormalize.pkl`` and
``step_N_sidecar.json`` (``agents/train_ppo.py``)."""


class PolicyError(ValueError):
    """A policy file is missing, malformed, or does not fit the environment."""


@dataclass
class MimicPolicy:
    """A trained policy: ``policy(obs)`` → deterministic action.

    Attributes:
        path: the policy directory.
        model: the SB3 PPO model.
        normalizer: the running observation statistics it was trained with (SB3 ``VecNormalize``).
        sidecar: the sidecar's contents (``{}`` when absent).
        mirror: when set, the policy acts as its mirror-symmetric actor (:meth:`mirror_averaged`).
            A network trained as that actor (:attr:`symmetric_network`) is one already.
        source: what :func:`load_policy` was given (the directory, its ``model.zip`` or a run's
            checkpoint ``step_N.zip``), so a report can name the checkpoint and not only its
            directory; ``None`` for a policy built in memory.
    """

    path: Path
    model: PPO
    normalizer: VecNormalize
    sidecar: dict = field(default_factory=dict)
    mirror: MirrorMaps | None = None
    source: Path | None = None

    @property
    def model_file(self) -> Path:
        """The model archive the weights were loaded from: :attr:`source` where it names one (a run's
        checkpoint ``step_N.zip``), else the directory's ``model.zip``. Weights changed in memory
        since (a training copy, a mirrored network) are not that file's."""
        return self._files[1]

    @property
    def stats_file(self) -> Path:
        """The observation statistics saved beside :attr:`model_file`."""
        return self._files[2]

    @property
    def _files(self) -> tuple[Path, Path, Path]:
        """:func:`policy_files` of what the policy was loaded from (:attr:`source`, else :attr:`path`)."""
        return policy_files(self.source if self.source is not None else self.path)

    @property
    def name(self) -> str:
        """How reports name the policy: its directory, or a run's checkpoint by its file
        (``RUN/checkpoints/step_N.zip``), so two checkpoints of one run are told apart."""
        return str(self.path if self.model_file.name == MODEL_FILE else self.model_file)

    @property
    def short_name(self) -> str:
        """:attr:`name` without its folders: the directory's name, or ``RUN/step_N`` for a checkpoint."""
        if self.model_file.name == MODEL_FILE:
            return Path(self.path).name
        return f"{Path(self.path).parent.name}/{self.model_file.stem}"

    @property
    def symmetric_network(self) -> bool:
        """Whether PPO trained the symmetric actor itself (``train_ppo.py --symmetric``,
        :class:`agents.symmetric_policy.SymmetricActorCriticPolicy`): the network's action is the
        mean of its two mirror halves, on mirror-symmetric observation statistics."""
        return isinstance(self.model.policy, SymmetricActorCriticPolicy)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        """The deterministic action ``(A,)`` (rad offsets) for one raw observation ``obs (D,)``:
        :meth:`mean_action`, or with :attr:`mirror` the mean of it and, mapped back, of its action
        on the mirrored observation (:class:`agents.mirror.MirrorAveraged`)."""
        if self.mirror is not None:
            return MirrorAveraged(self.mean_action, self.mirror)(obs)
        return self.mean_action(obs)

    def mirror_averaged(self, env: gym.Env) -> MimicPolicy:
        """This policy acting as its mirror-symmetric actor (:mod:`agents.mirror`) in ``env``, an
        environment of its task: the same weights and statistics; its stochastic actions
        (:func:`agents.rollout.sampling_policy`) are that actor's plus the policy's Gaussian
        exploration noise. Training a copy (:mod:`agents.adaptation`) trains the network itself."""
        self.check_env(env)
        if self.symmetric_network:  # already that actor
            return self
        return replace(self, mirror=MirrorMaps.of(env))

    def mirror_averaged_on(self, clip: Any) -> MimicPolicy:
        """:meth:`mirror_averaged` in this policy's own task on ``clip`` (a clip SOURCE or
        :class:`~reference_motion.motion.Motion`; the maps depend on the task, not the clip), the
        environment built for the maps and closed."""
        env = self.make_env([clip], artefacts=None)
        try:
            return self.mirror_averaged(env)
        finally:
            env.close()

    def mean_action(self, obs: np.ndarray) -> np.ndarray:
        """The network's deterministic action ``(A,)`` (rad offsets, clipped to the action space)
        for one raw observation ``obs (D,)``: what ``model.predict(..., deterministic=True)``
        returns, computed with NumPy on the actor's current weights (:func:`mlp_mean_action`; 5×
        faster than stable-baselines3's path for one observation, which a rollout calls every step).
        For a :attr:`symmetric_network`, the mean of its two mirror halves, as its Gaussian's."""
        x = np.asarray(self.normalizer.normalize_obs(obs), dtype=np.float32)
        if self.symmetric_network:  # mirror-symmetric statistics: the normalised mirror image is the mirrored input
            maps = self.model.policy.mirror_maps
            halves = mlp_mean_action(self.model.policy, np.stack([x, maps.observation(x)]))
            mean = None if halves is None else maps.averaged(*halves)
        else:
            mean = mlp_mean_action(self.model.policy, x)
        if mean is None:  # an actor this shortcut does not cover
            action, _ = self.model.predict(x, deterministic=True)
            return action
        space = self.model.action_space
        return np.clip(mean, space.low, space.high)

    def values(self, obs: np.ndarray) -> np.ndarray:
        """The critic's estimates ``(K,)`` of the discounted return (reward units) from raw
        observations ``obs (K, D)``."""
        x = torch.as_tensor(np.asarray(self.normalizer.normalize_obs(obs), dtype=np.float32))
        with torch.no_grad():
            return self.model.policy.predict_values(x).numpy()[:, 0]

    @property
    def record(self) -> PolicySidecar:
        """The sidecar, typed (:class:`agents.sidecar.PolicySidecar`; either layout)."""
        return PolicySidecar.from_dict(self.sidecar)

    @property
    def env_id(self) -> str:
        return self.record.env.env_id

    @property
    def foot(self) -> str:
        return self.record.env.foot

    def make_env(self, clips: Any, **kwargs: Any) -> gym.Env:
        """The environment this policy was trained in (id, foot, every MimicConfig constant, from
        the sidecar) on ``clips``; ``kwargs`` add constructor arguments (``artefacts``, ...)."""
        env = self.record.env.make(clips, **kwargs)
        self.check_env(env)
        return env

    def ablated(self, ablation: str) -> MimicPolicy:
        """This policy, its task changed to one of ContactVision Fig. 12's ablations of
        ``MimicGait-v0`` (:meth:`envs.config.GaitConfig.ablated`: ``"no_fc"`` or ``"no_toeref"``):
        the same weights, but :meth:`make_env` builds the ablated task, so adapting the copy
        (:mod:`agents.adaptation`) fine-tunes it under the ablated reward or toe targets. The
        sidecar records the change (``ablation``); the files on disk are not touched, and the copy
        shares this policy's model and statistics objects (:func:`agents.adaptation.adapt_policy`
        trains a copy loaded from disk). A policy already in an ablated task (ablated here, or
        trained with ``--gait-ablation``) is refused: ablations are compared one at a time."""
        record = self.record
        if record.env.env_id != GAIT_ENV_ID:
            raise PolicyError(f"{self.name}: a {record.env.env_id} policy; gait ablations apply to {GAIT_ENV_ID}")
        if ablation not in GAIT_ABLATIONS:
            raise PolicyError(f"{self.name}: unknown gait ablation {ablation!r}; expected one of {GAIT_ABLATIONS}")
        gait = record.env.gait_config()
        if "ablation" in record.extra or gait.w_fc == 0 or not gait.toe_reference:
            raise PolicyError(f"{self.name}: already in an ablated task (w_fc {gait.w_fc}, toe_reference "
                              f"{gait.toe_reference}); ablate the full policy instead")
        task = replace(record.env, gait=asdict(gait.ablated(ablation)))
        sidecar = replace(record, env=task, extra={**record.extra, "ablation": ablation}).to_dict()
        return replace(self, sidecar=sidecar)

    def observing(self, frame: str) -> MimicPolicy:
        """This policy, its observation turned into ``frame`` (one of
        :data:`envs.observations.SAME_LAYOUT_FRAMES`: ``"world"`` or ``"reference"``, which differ
        only by a turn about z): the same weights, but :meth:`make_env` builds its task observing
        in ``frame``, and adapting the copy fine-tunes it there. The sidecar records the change
        (``observed_in``: the frame it was given in first); the files on disk are not touched."""
        record = self.record
        config = record.env.mimic_config()
        if config.obs_frame == frame:
            return self
        if not same_layout(config.obs_frame, frame):
            raise PolicyError(f"{self.name}: observes in the {config.obs_frame!r} frame; only "
                              f"{' and '.join(SAME_LAYOUT_FRAMES)} have the same layout, so it cannot run in {frame!r}")
        return self._reconfigured("obs_frame", frame, "observed_in")

    def simulating(self, rate_hz: float) -> MimicPolicy:
        """This policy, its task's physics stepped at ``rate_hz`` (:attr:`envs.config.MimicConfig.physics_rate_hz`):
        the same weights, but :meth:`make_env` builds its task with the finer step and stiffer
        contacts, so its rollouts (evaluation, the cleaned clip) sink less into the floor and slide
        less; adapting the copy fine-tunes it there. The sidecar records the change
        (``simulated_at``: the rate it was given at first); the files on disk are not touched."""
        if abs(self.record.env.mimic_config().physics_rate_hz - rate_hz) <= 1e-6 * rate_hz:
            return self
        return self._reconfigured("physics_rate_hz", float(rate_hz), "simulated_at")

    def steering(self, gain_hz: float, max_speed_mps: float | None = None) -> MimicPolicy:
        """This policy, the reference velocities its task observes steered back onto the reference's
        position at ``gain_hz`` (1/s, :attr:`envs.config.MimicConfig.steer_gain_hz`; the layout is
        the same, so any policy runs with it), the pull capped at ``max_speed_mps`` (m/s,
        :attr:`~envs.config.MimicConfig.steer_max_speed_mps`; ``None``: the cap its task has): the same
        weights, but :meth:`make_env` builds its task with them, and adapting the copy fine-tunes it
        there. The sidecar records each change (``steered_at`` and ``steer_capped_at``: the values it was
        given with first); the files on disk are not touched."""
        config = self.record.env.mimic_config()
        policy = self if config.steer_gain_hz == gain_hz else self._reconfigured(
            "steer_gain_hz", float(gain_hz), "steered_at")
        if max_speed_mps is None or config.steer_max_speed_mps == max_speed_mps:
            return policy
        return policy._reconfigured("steer_max_speed_mps", float(max_speed_mps), "steer_capped_at")

    def _reconfigured(self, name: str, value: Any, given_as: str) -> MimicPolicy:
        """This policy, its task's :class:`~envs.config.MimicConfig` field ``name`` set to ``value``
        (checked by the config), the sidecar's extra ``given_as`` keeping the value it had first."""
        record = self.record
        task = replace(record.env, config={**record.env.config, name: value})
        first = getattr(record.env.mimic_config(), name)
        task.mimic_config()  # raises for a value the config refuses
        sidecar = replace(record, env=task, extra={given_as: first, **record.extra}).to_dict()
        return replace(self, sidecar=sidecar)

    def preparation_note(self, denoiser: str | Path | None, grounding: Grounding | None = None,
                         lift: SwingLift | None = None, *, legs: LegGap | None = None,
                         symmetry: LegSymmetry | None = None, denoise_slow_s: float | None = None) -> str | None:
        """A warning when the policy's training references were prepared (``train_ppo.py
        --denoise``, ``--even-legs``, ``--part-legs``, ``--ground``, ``--swing-lift``;
        :class:`~agents.sidecar.TrainingRecord`'s ``denoiser``, ``leg_symmetry``, ``legs``, ``grounding``
        and ``lift``) and the takes it is given now are not, or otherwise: through another IMU denoiser
        or none (``denoiser``: a path or ``None``), its corrections slowed otherwise or not
        (``denoise_slow_s``), with the legs evened otherwise or not, parted
        otherwise or not, set on the floor with other settings or not, lifted in
        backward swing otherwise or not; else
        ``None``. Settings are compared where the sidecar records them (a field added since keeps
        its default's silence). Preparations the policy did not train on draw no note."""
        trained = self.record.training
        unlike = []
        if trained.denoiser and not (denoiser and Path(denoiser).resolve() == recorded_path(trained.denoiser)):
            unlike.append(f"passed through the IMU denoiser {trained.denoiser}; these takes are "
                          f"{f'denoised by {denoiser}' if denoiser else 'not denoised'} (--denoise)")
        if trained.denoiser and trained.denoise_slow_s != denoise_slow_s:
            unlike.append(f"behind the denoiser's corrections "
                          f"{f'slowed to {trained.denoise_slow_s:g} s' if trained.denoise_slow_s else 'unslowed'}; "
                          f"these takes are behind "
                          f"{f'corrections slowed to {denoise_slow_s:g} s' if denoise_slow_s else 'unslowed ones'} "
                          f"(--denoise-slow)")
        if trained.leg_symmetry and not recorded_as(trained.leg_symmetry, symmetry):
            unlike.append(f"with the legs evened; these takes are {'evened otherwise' if symmetry else 'not'} "
                          f"(--even-legs)")
        if trained.legs and not recorded_as(trained.legs, legs):
            unlike.append(f"with the legs parted to {trained.legs.get('min_gap_m')} m; these takes are "
                          f"{'parted otherwise' if legs else 'not'} (--part-legs)")
        if trained.grounding and not recorded_as(trained.grounding, grounding):
            unlike.append(f"set on the floor; these takes are {'set on it otherwise' if grounding else 'not'} "
                          f"(--ground)")
        if trained.lift and not recorded_as(trained.lift, lift):
            unlike.append(f"lifted in backward swing ({trained.lift.get('knee_deg')}°); these takes are "
                          f"{'lifted otherwise' if lift else 'not'} (--swing-lift)")
        return f"note: {self.name} was trained on references " + "; and ".join(unlike) if unlike else None

    def check_env(self, env: gym.Env) -> None:
        """Raise :class:`PolicyError` unless ``env``'s spaces are the ones the policy was trained on."""
        obs, act = self.model.observation_space.shape, self.model.action_space.shape
        if env.observation_space.shape != obs or env.action_space.shape != act:
            raise PolicyError(f"{self.name}: the policy expects observations {obs} and actions {act}, but the "
                              f"environment gives {env.observation_space.shape} and {env.action_space.shape}; it was "
                              f"trained on {self.env_id} with foot={self.foot!r}")


_NUMPY_ACTIVATIONS = {torch.nn.Tanh: np.tanh, torch.nn.ReLU: lambda h: np.maximum(h, 0.0)}


def recorded_as(recorded: dict, settings: Any) -> bool:
    """Whether the dataclass ``settings`` (or ``None``) has every value a sidecar ``recorded`` for it
    (nested dataclasses as nested dicts; compared as JSON holds them, so tuples match lists)."""
    if settings is None:
        return False
    given = json.loads(json.dumps(asdict(settings)))

    def within(stored: dict, now: dict) -> bool:
        return all(within(v, now.get(k)) if isinstance(v, dict) and isinstance(now.get(k), dict)
                   else now.get(k, object()) == v for k, v in stored.items())
    return within(recorded, given)


def mlp_mean_action(policy: torch.nn.Module, x: np.ndarray) -> np.ndarray | None:
    """The Gaussian mean ``(..., A)`` of an SB3 ``ActorCriticPolicy`` whose actor is an MLP (linear
    layers with tanh or ReLU between, as ``train_ppo.py`` builds them), for normalised observations
    ``x (..., D)`` float32, in NumPy on views of the current weights (no copy: always the weights
    as trained so far); ``None`` for any other actor."""
    if (not isinstance(getattr(policy, "features_extractor", None), FlattenExtractor) or x.ndim < 1
            or len(policy.observation_space.shape) != 1):
        return None
    layers = [*policy.mlp_extractor.policy_net, policy.action_net]
    h = x
    for layer in layers:
        if isinstance(layer, torch.nn.Linear):
            h = h @ layer.weight.detach().numpy().T + layer.bias.detach().numpy()
        elif type(layer) in _NUMPY_ACTIVATIONS:
            h = _NUMPY_ACTIVATIONS[type(layer)](h)
        else:
            return None
    return h


def set_action_variance(model: PPO, variance: float) -> None:
    """Set ``model``'s Gaussian exploration noise to σ² = ``variance`` (rad²) on every action
    dimension (its ``log_std`` parameter, ½ log σ²)."""
    with torch.no_grad():
        model.policy.log_std.fill_(0.5 * math.log(variance))


def save_policy(path: Path, model: PPO, statistics: VecNormalize | Path, sidecar: PolicySidecar) -> None:
    """Write the policy directory ``path`` whole: ``model``, the observation ``statistics`` (a
    ``VecNormalize`` wrapping environments, or a policy's statistics file to copy: a policy's
    loaded statistics wrap none and cannot be saved again) and ``sidecar``; into a temporary
    folder beside it, then renamed in place of the old one (set aside until then), so an
    interrupted write leaves no half policy, and a write that raises leaves no temporary folder and
    the old policy as it was."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir()
    try:
        model.save(tmp / MODEL_FILE)
        if isinstance(statistics, VecNormalize):
            statistics.save(str(tmp / STATS_FILE))
        else:
            shutil.copy2(statistics, tmp / STATS_FILE)
        sidecar.save(tmp / SIDECAR_FILE)
    except BaseException:  # a write that raised leaves nothing behind, and the old policy in place
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    old = path.with_name(f".{path.name}.{os.getpid()}.old")
    shutil.rmtree(old, ignore_errors=True)
    try:
        if path.exists():
            os.replace(path, old)  # set aside, not deleted, until the new policy is in place
        os.replace(tmp, path)
    except BaseException:
        if old.exists() and not path.exists():
            os.replace(old, path)
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    shutil.rmtree(old, ignore_errors=True)


def with_statistics(normalizer: VecNormalize, mean: np.ndarray, var: np.ndarray) -> VecNormalize:
    """A copy of a loaded policy's observation ``normalizer`` (the same settings; the original is
    untouched) normalising by ``mean`` and ``var`` ``(D,)``, with the original's count of samples
    and an observation space of ``D`` values, so that it loads onto an env of ``D`` observations (a DAgger student's,
    :mod:`agents.distill`; a privileged critic's actor, :func:`agents.privileged_critic.actor_only`)."""
    widened = VecNormalize.__new__(VecNormalize)  # a loaded one wraps no envs, which copy.copy would look up
    widened.__dict__.update(normalizer.__dict__)
    widened.observation_space = gym.spaces.Box(-np.inf, np.inf, mean.shape, np.float32)  # VecNormalize.load checks it
    widened.obs_rms = RunningMeanStd(shape=mean.shape)
    widened.obs_rms.mean, widened.obs_rms.var, widened.obs_rms.count = mean, var, normalizer.obs_rms.count
    return widened


def save_loaded_policy(path: Path, model: PPO, statistics: VecNormalize, sidecar: PolicySidecar) -> None:
    """:func:`save_policy` for ``statistics`` a loaded policy holds (:func:`load_policy`), whose
    weights or statistics a tool changed: they lack what ``VecNormalize``'s pickling drops (the
    envs, their attributes, the returns), so they are given empty ones and pickled as
    :func:`load_policy` reads them."""
    statistics.venv, statistics.class_attributes, statistics.returns = None, {}, None
    with tempfile.TemporaryDirectory() as tmp:
        stats_file = Path(tmp) / STATS_FILE
        stats_file.write_bytes(pickle.dumps(statistics))
        save_policy(path, model, stats_file, sidecar)


def policy_files(path: str | Path) -> tuple[Path, Path, Path]:
    """``(directory, model archive, observation statistics)`` of what :func:`load_policy` reads for
    ``path``: a policy directory or its ``model.zip`` (``model_vecnormalize.pkl`` beside it), or a
    run's checkpoint ``step_N.zip`` (``step_N_vecnormalize.pkl``). Nothing is checked to exist."""
    path = Path(path)
    directory = path.parent if path.suffix == ".zip" else path
    model_file = path if path.suffix == ".zip" else directory / MODEL_FILE
    return directory, model_file, model_file.with_name(model_file.stem + "_vecnormalize.pkl")


def load_policy(path: str | Path) -> MimicPolicy:
    """Load a policy directory (or its ``model.zip``), or a training run's checkpoint
    ``RUN/checkpoints/step_N.zip`` (with its ``step_N_sidecar.json``); :class:`PolicyError` names
    what is wrong. A network trained with a privileged critic (``train_ppo.py --privileged-critic``)
    loads as its actor (:func:`agents.privileged_critic.actor_only`; its values are the critic's without
    the privileged inputs)."""
    path = Path(path)
    directory, model_file, stats_file = policy_files(path)
    if not model_file.exists():
        raise PolicyError(f"{model_file}: no such policy file (a policy is a directory with {MODEL_FILE}, "
                          f"{STATS_FILE} and {SIDECAR_FILE})")
    if not zipfile.is_zipfile(model_file):
        raise PolicyError(f"{model_file}: not a stable-baselines3 model (not a zip archive)")
    try:
        model = PPO.load(model_file, device="cpu")
    except Exception as err:  # SB3 raises many kinds on a damaged archive
        raise PolicyError(f"{model_file}: cannot load the PPO model: {err}") from err
    if not stats_file.exists():
        raise PolicyError(f"{stats_file}: missing; the policy needs the observation statistics it was trained with")
    try:
        with open(stats_file, "rb") as f:
            stats = pickle.load(f)
        shape = stats.obs_rms.mean.shape
    except Exception as err:
        raise PolicyError(f"{stats_file}: not VecNormalize statistics: {err}") from err
    if not isinstance(stats, VecNormalize):
        raise PolicyError(f"{stats_file}: holds a {type(stats).__name__}, not VecNormalize statistics")
    from agents.privileged_critic import PrivilegedCriticPolicy, actor_only  # not at the top: it imports this module
    if shape == model.observation_space.shape and isinstance(model.policy, PrivilegedCriticPolicy):
        model, stats = actor_only(model, stats)  # trained with a privileged critic: the policy is its actor
        shape = stats.obs_rms.mean.shape
    if shape != model.observation_space.shape:
        raise PolicyError(f"{stats_file}: statistics for observations {shape}, but the model takes "
                          f"{model.observation_space.shape}: the two files come from different runs")
    sidecar_file = model_file.with_name(f"{model_file.stem}_{SIDECAR_FILE}")  # a run's checkpoint: step_N_sidecar.json
    if not sidecar_file.exists():
        sidecar_file = directory / SIDECAR_FILE
    if not sidecar_file.exists() and directory.name == CHECKPOINTS_DIR:
        raise PolicyError(f"{model_file}: a checkpoint without a sidecar (saved before checkpoints had one), so "
                          f"the environment it trained in is unknown; copy it with the run's "
                          f"{directory.parent / 'best' / SIDECAR_FILE} into a policy directory ({MODEL_FILE}, "
                          f"{STATS_FILE}, {SIDECAR_FILE}), checking that the run did not change its environment "
                          f"on resume")
    sidecar = json.loads(sidecar_file.read_text()) if sidecar_file.exists() else {}
    return MimicPolicy(directory, model, stats, sidecar, source=path)
