"""ADAPT's rollout metrics (adapt §3.2.6, eqs. 11–15), and the progress ratio, as pure functions of
one rollout.

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


def progress_ratio(root: np.ndarray, ref_root: np.ndarray, min_distance_m: float = 0.3) -> float:
    """How far the simulated root got along the reference root's way, as a fraction of it: the
    horizontal displacement of ``root`` from its first to its last frame, projected on the
    reference's over the same frames, over the length of the reference's (both ``(N, 3)``, m,
    world). 1.0: as far as the take; 0.8: a fifth short, as a body taking shorter steps than the
    take ends up (the lag termination's usual cause). NaN when the reference moves less than
    ``min_distance_m`` (e.g. standing), where the ratio means nothing."""
    root, ref_root = np.asarray(root, float), np.asarray(ref_root, float)
    if root.shape != ref_root.shape or root.ndim != 2 or root.shape[1] != 3 or len(root) == 0:
        raise ValueError(f"root and ref_root must both be (N, 3) with N > 0, got {root.shape} and {ref_root.shape}")
    way = ref_root[-1, :2] - ref_root[0, :2]
    length = float(np.linalg.norm(way))
    if length < min_distance_m:
        return float("nan")
    return float((root[-1, :2] - root[0, :2]) @ way / length ** 2)
