"""A PPO learning rate that follows the policy's KL divergence per update (rsl_rl's "adaptive"
schedule, as used for legged robots and motion imitation).

With a fixed, small action noise (ADAPT's σ² = 0.03, σ ≈ 0.17 rad) a fixed learning rate moves the
policy's mean far in units of σ: the generalist's updates ran at an approximate KL of 0.12–0.18
per update with 60% of the samples clipped (README, "The generalist on clips never seen"). After
every update this schedule divides the learning rate by ``factor`` when the update's KL exceeded
twice the target and multiplies it by ``factor`` when the KL stayed under half of it, within
``[min_lr, max_lr]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.utils import FloatSchedule


@dataclass(frozen=True)
class KLSchedule:
    """Settings of the KL-following learning rate.

    Attributes:
        target_kl: the approximate KL divergence per PPO update aimed at (SB3's ``train/approx_kl``,
            the mean over the update's minibatches); rsl_rl's default is 0.01.
        factor: the learning rate is divided or multiplied by this after an update outside the band.
        min_lr, max_lr: bounds of the learning rate.
    """

    target_kl: float = 0.01
    factor: float = 1.5
    min_lr: float = 1e-6
    max_lr: float = 1e-3

    def __post_init__(self) -> None:
        if not (self.target_kl > 0 and self.factor > 1 and 0 < self.min_lr <= self.max_lr):
            raise ValueError(f"KLSchedule needs target_kl > 0, factor > 1 and 0 < min_lr <= max_lr; got {self}")


def next_learning_rate(lr: float, kl: float, schedule: KLSchedule) -> float:
    """The learning rate for the next PPO update after one at ``lr`` reached approximate KL ``kl``.

    Raises:
        ValueError: ``kl`` is NaN or infinite (the update diverged; no rate follows from it).
    """
    if not math.isfinite(kl):
        raise ValueError(f"approximate KL of the last PPO update is {kl}; the update diverged")
    if kl > 2.0 * schedule.target_kl:
        lr /= schedule.factor
    elif kl < 0.5 * schedule.target_kl:
        lr *= schedule.factor
    return min(max(lr, schedule.min_lr), schedule.max_lr)


class KLAdaptiveLearningRate(BaseCallback):
    """Sets the model's learning rate before each rollout from the KL of the update just made.

    The rate is stored in the model (``learning_rate`` and ``lr_schedule``), so a checkpoint
    resumes with the rate it had reached.
    """

    def __init__(self, schedule: KLSchedule):
        super().__init__()
        self.schedule = schedule

    def _on_rollout_start(self) -> None:
        # SB3 dumps its log before each update, so what the logger holds now is the last update's
        kl = self.model.logger.name_to_value.get("train/approx_kl")
        if kl is None:  # no update since this learn() call began
            return
        lr = next_learning_rate(self.model.lr_schedule(1.0), float(kl), self.schedule)
        self.model.learning_rate = lr
        self.model.lr_schedule = FloatSchedule(lr)

    def _on_step(self) -> bool:
        return True


def kl_following(target_kl: float | None) -> list[BaseCallback]:
    """The callbacks that make a PPO run's learning rate follow ``target_kl`` (``None``: none, the
    rate stays fixed); for ``model.learn`` beside the run's own callbacks."""
    return [] if target_kl is None else [KLAdaptiveLearningRate(KLSchedule(target_kl))]
