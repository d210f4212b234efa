"""BF16UpdatePPO (agents/mixed_precision.py): updates multiply in bfloat16, everything kept is fp32."""

from __future__ import annotations

import pytest
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_util import make_vec_env

import envs  # noqa: F401  (registers the ids)
from agents.mixed_precision import BF16UpdatePPO, ppo_class


def small_ppo(cls):
    venv = make_vec_env("MimicIMU-v0", n_envs=2, seed=0, env_kwargs={"clips": ["deepmimic:walk"]})
    return cls("MlpPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu",
               policy_kwargs={"net_arch": {"pi": [32, 32], "vf": [32, 32]}})


def test_updates_multiply_in_bfloat16_and_keep_fp32_weights(tmp_path):
    model = small_ppo(BF16UpdatePPO)
    seen: list[torch.dtype] = []
    layer = model.policy.mlp_extractor.policy_net[0]
    handle = layer.register_forward_hook(lambda module, inputs, output: seen.append(output.dtype))
    before = layer.weight.detach().clone()
    model.learn(128)
    handle.remove()
    assert torch.bfloat16 in seen  # the update's forward passes (rollouts run in fp32)
    assert torch.float32 in seen
    assert layer.weight.dtype == torch.float32 and not torch.equal(layer.weight.detach(), before)  # it learned
    assert all(p.dtype == torch.float32 for p in model.policy.parameters())
    model.save(tmp_path / "m.zip")
    plain = PPO.load(tmp_path / "m.zip", device="cpu")  # a checkpoint of either loads into the other
    assert torch.equal(plain.policy.mlp_extractor.policy_net[0].weight, layer.weight.detach())


def test_precision_names():
    assert ppo_class("fp32") is PPO and ppo_class("bf16") is BF16UpdatePPO
    with pytest.raises(ValueError, match="update precision must be one of fp32, bf16"):
        ppo_class("fp16")
