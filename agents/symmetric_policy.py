"""PPO on the mirror-symmetric actor: an SB3 policy whose Gaussian mean is that actor's.

:class:`agents.mirror.MirrorAveraged` makes any trained policy mirror symmetric at run time,
``a(o) = ½ (π(o) + M_a π(M_o o))``; PPO, though, improved ``π``, not ``a``. This policy class puts
the same equation inside the network, so that PPO's rollouts, log-likelihoods and gradients are
those of the symmetric actor (``train_ppo.py --symmetric``; a warm start from a policy begins as
its symmetric actor, the halves unclipped):

* the actor runs once on the batch of observations and once on their mirror images (one pass on
  a batch twice as long) and averages the two means, the second mapped back by ``M_a``;
* the exploration noise's log σ is averaged with its mirror image too (``--action-variance``
  fixes it anyway);
* the critic is the plain one: a value needs no symmetry to serve as a baseline.

The network sees *normalised* observations, so ``M_o`` acts on them, which equals mirroring the raw
observation only when the observation statistics are themselves mirror symmetric:
``μ = M_o μ`` and ``σ = |M_o| σ``. :func:`symmetrise_statistics` makes them so (a warm start folds
the change into the first layers, :func:`agents.warm_start.renormalised_inputs`, so the network
acts on raw observations as before), and a run that trains this policy freezes them (they would drift off symmetry as they update), so the stored
policy acts as :class:`~agents.mirror.MirrorAveraged` of its own actor on raw observations, exactly:
:class:`~agents.policy.MimicPolicy` acts that way on any policy of this class.
"""

from __future__ import annotations

from typing import Any

import torch
from stable_baselines3.common.distributions import DiagGaussianDistribution, Distribution
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.running_mean_std import RunningMeanStd

from agents.mirror import MirrorMaps


def maps_as_kwargs(maps: MirrorMaps) -> dict[str, list]:
    """``maps`` as the policy's constructor argument ``mirror`` (plain lists: SB3 stores a policy's
    keyword arguments in its ``model.zip``)."""
    return {"obs_perm": maps.obs_perm.tolist(), "obs_sign": maps.obs_sign.tolist(),
            "action_perm": maps.action_perm.tolist(), "action_sign": maps.action_sign.tolist()}


class SymmetricActorCriticPolicy(ActorCriticPolicy):
    """SB3's ``ActorCriticPolicy`` (MLP actor and critic, diagonal Gaussian actions) whose action
    mean for normalised observations ``obs (N, D)`` is ``½ (μ(obs) + M_a μ(M_o obs))`` ``(N, A)``.

    Args:
        mirror: the maps of the environment's observation and action (:func:`maps_as_kwargs` of
            :meth:`agents.mirror.MirrorMaps.of`).
        *args, **kwargs: those of ``ActorCriticPolicy``.
    """

    def __init__(self, *args: Any, mirror: dict[str, list], **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.mirror_maps = MirrorMaps(**mirror)  # it takes the lists as arrays
        sizes = (len(self.mirror_maps.obs_perm), len(self.mirror_maps.action_perm))
        if sizes != (self.observation_space.shape[0], self.action_space.shape[0]):
            raise ValueError(f"mirror maps for observations ({sizes[0]},) and actions ({sizes[1]},); the policy "
                             f"takes {self.observation_space.shape} and acts {self.action_space.shape}")
        if not isinstance(self.action_dist, DiagGaussianDistribution):
            raise ValueError(f"the symmetric actor needs Gaussian actions, not {type(self.action_dist).__name__}")
        for name in ("obs_perm", "obs_sign", "action_perm", "action_sign"):  # move with the policy, not saved
            self.register_buffer(name, torch.as_tensor(getattr(self.mirror_maps, name)), persistent=False)

    def _get_constructor_parameters(self) -> dict[str, Any]:
        return {**super()._get_constructor_parameters(), "mirror": maps_as_kwargs(self.mirror_maps)}

    def symmetric_distribution(self, obs: torch.Tensor) -> Distribution:
        """The Gaussian of the symmetric actor for normalised observations ``obs (N, D)``."""
        both = torch.cat([obs, obs[:, self.obs_perm] * self.obs_sign])
        features = super().extract_features(both, self.pi_features_extractor)
        mean, mirrored = self.action_net(self.mlp_extractor.forward_actor(features)).chunk(2)
        mean = 0.5 * (mean + mirrored[:, self.action_perm] * self.action_sign)
        log_std = 0.5 * (self.log_std + self.log_std[self.action_perm])
        return self.action_dist.proba_distribution(mean, log_std)

    def forward(self, obs: torch.Tensor, deterministic: bool = False) -> tuple[torch.Tensor, ...]:
        distribution = self.symmetric_distribution(obs)
        actions = distribution.get_actions(deterministic=deterministic)
        log_prob = distribution.log_prob(actions)
        return actions.reshape((-1, *self.action_space.shape)), self.predict_values(obs), log_prob

    def evaluate_actions(self, obs: torch.Tensor, actions: torch.Tensor) -> tuple[torch.Tensor, ...]:
        distribution = self.symmetric_distribution(obs)
        return self.predict_values(obs), distribution.log_prob(actions), distribution.entropy()

    def get_distribution(self, obs: torch.Tensor) -> Distribution:
        return self.symmetric_distribution(obs)


def symmetrise_statistics(rms: RunningMeanStd, maps: MirrorMaps) -> RunningMeanStd:
    """Observation statistics ``rms`` (mean and variance ``(D,)``) made mirror symmetric: those of
    the observations it summarises pooled with their mirror images (mean ½ (μ + M_o μ); variance
    the mean of the two, the variance permuted, plus the spread of the two means). A copy."""
    symmetric = rms.copy()
    mirrored_mean = maps.observation(rms.mean)
    symmetric.mean = 0.5 * (rms.mean + mirrored_mean)
    symmetric.var = 0.5 * (rms.var + rms.var[maps.obs_perm]) + (0.5 * (rms.mean - mirrored_mean)) ** 2
    return symmetric
