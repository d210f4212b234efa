"""The KL-following learning rate (agents/lr_schedule.py) on hand-made KL values."""

import math

import pytest

from agents.lr_schedule import KLSchedule, next_learning_rate


def test_the_rate_follows_the_kl_within_its_band_and_bounds():
    s = KLSchedule(target_kl=0.01, factor=1.5, min_lr=1e-6, max_lr=1e-3)
    assert next_learning_rate(1e-4, 0.15, s) == pytest.approx(1e-4 / 1.5)   # KL > 2 x target: smaller steps
    assert next_learning_rate(1e-4, 0.004, s) == pytest.approx(1.5e-4)       # KL < target / 2: larger steps
    assert next_learning_rate(1e-4, 0.02, s) == 1e-4                         # inside [target/2, 2 target]: kept
    assert next_learning_rate(1e-4, 0.005, s) == 1e-4
    assert next_learning_rate(1.2e-6, 1.0, s) == 1e-6                        # clipped to the bounds
    assert next_learning_rate(9e-4, 0.0, s) == 1e-3


def test_bad_settings_and_a_diverged_update_are_refused():
    with pytest.raises(ValueError, match="factor > 1"):
        KLSchedule(factor=1.0)
    with pytest.raises(ValueError, match="target_kl > 0"):
        KLSchedule(target_kl=0.0)
    with pytest.raises(ValueError, match="diverged"):
        next_learning_rate(1e-4, math.nan, KLSchedule())
