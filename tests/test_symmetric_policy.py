"""PPO on the mirror-symmetric actor (agents/symmetric_policy.py, ``train_ppo.py --symmetric``): the
network's Gaussian is mirror symmetric whatever its weights, its statistics are those of the data
pooled with its mirror image, and a warm-started run acts as the source's symmetric actor."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.running_mean_std import RunningMeanStd

import envs  # noqa: F401  (registers the ids)
from agents.mirror import MirrorMaps
from agents.adaptation import AdaptConfig, adapt_policy
from agents.average_policies import average_policies
from agents.policy import PolicyError, load_policy, mlp_mean_action
from agents.symmetric_policy import SymmetricActorCriticPolicy, maps_as_kwargs, symmetrise_statistics
from agents.train_ppo import main, newest_checkpoint, policy_kwargs
from reference_motion.library import load_motion

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


@pytest.fixture(scope="module")
def env():
    environment = gym.make("MimicIMU-v0", clips=[load_motion("deepmimic:walker/turn_left0")], artefacts=None)
    yield environment
    environment.close()


def test_the_networks_gaussian_is_mirror_symmetric_whatever_its_weights(env):
    """Random weights (far from symmetric): the mean for a mirrored observation is the mirrored mean,
    and the log-likelihood of a mirrored action under it is the same, to float precision."""
    maps = MirrorMaps.of(env)
    torch.manual_seed(0)
    kwargs = {**policy_kwargs("32,32", 0.03), "mirror": maps_as_kwargs(maps)}
    policy = PPO(SymmetricActorCriticPolicy, env, policy_kwargs=kwargs, n_steps=64, batch_size=64, device="cpu").policy
    with torch.no_grad():
        policy.action_net.weight.normal_()  # SB3 starts it near zero
        policy.log_std.copy_(torch.linspace(-2.0, -1.0, len(maps.action_perm)))  # not symmetric either
    obs = np.random.default_rng(1).normal(size=(5, len(maps.obs_perm))).astype(np.float32)
    mirrored = obs[:, maps.obs_perm] * maps.obs_sign
    actions = torch.as_tensor(np.random.default_rng(2).normal(0, 0.3, (5, len(maps.action_perm))).astype(np.float32))
    with torch.no_grad():
        gauss = policy.get_distribution(torch.as_tensor(obs))  # SB3 reuses one distribution object: read it now
        mean, log_p = gauss.distribution.mean.numpy().copy(), gauss.log_prob(actions).numpy()
        gauss = policy.get_distribution(torch.as_tensor(mirrored))
        mean_m = gauss.distribution.mean.numpy()
        log_p_m = gauss.log_prob(actions[:, torch.as_tensor(maps.action_perm)] * torch.as_tensor(maps.action_sign))
        assert np.abs(mean - mean_m).max() > 0.1  # the observations differ, and so do the means
        np.testing.assert_allclose(mean_m, mean[:, maps.action_perm] * maps.action_sign, atol=1e-5)
        np.testing.assert_allclose(log_p_m.numpy(), log_p, rtol=1e-5)
        # the actor half alone: its own mean on obs, and the mirror of its mean on the mirrored obs, averaged
        halves = [mlp_mean_action(policy, o) for o in (obs, mirrored)]
        np.testing.assert_allclose(mean, 0.5 * (halves[0] + halves[1][:, maps.action_perm] * maps.action_sign),
                                   atol=1e-5)


def test_symmetrised_statistics_are_those_of_the_data_pooled_with_its_mirror_image(env):
    maps = MirrorMaps.of(env)
    data = np.random.default_rng(3).normal(1.0, 2.0, (400, len(maps.obs_perm))) * np.linspace(0.5, 2.0,
                                                                                              len(maps.obs_perm))
    rms = RunningMeanStd(shape=data.shape[1:])
    rms.update(data)
    pooled = np.concatenate([data, data[:, maps.obs_perm] * maps.obs_sign])
    symmetric = symmetrise_statistics(rms, maps)
    np.testing.assert_allclose(symmetric.mean, pooled.mean(axis=0), atol=1e-6)
    np.testing.assert_allclose(symmetric.var, pooled.var(axis=0), rtol=1e-6)
    np.testing.assert_allclose(maps.observation(symmetric.mean), symmetric.mean, atol=1e-12)
    assert rms.mean[maps.obs_sign < 0].any()  # the input was not symmetric (a copy is returned)


def test_a_symmetric_run_starts_as_the_sources_symmetric_actor_and_keeps_its_statistics(tmp_path, env):
    """``train_ppo.py --symmetric --init-from``: at learning rate ~0 the checkpoint acts as the
    source's two mirror halves, each on the source's own statistics, averaged (the first layers
    absorbed the statistics made symmetric, which stay frozen); load_policy acts with it (its
    deterministic action is the Gaussian's mean, clipped)."""
    source = load_policy(WALK_POLICY)
    maps = MirrorMaps.of(env)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--symmetric", "--mirror", "--run-dir",
          str(run), "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--total-steps",
          "128", "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "1000"])
    policy = load_policy(newest_checkpoint(run))
    assert policy.symmetric_network and policy.record.training.symmetric and policy.mirror is None
    expected = symmetrise_statistics(source.normalizer.obs_rms, maps)
    assert np.abs(expected.var / source.normalizer.obs_rms.var - 1).max() > 0.1  # the source's were not symmetric
    np.testing.assert_allclose(policy.normalizer.obs_rms.mean, expected.mean)  # frozen while it trained
    np.testing.assert_allclose(policy.normalizer.obs_rms.var, expected.var)
    obs, _ = env.reset(seed=4)
    halves = [mlp_mean_action(source.model.policy, np.asarray(source.normalizer.normalize_obs(o), dtype=np.float32))
              for o in (obs, maps.observation(obs))]
    space = policy.model.action_space
    symmetric = np.clip(0.5 * (halves[0] + maps.action(halves[1])), space.low, space.high)
    np.testing.assert_allclose(policy(obs), symmetric, atol=1e-4)
    np.testing.assert_allclose(policy(maps.observation(obs)), maps.action(policy(obs)), atol=1e-5)
    action, _ = policy.model.predict(np.asarray(policy.normalizer.normalize_obs(obs), dtype=np.float32),
                                     deterministic=True)
    np.testing.assert_allclose(policy(obs), action, atol=1e-5)
    assert policy.mirror_averaged(env) is policy  # already that actor
    with pytest.raises(PolicyError, match=r"checkpoints/step_\d+\.zip: trained as the symmetric actor .* the others not"):
        average_policies([source, policy])
    with pytest.raises(ValueError, match="needs its mirror-symmetric observation statistics frozen"):
        adapt_policy(policy, load_motion("deepmimic:walk"), AdaptConfig(update_normalizer=True))
    with pytest.raises(SystemExit, match="a network trained as the symmetric actor; train on with --symmetric"):
        main(["--clips", "deepmimic:walk", "--init-from", str(newest_checkpoint(run)), "--run-dir",
              str(tmp_path / "plain")])
    assert not (tmp_path / "plain").exists()
    with pytest.raises(SystemExit, match="its network was trained as the symmetric actor; resume it with --symmetric"):
        main(["--run-dir", str(run), "--resume", "--no-symmetric", "--total-steps", "256"])


def test_symmetric_needs_a_policy_to_start_from(tmp_path):
    with pytest.raises(SystemExit, match="--symmetric trains the symmetric actor of a trained policy: give "
                                         "--init-from"):
        main(["--clips", "deepmimic:walk", "--symmetric", "--run-dir", str(tmp_path / "run"), "--total-steps", "64"])
    assert not (tmp_path / "run").exists()
