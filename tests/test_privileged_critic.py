"""The asymmetric critic (``train_ppo.py --privileged-critic``): what it sees (envs/privileged.py), a
network whose actor cannot see it, the warm start, and a run's checkpoints loading as their actor."""

import shutil
from dataclasses import replace
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecNormalize

from agents.batched_vec_env import BatchedMimicVecEnv
from agents.policy import load_policy, mlp_mean_action
from agents.ship import _as_actor
from agents.privileged_critic import PrivilegedCriticPolicy, PrivilegedObservation, actor_only, widen_critic
from agents.train_ppo import main, newest_checkpoint, policy_kwargs
from envs.config import ArtefactMix, Dynamics, MimicConfig
from envs.physics import PhysicsDraw
from envs.privileged import PATH_STEPS, privileged_features, privileged_size

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


def _env(fraction: float, dynamics: Dynamics | None = None, episode_frames: int = 300) -> gym.Env:
    mix = ArtefactMix(strength=(1.0, 1.0), fraction=fraction, variants_per_clip=2, judge="clean_pose", seed=3)
    return gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=mix, dynamics=dynamics,
                    config=MimicConfig(episode_frames=episode_frames)).unwrapped


def test_privileged_features_of_hand_made_tracks():
    env = _env(0.0)
    env.reset(seed=0)
    track = env.current_track
    nu, nb, T = env.model.nu, env.model.nbody, env.current_track.n_frames
    quarter = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # world → a heading facing +y
    tracked = replace(track, to_heading=np.broadcast_to(quarter, (T, 3, 3)))
    ramp = np.arange(T)[:, None] * [0.01, 0.0, 0.0] + [0.0, -0.2, 0.0]  # the clean path pulls ahead 1 cm a frame
    clean = replace(track, com=track.com + ramp, com_vel=track.com_vel + [0.3, 0.0, 0.0])
    judged = replace(track, ctrl=track.ctrl - 0.05)
    body = PhysicsDraw(mass=np.full(nb, 1.1), friction=0.8, strength=np.full(nu, 0.9), offset=np.full(nu, 0.02))
    frame = T - 20  # 0, 4, 8, 16 frames ahead, and 32 clamped to the last frame
    features = privileged_features(tracked, judged, clean, frame, 2, body)
    assert features.shape == (privileged_size(nu, nb),) == (env.privileged_size,) and features.dtype == np.float32
    parts = np.split(features, np.cumsum([nu, 3 * len(PATH_STEPS), 3, nb, 1, nu]))
    np.testing.assert_allclose(parts[0], 0.05, atol=1e-6)  # tracked − judged hinge angles
    ahead = [frame, frame + 4, frame + 8, frame + 16, T - 1]
    expected = np.stack([[-0.2, -0.01 * f, 0.0] for f in ahead])  # clean − tracked: world +x is the heading's right
    np.testing.assert_allclose(parts[1].reshape(-1, 3), expected, atol=1e-6)
    np.testing.assert_allclose(parts[2], [0.0, -0.3, 0.0], atol=1e-6)
    np.testing.assert_allclose(np.concatenate(parts[3:6]), np.concatenate([[0.0], np.full(nb - 1, 0.1), [-0.2],
                                                                           np.full(nu, -0.1)]), atol=1e-6)
    np.testing.assert_allclose(parts[6], 0.02, atol=1e-7)
    with pytest.raises(ValueError, match="the clean track has 5 frames"):
        privileged_features(track, track, replace(track, motion=track.motion.with_qpos(track.motion.qpos[:5])), 0, 2,
                            body)


def test_a_clean_episode_on_the_nominal_body_hides_nothing_and_a_corrupted_one_does():
    clean, corrupted = _env(0.0), _env(1.0)
    clean.reset(seed=1)
    assert clean.variant_index == -1 and not clean.privileged_observation().any()
    corrupted.reset(seed=1)
    hidden = corrupted.privileged_observation()
    nu = corrupted.model.nu
    assert corrupted.variant_index >= 0
    assert np.abs(hidden[:nu]).max() > 0.01  # the suit's hinge errors, against the judged clean pose
    assert np.abs(hidden[nu:nu + 3 * len(PATH_STEPS)]).max() > 0.001  # its path, against the clean clip's
    body = _env(0.0, Dynamics(mass=0.1, friction=0.2, strength=0.1, offset_deg=2.0))
    body.reset(seed=2)
    drawn = body.privileged_observation()[nu + 3 * len(PATH_STEPS) + 3:]
    assert np.abs(drawn).max() > 0.01 and np.abs(drawn).max() < 0.21


def _privileged_model(venv, net: str = "16,16") -> PPO:
    kwargs = {**policy_kwargs(net, 0.03), "policy_inputs": venv.policy_inputs}
    return PPO(PrivilegedCriticPolicy, venv, n_steps=16, batch_size=16, policy_kwargs=kwargs, device="cpu", seed=0)


def test_the_actor_reads_its_own_observation_and_the_critic_also_the_privileged_columns():
    venv = PrivilegedObservation(BatchedMimicVecEnv([lambda: _env(1.0, episode_frames=40)] * 2, n_threads=1))
    try:
        obs = venv.reset()
        d, p = venv.policy_inputs, venv.get_attr("privileged_size", [0])[0]
        assert obs.shape == (2, d + p) and d == 273
        np.testing.assert_array_equal(obs[:, d:], np.stack(venv.env_method("privileged_observation")))
        model = _privileged_model(venv)
        policy = model.policy
        assert policy.mlp_extractor.policy_net[0].in_features == d
        assert policy.mlp_extractor.value_net[0].in_features == d + p
        changed = obs.copy()
        changed[:, d:] += 1.0
        actions = torch.zeros((2, venv.action_space.shape[0]))
        with torch.no_grad():
            seen = [(policy.get_distribution(o).distribution.mean, policy(o, deterministic=True)[0],
                     policy.evaluate_actions(o, actions)[1], policy.predict_values(o))
                    for o in (torch.as_tensor(obs), torch.as_tensor(changed))]
        for mine, other in list(zip(*seen))[:3]:  # every path the actor is read by: the same action
            torch.testing.assert_close(mine, other)
        np.testing.assert_array_equal(model.predict(obs, deterministic=True)[0], model.predict(changed, deterministic=True)[0])
        assert not torch.allclose(seen[0][3], seen[1][3])  # the critic reads them
        truncated = 0
        for _ in range(60):  # 40-frame episodes: the time limit after 20 control steps, unless it falls first
            before = obs
            obs, _, dones, infos = venv.step(np.zeros((2, venv.action_space.shape[0]), np.float32))
            for i in np.flatnonzero(dones):
                terminal = infos[i]["terminal_observation"]
                assert terminal.shape == (d + p,) and not np.array_equal(terminal[d:], obs[i, d:])
                if infos[i]["TimeLimit.truncated"]:  # valued by PPO: the features of its last state
                    truncated += 1
                    np.testing.assert_array_equal(terminal[d:], infos[i]["privileged_observation"])
                    assert not np.array_equal(terminal[d:], before[i, d:])
                else:  # not valued: the step before's
                    assert "privileged_observation" not in infos[i]
                    np.testing.assert_array_equal(terminal[d:], before[i, d:])
        assert truncated >= 2
    finally:
        venv.close()


def test_widen_critic_and_actor_only_keep_the_source():
    source = load_policy(WALK_POLICY)
    venv = PrivilegedObservation(BatchedMimicVecEnv([lambda: _env(1.0)] * 2, n_threads=1))
    try:
        obs = venv.reset()
        model = _privileged_model(venv, source.record.ppo.net)
        widen_critic(model, source.model)
        d = venv.policy_inputs
        with torch.no_grad():
            for o in obs:
                own = torch.as_tensor(o[None, :d])
                full = torch.as_tensor(o[None])
                torch.testing.assert_close(model.policy.predict_values(full), source.model.policy.predict_values(own))
                torch.testing.assert_close(model.policy.get_distribution(full).distribution.mean,
                                           source.model.policy.get_distribution(own).distribution.mean)
            model.policy.mlp_extractor.value_net[0].weight[:, d:].normal_()  # as if trained: the critic reads them
        statistics = VecNormalize(venv, norm_reward=False)  # the source's statistics and others for the critic's
        statistics.obs_rms.mean[:d], statistics.obs_rms.var[:d] = source.normalizer.obs_rms.mean, source.normalizer.obs_rms.var
        rngs = torch.random.get_rng_state(), np.random.get_state()[1].copy()
        plain, sliced = actor_only(model, statistics)
        assert torch.equal(torch.random.get_rng_state(), rngs[0]) and np.array_equal(np.random.get_state()[1], rngs[1])
        assert plain.observation_space.shape == (d,) and sliced.obs_rms.mean.shape == (d,)
        assert (plain.n_steps, plain.batch_size, plain.gamma) == (model.n_steps, model.batch_size, model.gamma)
        np.testing.assert_array_equal(sliced.obs_rms.var, source.normalizer.obs_rms.var)
        assert statistics.obs_rms.mean.shape == (d + venv.get_attr("privileged_size", [0])[0],)  # left as it was
        assert sliced.venv is None and not sliced.training
        with torch.no_grad():
            for o in obs:
                np.testing.assert_allclose(mlp_mean_action(plain.policy, o[:d]),
                                           mlp_mean_action(source.model.policy, o[:d]), atol=1e-6)
                blind = torch.as_tensor(np.concatenate([o[:d], np.zeros_like(o[d:])])[None])
                torch.testing.assert_close(plain.policy.predict_values(torch.as_tensor(o[None, :d])),
                                           model.policy.predict_values(blind))  # the critic without its extra inputs
        with pytest.raises(TypeError, match="a model trained with a privileged critic"):
            actor_only(source.model, source.normalizer)
        with pytest.raises(ValueError, match="the source's critic reads 273 inputs into 256 units; this run's critic "
                                             "reads 273 before its privileged ones into 32"):
            widen_critic(_privileged_model(venv, "32,32"), source.model)
    finally:
        venv.close()


def test_a_privileged_critic_run_starts_as_its_source_and_its_checkpoints_load_as_the_actor(tmp_path):
    """``train_ppo.py --privileged-critic --init-from``: at learning rate ~0 the checkpoint acts as the
    source, loads (and resumes) as a plain policy of the environment's observation, and its statistics
    of the critic's columns come from the run's resets; its best policy and a shipped checkpoint are
    plain policy directories."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    common = ["--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--lr", "1e-12",
              "--checkpoint-every", "128", "--eval-every", "128", "--eval-episodes", "1"]
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--privileged-critic", "--corrupted-fraction",
          "0.5", "--judge", "clean_pose", "--run-dir", str(run), "--total-steps", "128", *common])
    trained = PPO.load(newest_checkpoint(run), device="cpu")
    assert isinstance(trained.policy, PrivilegedCriticPolicy) and trained.observation_space.shape == (273 + 169,)
    policy = load_policy(newest_checkpoint(run))
    assert type(policy.model.policy).__name__ == "ActorCriticPolicy" and policy.model.observation_space.shape == (273,)
    assert policy.record.training.privileged_critic and not source.record.training.privileged_critic
    np.testing.assert_allclose(policy.normalizer.obs_rms.mean, source.normalizer.obs_rms.mean, atol=1e-4)  # 128 steps more
    env = policy.make_env(["deepmimic:walk"])
    obs, _ = env.reset(seed=5)
    np.testing.assert_allclose(policy(obs), source(obs), atol=1e-3)
    best = PPO.load(run / "best" / "model.zip", device="cpu")  # saved as the actor: every command reads it
    assert type(best.policy).__name__ == "ActorCriticPolicy" and best.observation_space.shape == (273,)
    shipped = tmp_path / "shipped"
    shipped.mkdir()
    checkpoint = newest_checkpoint(run)
    shutil.copy2(checkpoint, shipped / "model.zip")
    shutil.copy2(checkpoint.with_name(checkpoint.stem + "_vecnormalize.pkl"), shipped / "model_vecnormalize.pkl")
    shutil.copy2(checkpoint.with_name(checkpoint.stem + "_sidecar.json"), shipped / "sidecar.json")
    _as_actor(shipped)
    assert PPO.load(shipped / "model.zip", device="cpu").observation_space.shape == (273,)
    np.testing.assert_allclose(load_policy(shipped)(obs), policy(obs), atol=1e-6)
    with pytest.raises(SystemExit, match="its critic was trained with the privileged inputs; resume it with "
                                         "--privileged-critic"):
        main(["--run-dir", str(run), "--resume", "--total-steps", "256", "--no-progress", "--no-privileged-critic"])
    with pytest.raises(SystemExit, match="its critic learned at --critic-lr-scale 1; resume it with that"):
        main(["--run-dir", str(run), "--resume", "--total-steps", "256", "--no-progress", "--critic-lr-scale", "3"])
    main(["--run-dir", str(run), "--resume", "--total-steps", "256", "--no-progress"])  # one rollout of 2 × 64 more
    assert newest_checkpoint(run).name == "step_256.zip"
    assert isinstance(PPO.load(newest_checkpoint(run), device="cpu").policy, PrivilegedCriticPolicy)


@pytest.mark.parametrize("flag", [["--symmetric", "--init-from", str(WALK_POLICY)], ["--kickstart", "x.json"]])
def test_privileged_critic_refuses_what_reads_the_observations_as_the_policys(tmp_path, flag):
    with pytest.raises(SystemExit, match=f"--privileged-critic appends .* {flag[0]} reads them"):
        main(["--clips", "deepmimic:walk", "--privileged-critic", *flag, "--run-dir", str(tmp_path / "run")])
    assert not (tmp_path / "run").exists()


def test_the_critic_learns_at_its_own_rate(tmp_path):
    """``--critic-lr-scale``: one Adam step at learning rate ``lr`` moves the actor's weights by about
    ``lr`` and the critic's by about ``scale · lr`` (Adam's first step is ``lr · sign(g)``); the rate
    is the run's and cannot change on resume."""
    venv = PrivilegedObservation(BatchedMimicVecEnv([lambda: _env(1.0)] * 2, n_threads=1))
    try:
        kwargs = {**policy_kwargs("16,16", 0.03), "policy_inputs": venv.policy_inputs, "critic_lr_scale": 10.0}
        model = PPO(PrivilegedCriticPolicy, venv, n_steps=16, batch_size=16, n_epochs=1, learning_rate=1e-3,
                    policy_kwargs=kwargs, device="cpu", seed=0)
        policy = model.policy
        before = {name: p.detach().clone() for name, p in policy.named_parameters()}
        model.learn(32)  # one update: one epoch of two minibatches
        moved = {name: (p.detach() - before[name]).abs().max().item() for name, p in policy.named_parameters()}
        assert 1.5e-3 < moved["mlp_extractor.policy_net.0.weight"] < 2.5e-3  # two steps of 1e-3
        assert 1.5e-2 < moved["mlp_extractor.value_net.0.weight"] < 2.5e-2 and 1.5e-2 < moved["value_net.weight"] < 2.5e-2
        assert policy.optimizer.param_groups[1]["lr"] == policy.optimizer.param_groups[0]["lr"] == 1e-3  # as SB3 set it
        model.save(tmp_path / "model.zip")
        assert PPO.load(tmp_path / "model.zip", device="cpu").policy.critic_lr_scale == 10.0
    finally:
        venv.close()
    with pytest.raises(SystemExit, match="--critic-lr-scale sets the privileged critic's learning rate; give "
                                         "--privileged-critic"):
        main(["--clips", "deepmimic:walk", "--critic-lr-scale", "5", "--run-dir", str(tmp_path / "run")])
