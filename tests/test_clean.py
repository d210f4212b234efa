"""clean.py: retries and re-anchors after a failure, per-clip adaptation and its cache, the video
marks, with the shipped walk policy (each test a few seconds)."""

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from stable_baselines3 import PPO

from agents import clean
from agents.adaptation import AdaptConfig, adapt_policy, adaptation_key, chunk_rank, performance_rank
from agents.clean import POLICY_ALONE, CleanConfig, StateRing, clean_motion, reanchor_marks
from agents.policy import MimicPolicy, load_policy
from agents.rollout import FAILURES, run_episode
from reference_motion.cli import UsageError
from reference_motion.library import load_motion
from reference_motion.motion import Motion
from reference_motion.render import MARK_RGB, render_frames

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


@pytest.fixture(scope="module")
def walk_policy() -> MimicPolicy:
    return load_policy(WALK_POLICY)


class Flailing(MimicPolicy):
    """The walk policy, except that its calls number ``first`` to ``first + count - 1`` output the
    largest action on every driven hinge (a forced failure)."""

    def __init__(self, base: MimicPolicy, first: int = 1, count: int = 10**9):
        super().__init__(base.path, base.model, base.normalizer, base.sidecar)
        self.first, self.count, self.calls = first, count, 0

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        self.calls += 1
        if self.first <= self.calls < self.first + self.count:
            return np.ones(self.model.action_space.shape, dtype=np.float32)
        return super().__call__(obs)


def test_a_good_policy_performs_the_whole_clip_in_one_simulation(walk_policy, walk):
    cleaned = clean_motion(walk_policy, walk, POLICY_ALONE, progress=False)
    assert cleaned.n_frames == walk.n_frames and np.isfinite(cleaned.qpos).all()
    assert cleaned.source["simulated_fraction"] == 1.0
    assert cleaned.source["reanchors"] == [] and cleaned.source["recoveries"] == []
    assert not reanchor_marks(cleaned).any()
    # it is the physics, not the reference: the first stretch is the policy's own rollout from frame 0
    env = walk_policy.make_env([walk], artefacts=None)
    episode = run_episode(env, walk_policy, {"clip": 0, "start_frame": 0})
    assert episode.ended_by == "time_limit"
    np.testing.assert_allclose(cleaned.qpos[:100], episode.qpos[:100], atol=1e-9)
    assert not np.allclose(cleaned.qpos, walk.qpos, atol=1e-3)
    # its reward ratio: each simulated frame counts the reward of the control step that simulated it;
    # frames 1..300 are that rollout's (one ratio of at most 1 more: the last frame, a second stretch)
    per_frame = np.repeat(episode.rewards, walk_policy.record.env.mimic_config().frames_per_control)[:300]
    ratio = per_frame / env.unwrapped.max_step_reward
    assert walk.n_frames == 302 and 0.3 < ratio.mean() < 1
    assert cleaned.source["reward_ratio"] * 301 == pytest.approx(ratio.sum(), abs=1.0)


def test_a_failure_is_retried_from_before_it(walk_policy, walk):
    """The policy flails for 30 steps (a failure); stochastic retries of the walk policy from 1 s
    before it get past it: recorded as recoveries, no re-anchor, every frame simulated."""
    cleaned = clean_motion(Flailing(walk_policy, first=60, count=30), walk, CleanConfig(rewind_s=1.0, search=None),
                           progress=False)
    recoveries = cleaned.source["recoveries"]
    assert recoveries and all(r["reason"] in FAILURES and r["frame"] < r["failed_at"] for r in recoveries)
    assert cleaned.source["reanchors"] == [] and cleaned.source["simulated_fraction"] == 1.0
    assert np.isfinite(cleaned.qpos).all()


def test_when_every_retry_fails_it_reanchors_and_says_where_and_why(walk_policy, walk, monkeypatch):
    monkeypatch.setattr(clean, "sampling_policy", lambda policy: policy)  # the retries flail too
    cleaned = clean_motion(Flailing(walk_policy), walk, CleanConfig(retries=2, search=None), progress=False)
    reanchors = cleaned.source["reanchors"]
    assert reanchors, "a policy at the action limit must fail"
    frames = [r["frame"] for r in reanchors]
    assert frames == sorted(set(frames)) and 0 < frames[0] and frames[-1] <= walk.n_frames - 1
    for r in reanchors:
        assert r["reason"] in FAILURES and r["retries"] == 2 and r["failed_at"] <= r["best_reached"]
        assert r["jump_m"] is None or r["jump_m"] >= 0
    assert cleaned.source["simulated_fraction"] == pytest.approx(1 - len(reanchors) / (walk.n_frames - 1))
    assert cleaned.n_frames == walk.n_frames and np.isfinite(cleaned.qpos).all()
    # a re-anchored frame is the reference state there (lifted above the floor at most)
    f = frames[0]
    np.testing.assert_allclose(cleaned.qpos[f, 3:], walk.qpos[f, 3:], atol=1e-9)
    marks = reanchor_marks(cleaned)
    assert marks[f:f + 30].all() and not marks[:f].any()


def test_state_ring_keeps_the_last_frames_only():
    ring = StateRing(3)
    for f in range(5):
        ring.push(f, np.full(2, f), np.zeros(1))
    assert ring.state(4)[0][0] == 4 and ring.state(2)[0][0] == 2
    with pytest.raises(KeyError):
        ring.state(1)
    ring.drop_after(2)
    ring.push(3, np.full(2, 7), np.zeros(1))
    assert ring.state(3)[0][0] == 7
    with pytest.raises(ValueError):
        ring.push(5, np.zeros(2), np.zeros(1))


def test_marked_frames_get_a_red_border():
    motion = load_motion("deepmimic:walk")
    motion = motion.with_qpos(motion.qpos[:4])
    frames = render_frames(motion, 64, 48, marked=np.array([False, True, False, False]))
    assert tuple(frames[1, 0, 0]) == MARK_RGB and tuple(frames[1, 24, -1]) == MARK_RGB
    assert tuple(frames[0, 0, 0]) != MARK_RGB


def test_adaptation_writes_the_cache_and_reuses_it(walk_policy, tmp_path):
    """A tiny budget: one PPO update on a clip the walk policy lags on, then the cache."""
    turn = load_motion("deepmimic:walker/turn_left1", min_frames=600)
    config = AdaptConfig(budget_s=60, max_steps=1024, chunk_steps=1024, n_envs=2, eval_episodes=2,
                         cache_dir=tmp_path)  # the budget covers performing the 10-s clip twice (~9 re-anchors)
    first = adapt_policy(walk_policy, turn, config, progress=False)
    assert not first.cached and first.stopped_by in ("max_steps", "target", "budget")
    assert first.steps >= 1024 and first.wall_s < 60 and len(first.chunks) == 1
    assert first.path == tmp_path / adaptation_key(turn, walk_policy, config)
    # its settings are not the defaults (2 envs): kept apart from a run made with the defaults
    assert adaptation_key(turn, walk_policy, config) != adaptation_key(turn, walk_policy)
    assert adaptation_key(turn, walk_policy, AdaptConfig(budget_s=5)) == adaptation_key(turn, walk_policy)
    kept = first.before if first.kept_steps == 0 else first.chunks[0]
    assert performance_rank(kept) == max(performance_rank(first.before), performance_rank(first.chunks[0]))
    assert first.sr90_after == kept["SR90"] and first.elr_after == kept["ELR_mean"]
    sidecar = json.loads((first.path / "sidecar.json").read_text())
    assert sidecar["adaptation"]["steps"] == first.steps and sidecar["training"]["init_from"] == str(WALK_POLICY)
    assert first.policy.foot == walk_policy.foot and first.policy.env_id == walk_policy.env_id
    started = time.perf_counter()
    second = adapt_policy(walk_policy, turn, config, progress=False)
    assert second.cached and second.path == first.path and second.steps == first.steps
    assert time.perf_counter() - started < 5
    # another clip (here: the same one corrupted) is another entry; a bigger budget adapts again
    assert adaptation_key(turn.with_qpos(turn.qpos + 1e-6), walk_policy) != first.key
    assert not AdaptConfig(budget_s=20, max_steps=1024).covers(AdaptConfig(budget_s=60, max_steps=1024))


def test_adaptation_without_a_target_trains_to_its_limit_and_reports_each_chunk(walk_policy, tmp_path):
    """target_sr90=None: no early stop even where the policy already performs the clip whole
    (walk, its training clip); on_chunk sees the policy before training and after each chunk;
    action_variance replaces the policy's exploration noise."""
    walk = load_motion("deepmimic:walk", min_frames=300)
    seen = []

    def hook(policy: MimicPolicy, performed: Motion) -> dict:
        seen.append(policy.model.num_timesteps)
        assert performed.n_frames == walk.n_frames and performed.source["cleaned_by"] == str(policy.path)
        return {"calls": len(seen), "reanchors": -1}  # a figure of the performance's own is not overridden

    config = AdaptConfig(budget_s=60, max_steps=2048, chunk_steps=1024, n_envs=2, n_steps=512, eval_episodes=1,
                         target_sr90=None, action_variance=0.01, cache_dir=tmp_path)
    result = adapt_policy(walk_policy, walk, config, progress=False, on_chunk=hook)
    assert result.sr90_before == 1.0  # a target of 0.9 would have stopped before any training
    assert result.stopped_by == "max_steps" and result.steps == 2048
    assert [c["calls"] for c in result.chunks] == [2, 3] and result.before["calls"] == 1
    assert seen[1] - seen[0] == 1024 and seen[2] - seen[1] == 1024
    assert all(0 < c["MRR_mean"] <= 1 and c["reanchors"] >= 0 and 0 < c["reward_ratio"] <= 1 for c in result.chunks)
    assert result.kept_steps in (0, 1024, 2048)
    log_std = PPO.load(result.path / "model.zip", device="cpu").policy.log_std.detach().numpy()
    own = walk_policy.model.policy.log_std.detach().numpy()
    # a chunk kept: trained with the noise asked for; none: the policy as given, its own noise
    np.testing.assert_allclose(log_std, 0.5 * np.log(0.01) if result.kept_steps else own, rtol=1e-6)
    assert not np.allclose(own, 0.5 * np.log(0.01))
    again = adapt_policy(walk_policy, walk, config, progress=False)
    assert again.cached and again.before == result.before
    other_noise = adapt_policy(walk_policy, walk, replace(config, action_variance=0.02, max_steps=1024),
                               progress=False)
    assert not other_noise.cached  # the cache holds what was adapted with another noise: adapted anew
    # a cached run that stopped at a target does not stand in for one trained to the budget
    assert not AdaptConfig(budget_s=60, target_sr90=0.9).covers(AdaptConfig(budget_s=60, target_sr90=None))
    assert AdaptConfig(budget_s=60, target_sr90=None).covers(AdaptConfig(budget_s=60, target_sr90=0.9))


def test_adaptation_trains_at_the_learning_rate_asked_for(walk_policy, tmp_path):
    """learning_rate replaces the policy's own rate while adapting; a cached run made at another
    rate, or with other training settings, is not reused."""
    walk = load_motion("deepmimic:walk", min_frames=300)
    own = walk_policy.model.learning_rate
    config = AdaptConfig(budget_s=60, max_steps=1024, chunk_steps=1024, n_envs=2, n_steps=512, eval_episodes=1,
                         target_sr90=None, learning_rate=own * 3, keep="evaluation", cache_dir=tmp_path)
    result = adapt_policy(walk_policy, walk, config, progress=False)
    adapted = PPO.load(result.path / "model.zip", device="cpu")
    # the rate the optimizer last trained at (train() sets it from the schedule before each update)
    assert adapted.policy.optimizer.param_groups[0]["lr"] == pytest.approx(own * 3)
    assert adapt_policy(walk_policy, walk, config, progress=False).cached
    assert not adapt_policy(walk_policy, walk, replace(config, learning_rate=None), progress=False).cached
    assert not adapt_policy(walk_policy, walk, replace(config, n_steps=256), progress=False).cached
    with pytest.raises(ValueError, match="learning_rate must be positive or None, got 0"):
        AdaptConfig(learning_rate=0)


def test_adaptation_can_keep_the_chunk_that_performs_the_clip_best(walk_policy, tmp_path):
    """keep="performance": each chunk (and the policy as given) performs the clip whole; the chunk
    kept is the one ranked best by its performance, recorded with it; the rule is in the cache key."""
    turn = load_motion("deepmimic:walker/turn_right0", min_frames=300)
    config = AdaptConfig(budget_s=60, max_steps=2048, chunk_steps=1024, n_envs=2, n_steps=512, eval_episodes=1,
                         target_sr90=None, keep="performance", cache_dir=tmp_path)
    result = adapt_policy(walk_policy, turn, config, progress=False)
    figures = [result.before] + result.chunks
    assert all({"reanchors", "recoveries", "reward_ratio"} <= set(f) for f in figures)
    best = max(range(len(figures)), key=lambda i: performance_rank(figures[i]))
    assert result.kept_steps == (0 if best == 0 else result.chunks[best - 1]["steps"])
    kept = clean_motion(result.policy, turn, POLICY_ALONE, progress=False).source  # how chunks are ranked
    assert (len(kept["reanchors"]), len(kept["recoveries"])) == (figures[best]["reanchors"], figures[best]["recoveries"])
    assert adaptation_key(turn, walk_policy, config) != adaptation_key(turn, walk_policy, replace(config, keep="evaluation"))
    with pytest.raises(ValueError, match="keep must be one of"):
        AdaptConfig(keep="best")


def test_the_chunk_that_reaches_the_target_ends_the_adaptation_and_is_kept(walk_policy, tmp_path, monkeypatch):
    """Scripted judgements: chunk 1 performs best (no recovery, the higher reward) but its SR90 is
    short of the target; chunk 2 reaches it with no re-anchor: the adaptation stops there and keeps
    chunk 2, so what it reports (SR90 after, steps kept) is the chunk that ended it."""
    from agents import adaptation
    script = iter([(0.0, 2, 0, 0.3), (0.8, 0, 0, 0.8), (0.9, 0, 1, 0.5)])  # SR90, re-anchors, recoveries, ratio
    judged = []

    def evaluate(env, policy, episodes):
        sr90, *performance = next(script)
        judged[:] = performance  # what the performance that follows this evaluation reports
        return {"SR90": sr90, "ELR_mean": sr90, "MRR_mean": 0.5, "rollouts": 1}

    def perform(policy, reference):
        reanchors, recoveries, ratio = judged
        return reference, {"reanchors": reanchors, "recoveries": recoveries, "reward_ratio": ratio}

    monkeypatch.setattr(adaptation, "evaluate_on_clip", evaluate)
    monkeypatch.setattr(adaptation, "_performance", perform)
    walk = load_motion("deepmimic:walk", min_frames=300)
    config = AdaptConfig(budget_s=60, max_steps=4096, chunk_steps=1024, n_envs=2, n_steps=512, cache_dir=tmp_path)
    result = adapt_policy(walk_policy, walk, config, progress=False)
    assert result.stopped_by == "target" and len(result.chunks) == 2
    assert result.kept_steps == result.chunks[1]["steps"] == 2048 and result.sr90_after == 0.9


def test_performances_rank_by_reanchors_then_recoveries_then_reward():
    def rank(reanchors: int, recoveries: int, ratio: float | None) -> tuple:
        return performance_rank({"reanchors": reanchors, "recoveries": recoveries, "reward_ratio": ratio})

    assert rank(0, 3, 0.1) > rank(1, 0, 0.9)
    assert rank(0, 1, 0.1) < rank(0, 0, 0.05)
    assert rank(0, 0, 0.5) > rank(0, 0, 0.4) > rank(0, 0, None)  # None: nothing simulated


def test_a_target_is_reached_by_sr90_and_by_performance_only_with_no_reanchor():
    by_evaluation, by_performance = AdaptConfig(target_sr90=0.9, keep="evaluation"), AdaptConfig(target_sr90=0.9)
    assert by_evaluation.reached({"SR90": 0.9, "reanchors": 2}) and not by_evaluation.reached({"SR90": 0.8})
    assert by_performance.reached({"SR90": 1.0, "reanchors": 0})
    assert not by_performance.reached({"SR90": 1.0, "reanchors": 1})
    assert not by_performance.reached({"SR90": 0.8, "reanchors": 0})
    assert not by_performance.reached({"SR90": 1.0, "reanchors": None})  # an older cache entry: not known
    assert not AdaptConfig(target_sr90=None).reached({"SR90": 1.0, "reanchors": 0})


def test_chunks_rank_by_survival_then_length_then_reward():
    def rank(sr90: float, elr: float, mrr: float) -> tuple:
        return chunk_rank({"SR90": sr90, "ELR_mean": elr, "MRR_mean": mrr})

    assert rank(1.0, 0.9, 0.1) > rank(0.8, 1.0, 0.9)
    assert rank(1.0, 0.9, 0.1) < rank(1.0, 1.0, 0.05)
    assert rank(1.0, 1.0, 0.5) > rank(1.0, 1.0, 0.4)


def test_adapt_target_variance_and_lr_options_read_a_number_or_none():
    args = clean.build_parser().parse_args(["deepmimic:walk", "--policy", str(WALK_POLICY), "--out", "o.npz",
                                            "--adapt-target", "None", "--adapt-variance", "none", "--adapt-lr", "3e-4"])
    assert args.adapt_target is None and args.adapt_variance is None and args.adapt_lr == 3e-4
    assert clean.sr90_target("0.8") == 0.8
    with pytest.raises(argparse.ArgumentTypeError, match="from 0 to 1"):
        clean.sr90_target("1.5")
    with pytest.raises(UsageError, match="--adapt-variance: expected a positive number, got '0'"):
        clean.build_parser().parse_args(["deepmimic:walk", "--policy", str(WALK_POLICY), "--out", "o.npz",
                                         "--adapt-variance", "0"])


def test_adaptation_can_follow_a_target_kl(walk_policy, tmp_path):
    """AdaptConfig.target_kl: the learning rate falls after an update whose KL is far above it."""
    turn = load_motion("deepmimic:walker/turn_left1", min_frames=600)
    config = AdaptConfig(budget_s=30, max_steps=2048, chunk_steps=2048, n_envs=2, n_steps=512, eval_episodes=1,
                         target_kl=1e-9, keep="evaluation", cache_dir=tmp_path)  # no whole performances: quick
    result = adapt_policy(walk_policy, turn, config, progress=False)
    assert result.steps == 2048  # two updates: the second at the lowered rate
    adapted = PPO.load(result.path / "model.zip", device="cpu")
    assert adapted.learning_rate == pytest.approx(walk_policy.model.learning_rate / 1.5)
    assert json.loads((result.path / "sidecar.json").read_text())["adaptation"]["config"]["target_kl"] == 1e-9


def test_cli_adapts_by_default_and_not_with_no_adapt(tmp_path):
    common = ["deepmimic:walker/turn_left1", "--policy", str(WALK_POLICY), "--min-frames", "200"]
    adapted = clean.main([*common, "--out", str(tmp_path / "a.npz"), "--json", str(tmp_path / "a.json"),
                          "--adapt-budget-s", "20", "--adapt-steps", "512", "--adapt-chunk", "512",
                          "--adapt-cache", str(tmp_path / "cache")])
    record = json.loads((tmp_path / "a.json").read_text())
    assert record["adaptation"]["steps"] >= 512 and not record["adaptation"]["cached"]
    assert record["cleaned_by"] == record["adaptation"]["path"] != str(WALK_POLICY)
    frames = Motion.load(tmp_path / "a.npz").n_frames
    assert adapted["simulated_fraction"] == 1 - len(adapted["reanchors"]) / (frames - 1)
    zero_shot = clean.main([*common, "--no-adapt", "--out", str(tmp_path / "z.npz"),
                            "--json", str(tmp_path / "z.json")])
    assert zero_shot["adaptation"] is None and zero_shot["cleaned_by"] == str(WALK_POLICY)
    cleaned = Motion.load(tmp_path / "z.npz")
    assert cleaned.source["reanchors"] == zero_shot["reanchors"] and np.isfinite(cleaned.qpos).all()
    assert set(zero_shot["input"]) >= {"foot_skate_mps", "jitter"}
