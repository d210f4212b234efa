"""Paired comparison of two policies scored on the same IMU-corrupted draws (bench/imu_draws.py,
bench/select_policy.py)."""

from __future__ import annotations

import numpy as np


def paired(elr: np.ndarray, first: np.ndarray) -> dict:
    """``elr`` ``(draws,)`` against ``first`` ``(draws,)``, draw by draw: mean difference, its
    standard error, and the draws above / equal / below."""
    diff = elr - first
    se = float(diff.std(ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else float("nan")
    return {"mean_difference": float(diff.mean()), "standard_error": se, "draws_above": int(np.sum(diff > 0)),
            "draws_equal": int(np.sum(diff == 0)), "draws_below": int(np.sum(diff < 0))}


def overlapping_draws(rule_seeds: list[int], confirm_seeds: list[int]) -> str | None:
    """Why confirmation draws are not fresh, or None if they are: the seed range of the
    confirmation's draws (``seeds_of_first_clip``) must not overlap the rule's."""
    first, second = sorted(rule_seeds), sorted(confirm_seeds)
    if first[0] <= second[-1] and second[0] <= first[-1]:
        return (f"the confirmation draws (seeds {second[0]}..{second[-1]}) overlap the rule's draws "
                f"({first[0]}..{first[-1]}); they must be unused ones")
    return None
