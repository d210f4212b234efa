"""PPO with an asymmetric critic: the value network also reads what the policy cannot observe.

``train_ppo.py --privileged-critic`` appends each environment's
:meth:`envs.mimic.MimicEnv.privileged_observation` (the tracked reference's hidden corruption and the
episode's randomised body, :mod:`envs.privileged`) to the observation the rollouts store
(:class:`PrivilegedObservation`), and trains :class:`PrivilegedCriticPolicy`, whose actor reads the
first ``policy_inputs`` columns only and whose critic reads them all (Pinto et al. 2018, "Asymmetric
actor critic for image-based robot learning"). The actor is exactly a plain mimic policy's network,
so such a run's checkpoints load as their actor (:func:`actor_only`, which
:func:`agents.policy.load_policy` applies), and its ``best/`` and a shipped policy (``agents/ship.py``)
are written as the actor: evaluation, cleaning and every other command see a plain policy of the
environment's own observation, whose critic is the trained one without its privileged inputs.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from stable_baselines3.common.vec_env import DummyVecEnv, VecEnv, VecEnvWrapper, VecNormalize

from agents.policy import with_statistics


class PrivilegedObservation(VecEnvWrapper):
    """``venv``'s observations ``(N, D)`` with each environment's privileged features ``(N, P)`` after
    them: ``(N, D + P)`` float32. ``venv`` steps :class:`envs.mimic.MimicEnv` environments, whose
    ``privileged_observation`` is read after every reset and step (``env_method``: a call per
    environment in this process with ``--vec batched`` or ``dummy``, a round trip per shard with the
    sharded kinds).

    An episode that ended is reset inside the step, so its ``terminal_observation`` gets the features
    the environment put in ``info["privileged_observation"]`` when its time ran out (the only terminal
    observations PPO values, to bootstrap the truncation), else those of the step before (an episode
    that fell or lagged is not bootstrapped).
    """

    def __init__(self, venv: VecEnv):
        self.policy_inputs = int(venv.observation_space.shape[0])
        size = int(venv.get_attr("privileged_size", [0])[0])
        space = gym.spaces.Box(-np.inf, np.inf, (self.policy_inputs + size,), np.float32)
        super().__init__(venv, observation_space=space)
        self._last = np.zeros((venv.num_envs, size), np.float32)

    def _privileged(self) -> np.ndarray:
        return np.stack(self.venv.env_method("privileged_observation")).astype(np.float32)

    def reset(self) -> np.ndarray:
        obs = self.venv.reset()
        self._last = self._privileged()
        return np.concatenate([obs, self._last], axis=1)

    def step_wait(self):
        obs, rewards, dones, infos = self.venv.step_wait()
        for i in np.flatnonzero(dones):
            if "terminal_observation" in infos[i]:
                hidden = infos[i].get("privileged_observation", self._last[i])
                infos[i]["terminal_observation"] = np.concatenate([infos[i]["terminal_observation"], hidden])
        self._last = self._privileged()
        return np.concatenate([obs, self._last], axis=1), rewards, dones, infos


class ActorInputs(BaseFeaturesExtractor):
    """The actor's features: the first ``policy_inputs`` columns of the (flat) observation."""

    def __init__(self, observation_space: gym.spaces.Box, policy_inputs: int):
        super().__init__(observation_space, policy_inputs)
        self.policy_inputs = policy_inputs

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return observations[:, :self.policy_inputs]


class ScaledAdam(torch.optim.Adam):
    """Adam whose parameter groups may step at a multiple ``lr_scale`` (default 1) of the learning rate
    the training loop sets on every group (SB3 sets one rate, from its schedule, before each update)."""

    def step(self, closure=None):
        rates = [group["lr"] for group in self.param_groups]
        for group in self.param_groups:
            group["lr"] = group["lr"] * group.get("lr_scale", 1.0)
        try:
            return super().step(closure)
        finally:
            for group, rate in zip(self.param_groups, rates):
                group["lr"] = rate


class PrivilegedCriticPolicy(ActorCriticPolicy):
    """SB3's MLP actor-critic, its actor reading the first ``policy_inputs`` columns of the
    observation (the environment's own) and its critic every column (those and the privileged
    features). The two networks are separate (``share_features_extractor=False``), as ``MlpPolicy``'s
    are with ``net_arch`` ``{"pi": ..., "vf": ...}``. ``critic_lr_scale``: the critic's layers step at
    this multiple of PPO's learning rate (:class:`ScaledAdam`), so that a critic warm-started from a
    policy's learns to read its new inputs at a rate of its own while the actor moves as slowly as
    fine-tuning wants. Every other argument is ``ActorCriticPolicy``'s."""

    def __init__(self, observation_space: gym.spaces.Box, action_space: gym.spaces.Space, lr_schedule, *,
                 policy_inputs: int, critic_lr_scale: float = 1.0, **kwargs):
        if not 0 < policy_inputs < observation_space.shape[0]:
            raise ValueError(f"PrivilegedCriticPolicy: policy_inputs must be between 1 and the observation's "
                             f"{observation_space.shape[0]} columns less one, got {policy_inputs}")
        if not critic_lr_scale > 0:
            raise ValueError(f"PrivilegedCriticPolicy: critic_lr_scale must be > 0, got {critic_lr_scale}")
        self.policy_inputs, self.critic_lr_scale = policy_inputs, critic_lr_scale
        super().__init__(observation_space, action_space, lr_schedule, share_features_extractor=False, **kwargs)
        if critic_lr_scale != 1.0:
            critic = {id(p) for p in (*self.mlp_extractor.value_net.parameters(), *self.value_net.parameters())}
            groups = [{"params": [p for p in self.parameters() if id(p) not in critic]},
                      {"params": [p for p in self.parameters() if id(p) in critic], "lr_scale": critic_lr_scale}]
            self.optimizer = ScaledAdam(groups, lr=lr_schedule(1), **self.optimizer_kwargs)

    def _build_mlp_extractor(self) -> None:
        super()._build_mlp_extractor()  # both nets read features_dim columns; the actor's first layer fewer
        first = self.mlp_extractor.policy_net[0]
        self.mlp_extractor.policy_net[0] = torch.nn.Linear(self.policy_inputs, first.out_features)
        self.pi_features_extractor = ActorInputs(self.observation_space, self.policy_inputs)

    def _get_constructor_parameters(self) -> dict:
        return {**super()._get_constructor_parameters(), "policy_inputs": self.policy_inputs,
                "critic_lr_scale": self.critic_lr_scale}


class _Spaces(gym.Env):
    """An environment that has only spaces: what SB3 needs to build a model that will not be stepped."""

    def __init__(self, observation_space: gym.spaces.Space, action_space: gym.spaces.Space):
        self.observation_space, self.action_space = observation_space, action_space

    def reset(self, *, seed=None, options=None):
        raise RuntimeError("a model built by plain_model is not stepped")

    def step(self, action):
        raise RuntimeError("a model built by plain_model is not stepped")


SETTINGS = ("learning_rate", "lr_schedule", "n_steps", "batch_size", "n_epochs", "gamma", "gae_lambda", "clip_range",
            "clip_range_vf", "ent_coef", "vf_coef", "max_grad_norm", "target_kl", "seed", "num_timesteps")
"""The PPO settings and progress :func:`actor_only` carries over (what ``PPO.save`` stores and a run
started from the policy, e.g. ``agents/adaptation.py``, reads)."""


def plain_model(observation_space: gym.spaces.Box, action_space: gym.spaces.Box, policy_kwargs: dict,
                device: str | torch.device = "cpu") -> PPO:
    """A new ``MlpPolicy`` PPO model of these spaces with no environment to step (a vessel for weights;
    SB3's default settings). The global random generators are left as they were: no seed, and the
    initial weights drawn from a fork of torch's, so a training run that evaluates through one keeps
    its own stream."""
    kwargs = {k: v for k, v in policy_kwargs.items() if k not in ("policy_inputs", "critic_lr_scale")}
    with torch.random.fork_rng(devices=[]):
        return PPO("MlpPolicy", DummyVecEnv([lambda: _Spaces(observation_space, action_space)]), verbose=0,
                   policy_kwargs=kwargs, device=device)


def actor_only(model: PPO, statistics: VecNormalize) -> tuple[PPO, VecNormalize]:
    """A plain ``MlpPolicy`` PPO model and its observation statistics for the actor of ``model``, a
    :class:`PrivilegedCriticPolicy` with ``statistics`` over its ``D + P`` columns: the same actor and
    exploration noise, statistics of the first ``D`` columns, and the critic without its privileged
    inputs (their first-layer weights dropped: a value of the observation alone, for a run started
    from it, not the trained critic's estimate)."""
    policy = model.policy
    if not isinstance(policy, PrivilegedCriticPolicy):
        raise TypeError(f"actor_only: a model trained with a privileged critic, got a {type(policy).__name__}")
    d = policy.policy_inputs
    space = gym.spaces.Box(-np.inf, np.inf, (d,), np.float32)
    plain = plain_model(space, model.action_space, model.policy_kwargs, model.device)
    for name in SETTINGS:
        setattr(plain, name, getattr(model, name))
    weights = policy.state_dict()
    weights["mlp_extractor.value_net.0.weight"] = weights["mlp_extractor.value_net.0.weight"][:, :d]
    plain.policy.load_state_dict(weights)
    sliced = with_statistics(statistics, statistics.obs_rms.mean[:d].copy(), statistics.obs_rms.var[:d].copy())
    # detached from the training envs and not updating; what pickling drops given empty, so that it saves
    sliced.venv, sliced.training, sliced.class_attributes, sliced.returns = None, False, {}, None
    return plain, sliced


def widen_critic(model: PPO, source: PPO) -> None:
    """Start ``model`` (a :class:`PrivilegedCriticPolicy`) from ``source``, a plain policy of its first
    ``D`` columns: every weight copied, the critic's first layer reading the privileged columns with
    zero weights, so the run starts acting and valuing exactly as ``source``."""
    weights = source.policy.state_dict()
    key = "mlp_extractor.value_net.0.weight"
    old = weights[key]
    target = model.policy.state_dict()[key]
    if old.shape[1] != model.policy.policy_inputs or target.shape[0] != old.shape[0]:
        raise ValueError(f"widen_critic: the source's critic reads {old.shape[1]} inputs into {old.shape[0]} units; "
                         f"this run's critic reads {model.policy.policy_inputs} before its privileged ones into {target.shape[0]}")
    widened = torch.zeros_like(target)
    widened[:, :old.shape[1]] = old
    model.policy.load_state_dict({**weights, key: widened})
