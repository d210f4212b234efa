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
