"""Failure-proportional sampling of episode starts: train where the policy currently falls.

Each clip's possible start frames are cut into bins of :attr:`SamplingConfig.bin_frames`. Every
finished episode adds to its (clip, start bin)'s running counts of episodes and failures (falls,
lagging, instability), decayed so that the rates follow the policy as it learns. A clip is drawn
with probability proportional to its bins' mean weight ``floor + failure rate``, then a bin of it
by its own weight, then a start frame uniformly inside the bin. Unvisited bins start at the prior
failure rate, so new clips are tried early. With ``failure_proportional=False`` clips and start
frames are drawn uniformly (ADAPT's reference state initialisation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SamplingConfig:
    """Settings of :class:`FailureSampler`.

    Attributes:
        failure_proportional: sample by failure rate; ``False``: uniform clips and start frames.
        bin_frames: start frames per bin (60 = 1 s at 60 Hz).
        floor: weight a bin keeps at a failure rate of 0, so mastered motion is still rehearsed.
        prior_rate: failure rate assumed before any episode of a bin.
        prior_episodes: weight of that prior, in episodes.
        decay: factor applied to a bin's counts at each of its episodes (forgetting old results).
    """

    failure_proportional: bool = True
    bin_frames: int = 60
    floor: float = 0.1
    prior_rate: float = 0.5
    prior_episodes: float = 2.0
    decay: float = 0.95

    def __post_init__(self) -> None:
        if self.bin_frames < 1:
            raise ValueError(f"SamplingConfig.bin_frames must be >= 1, got {self.bin_frames}")
        if not (self.floor > 0 and 0 <= self.prior_rate <= 1 and self.prior_episodes > 0 and 0 < self.decay <= 1):
            raise ValueError("SamplingConfig needs floor > 0, 0 <= prior_rate <= 1, prior_episodes > 0, "
                             f"0 < decay <= 1; got {self}")


def failure_weights(failures: np.ndarray, episodes: np.ndarray, config: SamplingConfig) -> np.ndarray:
    """Sampling weight ``floor + rate`` of bins with (decayed) ``failures`` and ``episodes`` counts
    (same shape), the rate smoothed towards the prior."""
    rate = (failures + config.prior_rate * config.prior_episodes) / (episodes + config.prior_episodes)
    return config.floor + rate


class FailureSampler:
    """Draws (clip, start frame) of episodes; :meth:`record` feeds back how each episode ended.

    Args:
        last_starts: ``(C,)`` latest start frame of each clip.
        config: see :class:`SamplingConfig`.
    """

    def __init__(self, last_starts: list[int], config: SamplingConfig = SamplingConfig()):
        self.config = config
        self.last_starts = [int(s) for s in last_starts]
        self.failures = [np.zeros(s // config.bin_frames + 1) for s in self.last_starts]
        self.episodes = [np.zeros(s // config.bin_frames + 1) for s in self.last_starts]

    def clip(self, rng: np.random.Generator) -> int:
        """Index of the clip of the next episode."""
        if not self.config.failure_proportional:
            return int(rng.integers(len(self.last_starts)))
        w = np.array([failure_weights(f, e, self.config).mean() for f, e in zip(self.failures, self.episodes)])
        return int(rng.choice(len(w), p=w / w.sum()))

    def start_frame(self, clip: int, last_start: int, rng: np.random.Generator) -> int:
        """A start frame in ``0..last_start`` of ``clip``."""
        if not self.config.failure_proportional:
            return int(rng.integers(last_start + 1))
        w = failure_weights(self.failures[clip], self.episodes[clip], self.config)
        b = int(rng.choice(len(w), p=w / w.sum()))
        lo = b * self.config.bin_frames
        return int(rng.integers(lo, min(lo + self.config.bin_frames - 1, last_start) + 1))

    def record(self, clip: int, start_frame: int, failed: bool) -> None:
        """Count an episode of ``clip`` started at ``start_frame`` that failed or not."""
        b = min(start_frame // self.config.bin_frames, len(self.episodes[clip]) - 1)
        self.failures[clip][b] = self.config.decay * self.failures[clip][b] + float(failed)
        self.episodes[clip][b] = self.config.decay * self.episodes[clip][b] + 1.0

    def failure_rates(self) -> list[float]:
        """Each clip's smoothed failure rate (mean over its start bins), for logging."""
        c = self.config
        return [float(failure_weights(f, e, c).mean() - c.floor) for f, e in zip(self.failures, self.episodes)]
