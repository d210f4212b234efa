"""Warm-starting a PPO run from a trained policy (``train_ppo.py --init-from``), also across an
observation that gained inputs.

A policy trained on ADAPT's world-frame observation (:mod:`envs.observations`) can be carried to
the same observation with ``dp_com`` (``MimicConfig.com_offset``): the first layer of actor and
critic gets zero weights for the new inputs, so the widened network computes exactly what the
source did until training gives those inputs weight, and the observation statistics get a
neutral entry for them. Any other mismatch of spaces is an error.
"""

from __future__ import annotations

import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecEnv, VecNormalize

from agents.policy import MimicPolicy, PolicyError
from envs.config import MimicConfig
from envs.observations import observation_slices

FIRST_LAYERS = ("mlp_extractor.policy_net.0.weight", "mlp_extractor.value_net.0.weight")
"""Parameters of SB3's ``MlpPolicy`` that read the observation: ``(hidden, D)`` each."""

COM_OFFSET_STD_M = 0.2
"""Running std (m) given to each new ``dp_com`` input: the offsets a tracking policy lives with are
0–0.9 m (the lag termination is at ~0.9 m of head distance), so normalised inputs are near unit
size. The statistics keep the source's count (tens of millions of steps), so this scale stays
all but fixed for the rest of the run (0.200 / 0.200 / 0.192 m after 2.4 M steps)."""


def observation_normalizer(venv: VecEnv, gamma: float) -> VecNormalize:
    """The running observation normalisation every run uses (observations only, not rewards)."""
    return VecNormalize(venv, norm_obs=True, norm_reward=False, gamma=gamma)


def widen_inputs(state_dict: dict[str, torch.Tensor], insert_at: int, n_new: int) -> dict[str, torch.Tensor]:
    """A copy of an SB3 ``MlpPolicy`` ``state_dict`` whose first layers (:data:`FIRST_LAYERS`) take
    ``n_new`` more inputs at index ``insert_at``, with zero weights: the widened network's outputs
    equal the source's for any values of the new inputs."""
    out = dict(state_dict)
    for name in FIRST_LAYERS:
        if name not in state_dict:
            raise PolicyError(f"warm start: the source policy has no {name!r}; not an SB3 MlpPolicy")
        weight = state_dict[name]
        if not 0 <= insert_at <= weight.shape[1]:
            raise PolicyError(f"warm start: cannot insert inputs at {insert_at} into {name} of {weight.shape[1]} inputs")
        zeros = weight.new_zeros(weight.shape[0], n_new)
        out[name] = torch.cat([weight[:, :insert_at], zeros, weight[:, insert_at:]], dim=1)
    return out


def widen_statistics(mean: np.ndarray, var: np.ndarray, insert_at: int, new_var: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Running observation mean and variance ``(D,)`` with entries for ``len(new_var)`` new inputs at
    ``insert_at`` (mean 0, variance ``new_var``)."""
    new_var = np.asarray(new_var, dtype=var.dtype)
    return (np.insert(mean, insert_at, np.zeros_like(new_var)), np.insert(var, insert_at, new_var))


def warm_start(model: PPO, venv: VecEnv, source: MimicPolicy, config: MimicConfig, gamma: float) -> VecNormalize:
    """Load ``source``'s weights into ``model`` (a new run on ``venv``, whose environments use
    ``config``) and return ``venv`` wrapped in ``source``'s observation statistics.

    The spaces must match, or differ only by ``dp_com``: ``config`` observes it and the source's
    environment did not (then the inputs are widened, see the module docstring)."""
    sizes = venv.observation_space.shape, source.model.observation_space.shape
    source_config = source.record.env.mimic_config()
    if config.obs_frame != source_config.obs_frame:  # same sizes possible (heading vs world + dp_com)
        raise PolicyError(f"{source.path}: observed in the {source_config.obs_frame!r} frame; a warm start cannot "
                          f"change the frame to {config.obs_frame!r}")
    span = observation_slices(1, 1, com_offset=True)["dp_com"]
    n_new = span.stop - span.start
    gained = config.observes_com_offset and not source_config.observes_com_offset
    state, rms = source.model.policy.state_dict(), source.normalizer.obs_rms.copy()
    widen = (gained and sizes[0][0] == sizes[1][0] + n_new
             and venv.action_space.shape == source.model.action_space.shape)
    if widen:
        state = widen_inputs(state, span.start, n_new)
        rms.mean, rms.var = widen_statistics(rms.mean, rms.var, span.start, np.full(n_new, COM_OFFSET_STD_M**2))
        print(f"widening {source.path}'s inputs by dp_com (zero weights at {span.start}:{span.stop})", flush=True)
    else:
        source.check_env(venv)  # raises PolicyError naming the mismatch, unless the spaces match
    model.policy.load_state_dict(state)
    normalizer = observation_normalizer(venv, gamma)
    normalizer.obs_rms = rms
    return normalizer

