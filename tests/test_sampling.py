"""Failure-proportional sampling of episode starts (envs/sampling.py), by hand-made counts."""

import numpy as np
import pytest

from envs.sampling import FailureSampler, SamplingConfig, failure_weights


def test_failure_weights_by_hand():
    c = SamplingConfig(floor=0.1, prior_rate=0.5, prior_episodes=2.0)
    # no episodes: the prior rate; 8 failures in 8: (8 + 1) / (8 + 2) = 0.9; 0 in 8: 1 / 10
    assert failure_weights(np.array([0.0, 8.0, 0.0]), np.array([0.0, 8.0, 8.0]), c) == pytest.approx([0.6, 1.0, 0.2])


def test_sampler_prefers_clips_and_bins_where_episodes_fail():
    sampler = FailureSampler([599, 100], SamplingConfig(bin_frames=60, decay=1.0))
    assert [len(f) for f in sampler.failures] == [10, 2]  # 0..599 in 60-frame bins; 0..100
    for _ in range(50):
        sampler.record(0, 130, failed=True)  # clip 0 fails from its third bin (frames 120–179)
        for start in range(10, 600, 60):
            if not 120 <= start < 180:
                sampler.record(0, start, failed=False)  # every other bin succeeds
        sampler.record(1, 10, failed=False)
        sampler.record(1, 90, failed=False)
    rng = np.random.default_rng(0)
    clips = np.array([sampler.clip(rng) for _ in range(2000)])
    assert 0.6 < np.mean(clips == 0) < 0.9  # the clip with a failing bin is drawn more than half the time
    starts = np.array([sampler.start_frame(0, 599, rng) for _ in range(2000)])
    # weights: failing bin 0.1 + 51/52, nine others 0.1 + 1/52 each → 1.08 / 2.15 ≈ 0.50 of the draws
    assert 0.45 < np.mean((starts >= 120) & (starts < 180)) < 0.56
    assert starts.min() >= 0 and starts.max() <= 599
    rates = sampler.failure_rates()
    assert rates[0] > rates[1]


def test_uniform_sampling_when_switched_off():
    sampler = FailureSampler([99, 99], SamplingConfig(failure_proportional=False))
    sampler.record(0, 0, failed=True)
    rng = np.random.default_rng(1)
    assert abs(np.mean([sampler.clip(rng) for _ in range(4000)]) - 0.5) < 0.03
    with pytest.raises(ValueError, match="bin_frames"):
        SamplingConfig(bin_frames=0)
