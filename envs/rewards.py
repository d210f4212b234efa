"""Rewards and terminations of the mimic task (adapt §3.2.3, eqs. 6–10), as pure array functions.

Nothing here touches MuJoCo: the environment hands in simulated and reference arrays, so every
term can be checked on hand-made states (``tests/test_env_rewards.py``).

Frames: positions and velocities are world-frame (m, m/s); ``axes (B, 3, 3)`` holds each body's
x, y, z axes in world coordinates as rows; quaternions are (w, x, y, z).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from reference_motion import rotations as rot


def cube_face_points(pos: np.ndarray, axes: np.ndarray, size: float = 1.0) -> np.ndarray:
    """Centres of the six faces of a cube of edge ``size`` (m) mounted at each body origin.

    Args:
        pos: ``(..., B, 3)`` body origins.
        axes: ``(..., B, 3, 3)`` body axes (rows) in world coordinates.

    Returns:
        ``(..., B, 6, 3)``: faces +x, +y, +z, −x, −y, −z.
    """
    offsets = 0.5 * size * np.concatenate([axes, -axes], axis=-2)
    return pos[..., None, :] + offsets


def cube_face_velocities(linvel: np.ndarray, angvel: np.ndarray, axes: np.ndarray, size: float = 1.0) -> np.ndarray:
    """Velocities ``(..., B, 6, 3)`` of the points of :func:`cube_face_points`: ``v + ω × r``.

    ``ω × a`` for the three axis rows ``a`` of ``axes`` is ``axes · [ω]×ᵀ``, one batched matrix
    product."""
    spin = (0.5 * size) * (axes @ np.swapaxes(rot.skew(angvel), -1, -2))
    return linvel[..., None, :] + np.concatenate([spin, -spin], axis=-2)


def local_pose_reward(local: np.ndarray, ref_local: np.ndarray, alpha: float) -> float:
    """r_local = exp(−α · mean_j ∠(q_j⁻¹ q̄_j)) over the ``J`` joints of ``local``/``ref_local``
    ``(J, 4)`` (adapt eq. 6; the angle in rad)."""
    dot = np.abs(np.einsum("ij,ij->i", local, ref_local))
    angle_sum = 2.0 * np.arccos(np.minimum(dot, 1.0)).sum()
    return math.exp(-alpha * angle_sum / local.shape[0])


def point_reward(points: np.ndarray, ref_points: np.ndarray, alpha: float) -> float:
    """exp(−α · (1/B) Σ_j Σ_k ‖p_jk − p̄_jk‖) for face points or face velocities ``(B, 6, 3)``
    (adapt eqs. 7 and 8)."""
    diff = points - ref_points
    dist_sum = np.sqrt(np.einsum("ijk,ijk->ij", diff, diff)).sum()
    return math.exp(-alpha * dist_sum / points.shape[0])


def fall_discount(head: np.ndarray, ref_head: np.ndarray) -> float:
    """e_discount = clamp(1.3 − 1.4 ‖p_head − p̄_head‖, 0, 1) (adapt eq. 9); positions in m."""
    dx, dy, dz = (float(v) for v in head - ref_head)
    return min(1.0, max(0.0, 1.3 - 1.4 * math.sqrt(dx * dx + dy * dy + dz * dz)))


@dataclass(frozen=True)
class RewardTerms:
    """The terms of r = e_discount · (r_local + r_p + r_v) (adapt eq. 10); ``total`` is r."""

    r_local: float
    r_p: float
    r_v: float
    e_discount: float
    total: float

    def as_dict(self) -> dict[str, float]:
        return dict(self.__dict__)


MAX_STEP_REWARD = 3.0
"""Largest possible r (all terms 1): the R_max of the max-reward ratio is this per step."""


def mimic_reward(local: np.ndarray, ref_local: np.ndarray, faces: np.ndarray, ref_faces: np.ndarray,
                 face_vel: np.ndarray, ref_face_vel: np.ndarray, head: np.ndarray, ref_head: np.ndarray,
                 alpha_local: float = 2.5, alpha_p: float = 1.0, alpha_v: float = 0.1) -> RewardTerms:
    """All reward terms of one step.

    Args:
        local, ref_local: ``(J, 4)`` joint rotations relative to the parent (the root's in world).
        faces, ref_faces: ``(B, 6, 3)`` cube face points relative to the root body's origin.
        face_vel, ref_face_vel: ``(B, 6, 3)`` their world velocities.
        head, ref_head: ``(3,)`` head positions (world).
        alpha_local, alpha_p, alpha_v: scales of adapt Table 2.
    """
    r_local = local_pose_reward(local, ref_local, alpha_local)
    r_p = point_reward(faces, ref_faces, alpha_p)
    r_v = point_reward(face_vel, ref_face_vel, alpha_v)
    e = fall_discount(head, ref_head)
    return RewardTerms(r_local, r_p, r_v, e, e * (r_local + r_p + r_v))


def fallen(spinal_contacts: int, threshold: int = 3) -> bool:
    """Fall termination: at least ``threshold`` spinal bodies touch the ground at once."""
    return spinal_contacts >= threshold


def lagging(e_discount: float, threshold: float = 0.025) -> bool:
    """Lag termination: the character is too far from the reference (e_discount < ε_discount)."""
    return e_discount < threshold


def unstable(qvel: np.ndarray, max_speed: float) -> bool:
    """The simulation blew up: a NaN/inf or a speed above ``max_speed`` in ``qvel`` (positions
    are integrated from velocities, so they cannot go bad alone)."""
    return not np.abs(qvel).max() <= max_speed  # NaN compares False
