"""The policy-guided search (agents/search.py), its use in clean.py, and continuing an episode from a
simulated state with its smoothed action (reset option ``state``), with the shipped walk policy."""

from pathlib import Path

import numpy as np
import pytest

from agents.clean import CleanConfig, build_parser, clean_config, clean_motion
from agents.policy import MimicPolicy, load_policy
from agents.rollout import run_episode
from agents import search as search_module
from agents.search import SearchConfig, joined, search

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


@pytest.fixture(scope="module")
def walk_policy() -> MimicPolicy:
    return load_policy(WALK_POLICY)


class Stumbling(MimicPolicy):
    """The walk policy, except that on reference frames ``first`` to ``first + frames - 1`` its
    action is the largest on every hinge (a forced failure)."""

    def __init__(self, base: MimicPolicy, env, first: int, frames: int):
        super().__init__(base.path, base.model, base.normalizer, base.sidecar)
        self.env, self.first, self.frames = env, first, frames

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        frame = self.env.unwrapped._frame
        if self.first <= frame < self.first + self.frames:
            return np.ones(self.model.action_space.shape, dtype=np.float32)
        return super().__call__(obs)


def test_an_episode_continues_from_a_state_with_its_smoothed_action(walk_policy, walk):
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    episode = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=40)
    assert episode.actions.shape == (41, env.action_space.shape[0])
    assert not episode.actions[0].any() and np.abs(episode.actions[20]).max() > 0.05
    # frames 2k-1 and 2k are simulated by the same control step: one smoothed action
    np.testing.assert_array_equal(episode.actions[19], episode.actions[20])
    qpos, qvel, action = episode.state(20)
    env.reset(options={"clip": 0, "start_frame": 20, "state": (qpos, qvel, action)})
    np.testing.assert_array_equal(env.unwrapped.smoothed, action)
    env.reset(options={"clip": 0, "start_frame": 20, "state": (qpos, qvel)})
    assert not env.unwrapped.smoothed.any()
    with pytest.raises(ValueError, match=r"'state' must be .*action \(\d+,\)"):
        env.reset(options={"clip": 0, "start_frame": 20, "state": (qpos, qvel, action[:3])})
    with pytest.raises(ValueError, match="'state' must be"):
        env.reset(options={"clip": 0, "start_frame": 20, "state": (qpos, qvel, np.full_like(action, np.nan))})


def test_joined_windows_make_one_episode_and_must_continue(walk_policy, walk):
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    a = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=10)
    b = run_episode(env, walk_policy, {"clip": 0, "start_frame": 10, "state": a.state(10)}, max_frames=10)
    one = joined([a, b])
    assert (one.start_frame, one.end_frame, len(one.rewards)) == (0, 20, 10)
    np.testing.assert_array_equal(one.qpos[:11], a.qpos)
    np.testing.assert_array_equal(one.qpos[10:], b.qpos)
    np.testing.assert_array_equal(one.actions[10:], b.actions)
    with pytest.raises(ValueError, match="does not continue"):
        joined([a, a])


def test_search_gets_past_where_the_policy_alone_fails(walk_policy, walk, monkeypatch):
    """The policy flails from frame 40 to 60 and falls; the search's samples (here the walk policy
    itself in place of the noisy one, so that they do not flail) survive, are kept over the failing
    noise-free sample and carry the simulation to frame 120, as one continuous simulation."""
    long_env = walk_policy.make_env([walk], artefacts=None, episode_frames=200)
    alone = run_episode(long_env, Stumbling(walk_policy, long_env, first=40, frames=20), {"clip": 0, "start_frame": 0},
                        max_frames=120)
    assert alone.failed and alone.end_frame < 120
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    monkeypatch.setattr(search_module, "noisy_policy", lambda policy, scale, rng, hold: walk_policy)
    stumbling = Stumbling(walk_policy, env, first=40, frames=20)
    start = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=0).state(0)
    config = SearchConfig(beam=2, samples=4, window_steps=5, patience=0)
    found, rollouts = search(env, stumbling, 0, start, 120, config, np.random.default_rng(0))
    assert found.ended_by == "" and found.end_frame == 120 and found.start_frame == 0
    assert rollouts == 12 * 4  # 12 windows of 10 frames, 4 samples each
    # one simulation: each frame's velocity carries it to the next (semi-implicit Euler, dt = 1/60 / substeps)
    assert np.isfinite(found.qpos).all() and len(found.qpos) == 121
    step = np.linalg.norm(np.diff(found.qpos[:, :3], axis=0), axis=1)
    assert step.max() < 0.1  # no jump: at most ~2 m/s × 1/60 s between frames


def test_search_gives_up_with_the_furthest_failure(walk_policy, walk):
    """A policy that always takes the largest action fails in every sample: the search returns the
    rollout that got furthest, failed, after ``patience + 1`` tries of the window where it fails (here
    the second: the flailing body is still up at the end of the first, frame 40)."""
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    flailing = Stumbling(walk_policy, env, first=0, frames=10**6)
    start = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=0).state(0)
    config = SearchConfig(beam=2, samples=3, window_steps=20, noise=0.0, patience=1)
    found, rollouts = search(env, flailing, 0, start, 240, config, np.random.default_rng(0))
    assert found.failed and 40 < found.end_frame < 80 and rollouts == 3 + 2 * 3


def test_clean_searches_everywhere_by_default(walk_policy, walk):
    """clean.py's default: every stretch searched (16 states, 64 rollouts per window), one
    continuous simulation of the clip; the settings are recorded with the result."""
    assert CleanConfig().searches_everywhere and not CleanConfig(search=None).searches_everywhere
    assert not CleanConfig(search_retries_only=True).searches_everywhere
    cleaned = clean_motion(walk_policy, walk, progress=False)
    assert cleaned.source["reanchors"] == [] and cleaned.source["simulated_fraction"] == 1.0
    assert cleaned.source["clean_config"]["search"] == {"beam": 16, "samples": 64, "window_steps": 5, "noise": 1.0,
                                                        "patience": 2, "position_weight": 0.0, "value_weight": 1.0,
                                                        "hold_noise": True, "max_drift_m": 0.5}
    assert np.isfinite(cleaned.qpos).all() and not np.allclose(cleaned.qpos, walk.qpos, atol=1e-3)
    step = np.linalg.norm(np.diff(cleaned.qpos[:, :3], axis=0), axis=1)
    assert step.max() < 0.1  # one simulation: no jump between frames


@pytest.mark.parametrize("bad", [dict(beam=0), dict(samples=0), dict(window_steps=0), dict(noise=-1.0),
                                 dict(position_weight=-0.1), dict(value_weight=-1.0)])
def test_search_config_refuses_bad_settings(bad):
    with pytest.raises(ValueError, match="SearchConfig"):
        SearchConfig(**bad)


@pytest.mark.parametrize("argv, search, retries_only", [
    ([], SearchConfig(), False),
    (["--search", "retries", "--search-beam", "4", "--search-samples", "8", "--search-noise", "0.5",
      "--search-value", "0", "--search-noise-per-step", "--search-max-drift", "none"],
     SearchConfig(beam=4, samples=8, noise=0.5, value_weight=0.0, hold_noise=False, max_drift_m=None), True),
    (["--search", "off", "--retries", "7"], None, False),
])
def test_clean_command_line_sets_the_search(walk_policy, walk, argv, search, retries_only):
    args = build_parser().parse_args(["deepmimic:walk", "--policy", str(WALK_POLICY), "--out", "x.npz", *argv])
    config = clean_config(walk_policy, walk, args)
    assert (config.search, config.search_retries_only) == (search, retries_only)
    assert config.retries == (7 if "--retries" in argv else 4)


def test_the_critic_values_a_walking_state_above_one_about_to_fall(walk_policy, walk):
    """What ``SearchConfig.value_weight`` ranks by: after 20 control steps of flailing the walk
    policy's critic expects far less return than after 20 steps of walking, from the same frame."""
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    walking = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=40)
    flailing = run_episode(env, Stumbling(walk_policy, env, first=0, frames=40), {"clip": 0, "start_frame": 0},
                           max_frames=40)
    assert walking.final_obs.shape == env.observation_space.shape and walking.end_frame == 40
    values = walk_policy.values(np.stack([walking.final_obs, flailing.final_obs]))
    assert not flailing.failed  # still up: the critic sees the fall coming (196 against -168 here)
    assert values.shape == (2,) and values[1] < 0.5 * values[0]


def test_search_asks_the_critic_once_per_window_only_when_weighted(walk_policy, walk, monkeypatch):
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    start = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=0).state(0)
    asked = []
    critic = walk_policy.values
    monkeypatch.setattr(walk_policy, "values", lambda obs: asked.append(len(obs)) or critic(obs))
    for weight, calls in ((0.0, []), (1.0, [4] * 6)):  # 6 windows of 10 frames, 4 survivors each
        asked.clear()
        found, rollouts = search(env, walk_policy, 0, start, 60, SearchConfig(beam=2, samples=4, value_weight=weight),
                                 np.random.default_rng(0))
        assert found.ended_by == "" and found.end_frame == 60 and rollouts == 6 * 4 and asked == calls


@pytest.mark.parametrize("hold", [False, True])
def test_noisy_policy_adds_noise_of_the_policys_own_sigma_held_or_not(walk_policy, walk, hold):
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    obs, _ = env.reset(options={"clip": 0, "start_frame": 0})
    act = search_module.noisy_policy(walk_policy, 2.0, np.random.default_rng(0), hold=hold)
    offsets = np.array([act(obs) - walk_policy(obs) for _ in range(200)])
    sigma = 2.0 * np.exp(walk_policy.model.policy.log_std.detach().numpy())
    if hold:  # one draw for the whole rollout
        np.testing.assert_allclose(offsets, offsets[:1].repeat(200, axis=0))
    else:
        ratio = offsets.std(axis=0) / sigma  # clipping at the action limits can only shrink it
        assert 0.75 < np.median(ratio) < 1.15 and np.abs(offsets.mean(axis=0) / sigma).max() < 0.35


def test_a_rollout_that_strays_past_max_drift_fails_as_lagging(walk_policy, walk):
    """The walk policy keeps the root within centimetres of the reference's over 10 frames, not
    within a micrometre: with that limit every rollout of the first window fails."""
    env = walk_policy.make_env([walk], artefacts=None, episode_frames=60)
    start = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0}, max_frames=0).state(0)
    rng = np.random.default_rng(0)
    loose, _ = search(env, walk_policy, 0, start, 30, SearchConfig(beam=2, samples=3, max_drift_m=0.2), rng)
    assert loose.ended_by == "" and loose.end_frame == 30
    tight, rollouts = search(env, walk_policy, 0, start, 30, SearchConfig(beam=2, samples=3, patience=0,
                                                                          max_drift_m=1e-6), rng)
    assert tight.ended_by == "lagging" and tight.end_frame == 10 and rollouts == 3
    with pytest.raises(ValueError, match="max_drift_m must be > 0"):
        SearchConfig(max_drift_m=0.0)


def test_a_search_failed_by_its_own_drift_limit_searches_again_without_it(walk_policy, walk):
    """clean.py's retry: where every rollout strays past the search's drift limit (a micrometre
    here) but the task's own terminations do not end them, the search is tried again without the
    limit and gets past, so the walk needs recoveries but no re-anchor."""
    config = CleanConfig(search=SearchConfig(beam=2, samples=3, patience=0, max_drift_m=1e-6))
    cleaned = clean_motion(walk_policy, walk, config, progress=False)
    assert cleaned.source["reanchors"] == [] and cleaned.source["simulated_fraction"] == 1.0
    assert len(cleaned.source["recoveries"]) >= 3
    assert {r["reason"] for r in cleaned.source["recoveries"]} == {"lagging"}
