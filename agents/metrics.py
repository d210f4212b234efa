"""ADAPT's rollout metrics (adapt §3.2.6, eqs. 11–15) as pure functions of one rollout.

A rollout mimics a reference of ``reference_frames`` frames and survives ``rollout_frames`` of
them. Lengths are in reference frames; positions in m (world).
"""

from __future__ import annotations

import numpy as np

from envs.rewards import MAX_STEP_REWARD


def episode_length_ratio(rollout_frames: int, reference_frames: int) -> float:
    """ELR = rollout length / reference length (eq. 11); 1.0 when the rollout was not cut short."""
    if reference_frames <= 0:
        raise ValueError(f"reference_frames must be positive, got {reference_frames}")
    return rollout_frames / reference_frames


def survived(rollout_frames: int, reference_frames: int, fraction: float = 0.9) -> float:
    """SR90 of one rollout (eq. 13): 1.0 if it lasted at least ``fraction`` of the reference."""
    return float(rollout_frames >= fraction * reference_frames)


def root_displacement_error(root: np.ndarray, ref_root: np.ndarray) -> float:
    """RDE (eq. 12): mean squared distance (m²) between the simulated and reference root
    positions ``(N, 3)`` over the rollout's ``N`` frames."""
    root, ref_root = np.asarray(root, float), np.asarray(ref_root, float)
    if root.shape != ref_root.shape or root.ndim != 2 or root.shape[1] != 3 or len(root) == 0:
        raise ValueError(f"root and ref_root must both be (N, 3) with N > 0, got {root.shape} and {ref_root.shape}")
    return float(np.mean(np.sum((root - ref_root) ** 2, axis=1)))


def max_reward_ratio(rewards: np.ndarray, reference_steps: int, max_step_reward: float = MAX_STEP_REWARD) -> float:
    """MRR (eqs. 14–15): Σ r over the rollout's steps / the most a full-length rollout could
    collect (``reference_steps`` steps of ``max_step_reward``: ADAPT's 3 = e_discount·(1 + 1 + 1);
    1 for ``MimicGait-v0``, whose weights sum to 1)."""
    if reference_steps <= 0:
        raise ValueError(f"reference_steps must be positive, got {reference_steps}")
    return float(np.sum(rewards)) / (max_step_reward * reference_steps)
