"""Adaptation episodes that start from a whole performance's simulated states
(:mod:`agents.performed_starts`), with the shipped walk policy."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from agents import adaptation
from agents.adaptation import AdaptConfig, adapt_policy, adaptation_key
from agents.clean import perform_clip
from agents.performed_starts import PerformedStarts, performed_start_frames
from agents.policy import load_policy
from agents.rollout import run_episode
from reference_motion.library import load_motion

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


@pytest.fixture(scope="module")
def walk_policy():
    return load_policy(WALK_POLICY)


def test_starts_are_the_window_before_each_failure_without_the_anchors():
    frames = performed_start_frames(failures=[100, 30], anchors=[0, 90], n_frames=200, window=20, latest=150)
    expected = sorted(set(range(80, 100)) - {90} | set(range(10, 30)))
    np.testing.assert_array_equal(frames, expected)
    # windows that overlap give each frame once; a window reaching before the clip is cut at 0
    np.testing.assert_array_equal(performed_start_frames([12, 15], [], 200, 10, 150), np.arange(2, 15))
    np.testing.assert_array_equal(performed_start_frames([5], [], 200, 10, 150), np.arange(0, 5))
    # no later than `latest` (a failure near the clip's end)
    np.testing.assert_array_equal(performed_start_frames([199], [], 200, 10, 195), np.arange(189, 196))


def test_with_no_failure_every_simulated_frame_is_a_start():
    np.testing.assert_array_equal(performed_start_frames([], [0], n_frames=50, window=20, latest=40),
                                  np.arange(1, 41))
    with pytest.raises(ValueError, match="window must be at least one frame, got 0"):
        performed_start_frames([10], [], 50, 0, 40)


def test_resets_start_from_the_given_states(walk_policy, walk):
    """fraction 1: every reset without options starts at a given frame from its simulated state,
    which may lie past the reference starts' last frame; a state start is not counted by the
    failure-proportional sampler; resets with options are passed on."""
    env = PerformedStarts(walk_policy.make_env([walk], artefacts=None), fraction=1.0)
    mimic = env.unwrapped
    episode = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0})
    late = mimic.last_start(0) + 50  # beyond where a reference start may begin
    assert late < walk.n_frames - 1
    chosen = [40, late]
    states = [episode.state(f) if f <= episode.end_frame else (walk.qpos[f], np.zeros(mimic.model.nv))
              for f in chosen]
    env.set_states(chosen, np.array([s[0] for s in states]), np.array([s[1] for s in states]))
    seen = set()
    for i in range(12):
        _, info = env.reset(seed=7 if i == 0 else None)
        f = info["frame"]
        seen.add(f)
        np.testing.assert_allclose(mimic.data.qpos, states[chosen.index(f)][0], atol=1e-12)
    assert seen == set(chosen)
    counted = mimic._sampler.episodes[0].sum()
    env.reset()
    _, _, terminated, truncated, _ = env.step(np.ones(env.action_space.shape, dtype=np.float32))
    while not (terminated or truncated):
        _, _, terminated, truncated, _ = env.step(np.ones(env.action_space.shape, dtype=np.float32))
    assert mimic._sampler.episodes[0].sum() == counted
    _, info = env.reset(options={"start_frame": 1})
    assert info["frame"] == 1
    with pytest.raises(ValueError, match="start_frame .* out of range"):
        mimic.reset(options={"start_frame": walk.n_frames - 1, "state": states[0]})
    with pytest.raises(ValueError, match="as many finite qpos and qvel rows as frames"):
        env.set_states([1, 2], np.zeros((1, mimic.model.nq)), np.zeros((1, mimic.model.nv)))


def test_a_performance_gives_the_states_before_its_failures(walk_policy):
    """A clip the walk policy fails (a turn): the start states are the performance's own simulated
    states in the second before each re-anchor's failure."""
    turn = load_motion("deepmimic:walker/turn_left1", min_frames=600)
    performance = perform_clip(walk_policy, turn, progress=False)
    assert performance.reanchors, "the walk policy must fail on a 10-s turn"
    frames, qpos, qvel = adaptation._start_states(performance, window_s=1.0)
    assert len(frames) and np.isfinite(qpos).all() and np.isfinite(qvel).all()
    np.testing.assert_array_equal(qpos, performance.qpos[frames])
    first = performance.reanchors[0]
    assert set(range(first.best_reached - 60, first.frame)) <= set(frames)
    assert first.frame not in frames and 0 not in frames
    assert frames.max() <= turn.n_frames - 1 - walk_policy.record.env.mimic_config().frames_per_control


def test_adaptation_from_performed_starts_trains_and_keys_apart(walk_policy, tmp_path):
    turn = load_motion("deepmimic:walker/turn_left1", min_frames=300)
    config = AdaptConfig(budget_s=60, max_steps=1024, chunk_steps=1024, n_envs=2, n_steps=512, eval_episodes=1,
                         target_sr90=None, performed_starts=0.5, cache_dir=tmp_path)
    result = adapt_policy(walk_policy, turn, config, progress=False)
    assert result.steps == 1024 and result.stopped_by == "max_steps"
    assert result.policy.record.extra["adaptation"]["config"]["performed_starts"] == 0.5
    assert adaptation_key(turn, walk_policy, config) != adaptation_key(turn, walk_policy,
                                                                       replace(config, performed_starts=0.0))
    assert adapt_policy(walk_policy, turn, config, progress=False).cached
    with pytest.raises(ValueError, match=r"performed_starts must be in \[0, 1\], got 1.5"):
        AdaptConfig(performed_starts=1.5)
