"""agents/policy.py: a loaded policy's deterministic action, computed in NumPy, is what
stable-baselines3's predict returns, follows weights changed in place, and falls back to predict
for an actor the shortcut does not cover; a policy write that fails leaves nothing behind."""

from pathlib import Path

import numpy as np
import pytest
import torch

from agents.policy import load_policy, mlp_mean_action

MODELS = Path(__file__).parents[1] / "models"


def test_policy_call_matches_predict_along_a_rollout_and_follows_the_current_weights():
    policy = load_policy(MODELS / "mimic_gait_ff")  # 22 actions: the key joints and both toes
    env = policy.make_env(["deepmimic:walk"])
    obs, _ = env.reset(seed=3)
    clipped = 0
    for _ in range(60):
        action = policy(obs)
        expected, _ = policy.model.predict(policy.normalizer.normalize_obs(obs), deterministic=True)
        assert action.shape == (22,) and action.dtype == np.float32
        np.testing.assert_allclose(action, expected, atol=2e-6)
        clipped += int(np.any(np.abs(action) >= policy.model.action_space.high - 1e-7))
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            obs, _ = env.reset()
    assert clipped >= 1  # some mean actions lay beyond the action limit, so the clipping was exercised
    before = policy(obs)
    with torch.no_grad():  # as a PPO update does: the weights change in place
        policy.model.policy.action_net.bias += 0.01
    np.testing.assert_allclose(policy(obs), np.clip(before + 0.01, -np.inf, policy.model.action_space.high), atol=2e-6)


def test_an_actor_the_shortcut_does_not_cover_falls_back_to_predict():
    policy = load_policy(MODELS / "mimic_walk")
    obs = np.zeros(policy.model.observation_space.shape, np.float32)
    net = policy.model.policy.mlp_extractor.policy_net
    assert mlp_mean_action(policy.model.policy, obs) is not None
    net[1] = torch.nn.ELU()  # no NumPy counterpart: the action must come from SB3's own forward pass
    assert mlp_mean_action(policy.model.policy, obs) is None
    expected, _ = policy.model.predict(policy.normalizer.normalize_obs(obs), deterministic=True)
    np.testing.assert_allclose(policy(obs), expected, atol=1e-7)


def test_a_policy_write_that_raises_leaves_no_folder_behind(tmp_path, monkeypatch):
    """save_policy writes into a temporary folder renamed in place of the target: when a write
    raises, no temporary folder is left, and an existing policy there stays as it was."""
    from agents import policy as policy_module
    from agents.sidecar import PolicySidecar

    walk = load_policy(MODELS / "mimic_walk")

    def broken(self, path):
        raise OSError("disk full")

    stats = walk.path / policy_module.STATS_FILE
    policy_module.save_policy(tmp_path / "out", walk.model, stats, walk.record)
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    monkeypatch.setattr(PolicySidecar, "save", broken)
    with pytest.raises(OSError, match="disk full"):
        policy_module.save_policy(tmp_path / "new", walk.model, stats, walk.record)
    with pytest.raises(OSError, match="disk full"):  # over an existing policy: that one stays whole
        policy_module.save_policy(tmp_path / "out", walk.model, stats, walk.record)
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == written
    assert load_policy(tmp_path / "out").record.env.env_id == walk.record.env.env_id


def test_a_failed_rename_puts_the_old_policy_back_and_leaves_no_folder(tmp_path, monkeypatch):
    from agents import policy as policy_module

    walk = load_policy(MODELS / "mimic_walk")
    stats = walk.path / policy_module.STATS_FILE
    policy_module.save_policy(tmp_path / "out", walk.model, stats, walk.record)
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    replace = policy_module.os.replace

    def failing(src, dst):  # setting the old policy aside works, putting the new one in place fails
        if str(src).endswith(".tmp"):
            raise OSError("rename failed")
        replace(src, dst)

    monkeypatch.setattr(policy_module.os, "replace", failing)
    with pytest.raises(OSError, match="rename failed"):
        policy_module.save_policy(tmp_path / "out", walk.model, stats, walk.record)
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == written
