"""BatchedMimicVecEnv (agents/batched_vec_env.py): the same transitions as the same envs stepped one at
a time (DummyVecEnv), through resets, unstable steps and every observation layout; bad batches refused."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import DummyVecEnv

import envs  # noqa: F401  (registers the ids)
from agents.batched_vec_env import BatchedMimicVecEnv, BatchShard
from agents.train_ppo import UpdateThreads, build_parser, vec_env_settings, vec_kind
from agents.vec_env import ShardedVecEnv
from envs import ArtefactMix, MimicConfig, MimicEnv
from envs.config import Dynamics, Pushes

CLIPS = ["deepmimic:walk", "deepmimic:run"]


def make(vec_env_cls, config: MimicConfig = MimicConfig(), n_envs: int = 3, judge: str = "corrupted",
         pushes: Pushes | None = None, dynamics: Dynamics | None = None, **vec_kwargs):
    kwargs = {"clips": CLIPS, "artefacts": ArtefactMix(seed=0, variants_per_clip=1, judge=judge), "config": config,
              "pushes": pushes, "dynamics": dynamics}
    return make_vec_env("MimicIMU-v0", n_envs=n_envs, seed=7, vec_env_cls=vec_env_cls, env_kwargs=kwargs,
                        vec_env_kwargs=vec_kwargs or None)


def assert_same_transitions(batched, dummy, steps: int, scale: float = 0.3) -> dict[str, int]:
    """Step both with the same random actions; every observation, reward, done and info entry the
    envs fill must agree. Returns how often each episode ending occurred."""
    actions = np.random.default_rng(0).normal(0, scale, (steps, batched.num_envs, batched.action_space.shape[0]))
    np.testing.assert_array_equal(batched.reset(), dummy.reset())
    endings: dict[str, int] = {}
    for a in actions.astype(np.float32):
        obs_b, rew_b, done_b, info_b = batched.step(a)
        obs_d, rew_d, done_d, info_d = dummy.step(a)
        np.testing.assert_array_equal(obs_b, obs_d)
        np.testing.assert_allclose(rew_b, rew_d, rtol=1e-6, atol=1e-7)
        np.testing.assert_array_equal(done_b, done_d)
        for ib, id_ in zip(info_b, info_d):
            for key in ("frame", "episode_frame", "clip", "corrupted", "ended_by", "unstable", "TimeLimit.truncated"):
                assert ib[key] == id_[key], key
            np.testing.assert_array_equal(ib["contacts"], id_["contacts"])
            for key in ("r_local", "r_p", "r_v", "r_still", "r_com", "e_discount", "reward"):
                assert ib[key] == pytest.approx(id_[key], rel=1e-9, abs=1e-12), key
            if "terminal_observation" in id_:
                np.testing.assert_array_equal(ib["terminal_observation"], id_["terminal_observation"])
                assert ib["episode"]["l"] == id_["episode"]["l"]
                assert ib["episode"]["r"] == pytest.approx(id_["episode"]["r"], abs=1e-5)
                endings[id_["ended_by"]] = endings.get(id_["ended_by"], 0) + 1
            else:
                assert "terminal_observation" not in ib and "episode" not in ib
    batched.close()
    dummy.close()
    return endings


def test_a_batch_steps_exactly_as_its_envs_one_at_a_time_through_resets():
    endings = assert_same_transitions(make(BatchedMimicVecEnv, n_threads=2), make(DummyVecEnv), steps=80)
    assert sum(endings.values()) >= 3  # random actions fall: the auto-reset path ran


def test_corrupted_episodes_judged_against_the_clean_clip_batch_alike():
    """Half the episodes corrupted, judged against the clean clip: the batch's rewards come from the
    clean tracks, its observations from the corrupted ones, as each env's own do."""
    batched, dummy = make(BatchedMimicVecEnv, judge="clean", n_threads=2), make(DummyVecEnv, judge="clean")
    assert_same_transitions(batched, dummy, steps=60)


@pytest.mark.parametrize("config", [MimicConfig(obs_frame="heading"), MimicConfig(obs_frame="reference"),
                                    MimicConfig(com_offset=True), MimicConfig(velocity_feedforward=True),
                                    MimicConfig(obs_frame="reference", lookahead=(1, 4, 10), lookbehind=(2, 8)),
                                    MimicConfig(physics_rate_hz=240.0, still_feet_weight=2.0),
                                    MimicConfig(obs_frame="reference", steer_gain_hz=1.0),
                                    MimicConfig(obs_frame="reference", steer_gain_hz=1.0, com_velocity_weight=1.0)],
                         ids=["heading", "reference", "com_offset", "feedforward", "window", "still_feet_240hz",
                              "steering", "com_velocity"])
def test_every_observation_layout_the_velocity_feedforward_and_the_still_feet_term_batch_alike(config):
    assert_same_transitions(make(BatchedMimicVecEnv, config, n_threads=2), make(DummyVecEnv, config), steps=40)


def test_random_pushes_batch_alike():
    pushes = Pushes(force_n=(150.0, 300.0), rate_hz=3.0)  # often and hard: the pushes decide who falls
    assert_same_transitions(make(BatchedMimicVecEnv, pushes=pushes), make(DummyVecEnv, pushes=pushes), steps=60)


def test_randomised_bodies_batch_alike():
    bodies = Dynamics(mass=0.3, friction=0.5, strength=0.3, offset_deg=5.0)  # far from nominal: episodes end
    endings = assert_same_transitions(make(BatchedMimicVecEnv, dynamics=bodies, n_threads=2),
                                      make(DummyVecEnv, dynamics=bodies), steps=60)
    assert sum(endings.values()) >= 1


def test_an_unstable_simulation_ends_its_episode_in_the_batch_as_alone():
    fragile = MimicConfig(max_joint_speed=6.0)  # any brisk joint motion counts as a blow-up
    endings = assert_same_transitions(make(BatchedMimicVecEnv, fragile, n_threads=2), make(DummyVecEnv, fragile),
                                      steps=30, scale=1.0)
    assert endings.get("unstable", 0) >= 1


def test_batches_in_worker_processes_step_exactly_as_their_envs_one_at_a_time():
    """--vec sharded-batched: a batch in this process and one in a worker, episodes ending on both."""
    sharded = make(ShardedVecEnv, n_envs=4, n_workers=2, shard=BatchShard)
    assert [len(s) for s in sharded.shards] == [2, 2] and isinstance(sharded.local, BatchShard)
    sharded.set_attr("marker", "y", indices=[3])
    assert sharded.get_attr("marker", indices=[3]) == ["y"]  # reached the worker's batch
    endings = assert_same_transitions(sharded, make(DummyVecEnv, n_envs=4), steps=60)
    assert sum(endings.values()) >= 3


def test_calls_reach_the_envs_and_the_batch_runs_on_its_threads():
    venv = make(BatchedMimicVecEnv, n_envs=5, n_threads=2)
    assert venv.shards == [[0, 1, 2], [3, 4]]
    venv.set_attr("marker", "x", indices=[3])
    assert venv.get_attr("marker", indices=[3]) == ["x"]
    assert venv.has_attr("marker") is False
    venv.reset()
    assert venv.env_method("last_start", 0) == [venv.envs[0].last_start(0)] * 5
    venv.close()


def test_batches_it_cannot_step_alike_are_refused():
    class OwnReward(MimicEnv):  # as MimicGaitEnv: a subclass may reward and observe otherwise
        pass

    with pytest.raises(ValueError, match="env 0 is a OwnReward"):
        BatchedMimicVecEnv([lambda: OwnReward(clips=CLIPS)])
    fns = [lambda: MimicEnv(clips=CLIPS), lambda: MimicEnv(clips=CLIPS, obs_mode="drecon")]
    with pytest.raises(ValueError, match="env 1 differs from env 0"):
        BatchedMimicVecEnv(fns)
    with pytest.raises(ValueError, match="at least one environment"):
        BatchedMimicVecEnv([])
    with pytest.raises(ValueError, match="n_threads must be >= 1"):
        BatchedMimicVecEnv([lambda: MimicEnv(clips=CLIPS)], n_threads=0)
    with pytest.raises(ValueError, match="wrapped in TimeLimit, which BatchedMimicVecEnv would skip"):
        BatchedMimicVecEnv([lambda: gym.wrappers.TimeLimit(MimicEnv(clips=CLIPS), 10)])


def test_an_env_with_a_recording_hook_is_not_stepped_in_a_batch():
    venv = make(BatchedMimicVecEnv, n_envs=2, n_threads=1)
    venv.reset()
    venv.envs[1].frame_hook = lambda data: None
    with pytest.raises(RuntimeError, match="env 1 has a frame_hook"):
        venv.step(np.zeros((2, venv.action_space.shape[0]), dtype=np.float32))
    venv.close()


def test_train_ppo_batches_mimic_tasks_by_default_and_refuses_to_batch_the_gait_task():
    parser = build_parser()
    assert vec_kind(parser.parse_args(["--run-dir", "r"])) == "batched"
    shards = parser.parse_args(["--run-dir", "r", "--n-envs", "32", "--vec", "sharded-batched"])
    cls, kwargs, collect, update = vec_env_settings(shards)
    assert cls is ShardedVecEnv and kwargs["shard"] is BatchShard and (collect, update) == (1, kwargs["n_workers"])
    assert vec_kind(parser.parse_args(["--run-dir", "r", "--env-id", "MimicGait-v0"])) == "sharded"
    for kind in ("batched", "sharded-batched"):
        with pytest.raises(ValueError, match=f"--vec {kind} steps MimicEnv's own reward"):
            vec_kind(parser.parse_args(["--run-dir", "r", "--env-id", "MimicGait-v0", "--vec", kind]))


def test_the_learner_gets_its_update_threads_only_between_rollouts_and_its_own_back_after():
    before = torch.get_num_threads()
    switch = UpdateThreads(collect=1, update=2)
    try:
        torch.set_num_threads(3)
        switch._on_training_start()
        switch._on_rollout_end()
        assert torch.get_num_threads() == 2
        switch._on_rollout_start()
        assert torch.get_num_threads() == 1
        switch._on_training_end()
        assert torch.get_num_threads() == 3
    finally:
        torch.set_num_threads(before)
