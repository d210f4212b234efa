"""ShardedVecEnv (agents/vec_env.py): the same transitions as DummyVecEnv, env calls in env order,
worker errors surfaced with their cause."""

from __future__ import annotations

import os
import time

import numpy as np
import pytest
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.monitor import Monitor
from stable_baselines3.common.vec_env import DummyVecEnv

import envs  # noqa: F401  (registers the ids)
from agents.vec_env import ShardedVecEnv, WorkerError, shard_count
from envs import ArtefactMix

KWARGS = {"clips": ["deepmimic:walk", "deepmimic:run"], "artefacts": ArtefactMix(seed=0, variants_per_clip=1)}


def make(vec_env_cls, **vec_kwargs):
    return make_vec_env("MimicIMU-v0", n_envs=3, seed=7, vec_env_cls=vec_env_cls, env_kwargs=KWARGS,
                        vec_env_kwargs=vec_kwargs or None)


@pytest.fixture(scope="module")
def sharded():
    venv = make(ShardedVecEnv, n_workers=2)
    yield venv
    venv.close()


def test_sharded_steps_like_dummy_through_resets(sharded):
    dummy = make(DummyVecEnv)
    actions = np.random.default_rng(0).normal(0, 0.3, (60, 3, dummy.action_space.shape[0])).astype(np.float32)
    np.testing.assert_array_equal(sharded.reset(), dummy.reset())
    episodes_ended = 0
    for a in actions:
        obs_s, rew_s, done_s, info_s = sharded.step(a)
        obs_d, rew_d, done_d, info_d = dummy.step(a)
        np.testing.assert_array_equal(obs_s, obs_d)
        np.testing.assert_array_equal(rew_s, rew_d)
        np.testing.assert_array_equal(done_s, done_d)
        for i in np.flatnonzero(done_s):
            np.testing.assert_array_equal(info_s[i]["terminal_observation"], info_d[i]["terminal_observation"])
            assert info_s[i]["ended_by"] == info_d[i]["ended_by"]
        episodes_ended += int(done_s.sum())
    assert episodes_ended >= 3  # the auto-reset path ran (random actions fell within 60 steps)
    dummy.close()


def test_calls_reach_the_right_envs_in_order(sharded):
    assert sharded.shards == [[0, 1], [2]]  # env 2 lives in the worker
    sharded.set_attr("marker", "worker", indices=[2])
    sharded.set_attr("marker", "local", indices=[0])
    assert sharded.get_attr("marker", indices=[2, 0]) == ["worker", "local"]
    assert sharded.has_attr("marker") is False  # env 1 has none: an AttributeError, not a WorkerError
    assert [t.n_frames > 0 for t in sharded.env_method("get_wrapper_attr", "current_track")] == [True] * 3
    assert sharded.env_is_wrapped(Monitor) == [True, True, True]


def test_worker_error_names_the_cause(sharded):
    with pytest.raises(WorkerError, match="unknown clip 'no-such-clip'"):
        sharded.env_method("reset", options={"clip": "no-such-clip"}, indices=[2])


def test_bad_worker_count():
    with pytest.raises(ValueError, match="n_workers must be 1..3"):
        make(ShardedVecEnv, n_workers=4)


def test_close_after_an_interrupted_step_returns():
    """``kill`` / Ctrl-C between sending a step and reading it: close() reads what the worker owes
    instead of waiting for an answer that never comes (an earlier version hung here)."""
    venv = make(ShardedVecEnv, n_workers=2)
    venv.reset()
    venv.step_async(np.zeros((3, venv.action_space.shape[0]), np.float32))
    start = time.perf_counter()
    venv.close()
    assert time.perf_counter() - start < 5.0
    assert not any(p.is_alive() for p in venv.processes)


def test_after_a_worker_error_the_other_workers_answers_are_not_left_behind():
    venv = make(ShardedVecEnv, n_workers=3)  # one env per shard: two workers
    try:
        venv.reset()
        with pytest.raises(WorkerError, match="unknown clip"):
            venv.env_method("reset", options={"clip": "no-such-clip"}, indices=[1])
        assert venv.get_attr("render_mode") == ["rgb_array"] * 3  # the next call reads its own answers
    finally:
        venv.close()


def test_shard_count_defaults_to_the_cores_and_never_exceeds_the_envs():
    cores = len(os.sched_getaffinity(0))
    assert shard_count(None, 64) == min(cores, 64)
    assert shard_count(16, 8) == 8 and shard_count(3, 8) == 3
