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


def local_pose_reward(local: np.ndarray, ref_local: np.ndarray, alpha: float) -> float | np.ndarray:
    """r_local = exp(−α · mean_j ∠(q_j⁻¹ q̄_j)) over the ``J`` joints of ``local``/``ref_local``
    ``(..., J, 4)`` (adapt eq. 6; the angle in rad); one value per leading index."""
    dot = np.abs(np.einsum("...i,...i->...", local, ref_local))
    return np.exp(-alpha * 2.0 * np.arccos(np.minimum(dot, 1.0)).mean(axis=-1))


def point_reward(points: np.ndarray, ref_points: np.ndarray, alpha: float) -> float | np.ndarray:
    """exp(−α · (1/B) Σ_j Σ_k ‖p_jk − p̄_jk‖) for face points or face velocities ``(..., B, 6, 3)``
    (adapt eqs. 7 and 8); one value per leading index."""
    diff = points - ref_points
    dist_sum = np.sqrt(np.einsum("...k,...k->...", diff, diff)).sum(axis=(-2, -1))
    return np.exp(-alpha * dist_sum / points.shape[-3])


def fall_discount(head: np.ndarray, ref_head: np.ndarray) -> float | np.ndarray:
    """e_discount = clamp(1.3 − 1.4 ‖p_head − p̄_head‖, 0, 1) (adapt eq. 9); positions ``(..., 3)``
    in m, one value per leading index."""
    diff = np.asarray(head, dtype=float) - ref_head
    return np.clip(1.3 - 1.4 * np.sqrt(np.einsum("...k,...k->...", diff, diff)), 0.0, 1.0)


def body_points(pos: np.ndarray, axes: np.ndarray, linvel: np.ndarray, angvel: np.ndarray,
                offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World positions and velocities of points fixed on bodies.

    Args:
        pos, axes, linvel, angvel: ``(..., K, 3)``, ``(..., K, 3, 3)``, ``(..., K, 3)``, ``(..., K, 3)``:
            origin, axes (rows, world), origin velocity (m/s) and angular velocity (rad/s) of the
            body each of the ``K`` points is fixed on.
        offsets: ``(K, 3)`` each point in its body's frame (m).

    Returns:
        ``(points, velocities)``, each ``(..., K, 3)`` (m, m/s): ``p = o + R·r`` and ``v + ω × (p − o)``.
    """
    arm = np.einsum("kj,...kji->...ki", offsets, axes)
    return pos + arm, linvel + rot.cross(angvel, arm)


def still_feet_reward(point_vel: np.ndarray, point_height: np.ndarray, contact_height: float,
                      alpha: float) -> float | np.ndarray:
    """r_still = exp(−α · Σ_k ‖v_xy,k‖ · [z_k ≤ contact_height]): 1 when every foot point within
    ``contact_height`` (m) of the floor stands still, lower the faster those points slide or turn
    horizontally (foot skate, the speed ``reference_motion.quality.foot_skate`` measures).

    Args:
        point_vel: ``(..., K, 3)`` world velocities (m/s) of the ``K`` foot points.
        point_height: ``(..., K)`` their heights above the floor (m).
        alpha: scale (1/(m/s)).

    Returns:
        One value per leading index.
    """
    speed = np.sqrt(np.einsum("...k,...k->...", point_vel[..., :2], point_vel[..., :2]))
    return np.exp(-alpha * np.where(point_height <= contact_height, speed, 0.0).sum(axis=-1))


def com_velocity_reward(com_vel: np.ndarray, target_vel: np.ndarray, alpha: float) -> float | np.ndarray:
    """r_com = exp(−α · ‖v_xy − v*_xy‖): 1 when the character's horizontal CoM velocity matches the
    target, lower the further it is (the speed error, not its square, so a steady shortfall of a
    fifth of a walking speed still costs a visible share).

    Args:
        com_vel: ``(..., 3)`` the character's CoM velocity (world, m/s).
        target_vel: ``(..., 2)`` or ``(..., 3)`` the target velocity (world, m/s; only x, y are read).
        alpha: scale (1/(m/s)).

    Returns:
        One value per leading index.
    """
    diff = np.asarray(com_vel, dtype=float)[..., :2] - np.asarray(target_vel, dtype=float)[..., :2]
    return np.exp(-alpha * np.sqrt(np.einsum("...k,...k->...", diff, diff)))


@dataclass(frozen=True)
class RewardTerms:
    """The terms of r = e_discount · (r_local + r_p + r_v + w_still · r_still + w_com · r_com) (adapt
    eq. 10 with ADAPT's weights w_still = w_com = 0); ``total`` is r. Each is a float, or ``(N,)``
    for a batch of ``N`` states."""

    r_local: float | np.ndarray
    r_p: float | np.ndarray
    r_v: float | np.ndarray
    r_still: float | np.ndarray
    r_com: float | np.ndarray
    e_discount: float | np.ndarray
    total: float | np.ndarray

    def as_dict(self) -> dict[str, float]:
        return dict(self.__dict__)


MAX_STEP_REWARD = 3.0
"""Largest possible r of ADAPT's reward (all terms 1, w_still = 0): the R_max of the max-reward
ratio is this per step (``MimicEnv.max_step_reward`` adds w_still)."""


def mimic_reward(local: np.ndarray, ref_local: np.ndarray, faces: np.ndarray, ref_faces: np.ndarray,
                 face_vel: np.ndarray, ref_face_vel: np.ndarray, head: np.ndarray, ref_head: np.ndarray,
                 r_still: float | np.ndarray = 1.0, alpha_local: float = 2.5, alpha_p: float = 1.0,
                 alpha_v: float = 0.1, still_weight: float = 0.0, r_com: float | np.ndarray = 1.0,
                 com_weight: float = 0.0) -> RewardTerms:
    """All reward terms of one step, or of a batch of ``N`` steps (every array with a leading
    ``(N,)`` axis; each term then ``(N,)``).

    Args:
        local, ref_local: ``(J, 4)`` joint rotations relative to the parent (the root's in world).
        faces, ref_faces: ``(B, 6, 3)`` cube face points relative to the root body's origin.
        face_vel, ref_face_vel: ``(B, 6, 3)`` their world velocities.
        head, ref_head: ``(3,)`` head positions (world).
        r_still: :func:`still_feet_reward` of the state.
        alpha_local, alpha_p, alpha_v: scales of adapt Table 2.
        still_weight: w_still, the weight of ``r_still`` in the total (0: ADAPT's reward).
        r_com: :func:`com_velocity_reward` of the state.
        com_weight: w_com, the weight of ``r_com`` in the total (0: ADAPT's reward).
    """
    r_local = local_pose_reward(local, ref_local, alpha_local)
    r_p = point_reward(faces, ref_faces, alpha_p)
    r_v = point_reward(face_vel, ref_face_vel, alpha_v)
    e = fall_discount(head, ref_head)
    return RewardTerms(r_local, r_p, r_v, r_still, r_com, e,
                       e * (r_local + r_p + r_v + still_weight * r_still + com_weight * r_com))


def fallen(spinal_contacts: int, threshold: int = 3) -> bool:
    """Fall termination: at least ``threshold`` spinal bodies touch the ground at once."""
    return spinal_contacts >= threshold


def lagging(e_discount: float, threshold: float = 0.025) -> bool:
    """Lag termination: the character is too far from the reference (e_discount < ε_discount)."""
    return e_discount < threshold


def unstable(qvel: np.ndarray, max_speed: float) -> bool | np.ndarray:
    """The simulation blew up: a NaN/inf or a speed above ``max_speed`` in ``qvel`` ``(..., nv)``
    (positions are integrated from velocities, so they cannot go bad alone); one bool, or one per
    leading index."""
    fine = np.abs(qvel).max(axis=-1) <= max_speed  # NaN compares False
    return not fine if np.ndim(fine) == 0 else ~fine


# --------------------------------------------------------------------------- MimicGait-v0
# ContactVision's reconstruction reward (contactvision eq. 4 and App. C, eqs. 6–9). Every term
# is exp(−α · squared error) of arrays handed in by the environment; ``GaitConfig`` holds the
# weights and α's with their sources.

WORLD_UP = np.array([0.0, 0.0, 1.0])


def squared_error_reward(value: np.ndarray, ref_value: np.ndarray, alpha: float) -> float:
    """exp(−α ‖v̂ − v‖²) of two arrays of the same shape (the squared norm sums every entry)."""
    diff = np.asarray(value, dtype=float) - np.asarray(ref_value, dtype=float)
    return math.exp(-alpha * float(np.sum(diff * diff)))


def joint_pose_reward(hinges: np.ndarray, ref_hinges: np.ndarray, alpha: float) -> float:
    """r_q = exp(−α_q ‖q̂ − q‖²) of hinge angles ``(H,)`` (rad) against their reference ``(H,)``
    (contactvision eq. 7)."""
    return squared_error_reward(hinges, ref_hinges, alpha)


def joint_velocity_reward(hinge_rates: np.ndarray, ref_hinge_rates: np.ndarray, alpha: float) -> float:
    """r_v = exp(−α_v ‖v̂ − v‖²) of hinge rates ``(H,)`` (rad/s) against their reference
    (contactvision eq. 7)."""
    return squared_error_reward(hinge_rates, ref_hinge_rates, alpha)


def end_effector_reward(effectors: np.ndarray, pelvis: np.ndarray, ref_effectors: np.ndarray, ref_pelvis: np.ndarray,
                        alpha: float) -> float:
    """r_e = exp(−α_e Σ_e ‖p̂_e − p_e‖²) of end-effector positions ``(E, 3)`` taken relative to
    the pelvis ``(3,)`` (world axes, m), against the reference's (contactvision eq. 7)."""
    return squared_error_reward(np.asarray(effectors) - pelvis, np.asarray(ref_effectors) - ref_pelvis, alpha)


def contact_mismatches(ref_contacts: np.ndarray, contacts: np.ndarray) -> int:
    """Σ_l xor(ĉ_l, c_l)² over the contact channels (LT, RT, LH, RH): how many of the target
    contacts ``ĉ (4,)`` the simulated contacts ``c (4,)`` get wrong (booleans or 0/1)."""
    return int(np.count_nonzero(np.asarray(ref_contacts, dtype=bool) ^ np.asarray(contacts, dtype=bool)))


def contact_reward(ref_contacts: np.ndarray, contacts: np.ndarray, alpha: float) -> float:
    """r_fc = exp(−α_fc Σ_l xor(ĉ_l, c_l)²) (contactvision eq. 4): 1 when every channel of the
    simulated contacts ``c (4,)`` matches the targets ``ĉ (4,)``, exp(−α_fc·n) with n wrong."""
    return math.exp(-alpha * contact_mismatches(ref_contacts, contacts))


def upper_body_tilt(pelvis: np.ndarray, head: np.ndarray) -> float:
    """θ: angle (rad, 0..π) between the pelvis→head vector (positions ``(3,)``, world) and the
    world's vertical (contactvision App. C, r_up)."""
    up = np.asarray(head, dtype=float) - np.asarray(pelvis, dtype=float)
    norm = float(np.linalg.norm(up))
    return math.acos(min(1.0, max(-1.0, float(up[2]) / norm))) if norm > 0 else 0.0


def upper_body_reward(tilt: float, ref_tilt: float, alpha: float) -> float:
    """r_up = exp(−α_up (θ̂ − θ)²) of the upper-body tilts (rad; :func:`upper_body_tilt`) of the
    character and of the reference (contactvision eq. 9)."""
    return math.exp(-alpha * (ref_tilt - tilt) ** 2)


def root_orientation_reward(root_z_axis: np.ndarray, alpha: float) -> float:
    """r_root_ori = exp(−α_root_ori (1 − z_root · ẑ_world)²) of the root body's z axis ``(3,)``
    (a unit vector in world coordinates; contactvision eq. 8)."""
    return math.exp(-alpha * (1.0 - float(np.dot(root_z_axis, WORLD_UP))) ** 2)


def torque_reward(torques: np.ndarray, alpha: float) -> float:
    """r_torque = exp(−α_torque ‖τ‖²) of joint torques ``(H,)`` (contactvision eq. 8); the
    environment passes each actuator's torque over its force limit, so τ is dimensionless."""
    return squared_error_reward(torques, np.zeros_like(torques, dtype=float), alpha)


@dataclass(frozen=True)
class GaitRewardTerms:
    """The seven terms of R = Σ_k w_k r_k (contactvision eq. 6) and ``total`` = R."""

    r_q: float
    r_v: float
    r_e: float
    r_fc: float
    r_up: float
    r_root_ori: float
    r_torque: float
    total: float

    def as_dict(self) -> dict[str, float]:
        return dict(self.__dict__)


GAIT_TERMS = ("r_q", "r_v", "r_e", "r_fc", "r_up", "r_root_ori", "r_torque")
"""Names of the terms of :class:`GaitRewardTerms`, in the order of contactvision eq. 6."""


def gait_reward(terms: dict[str, float], weights: dict[str, float]) -> GaitRewardTerms:
    """R = Σ_k w_k r_k over :data:`GAIT_TERMS`, from each term's value ``terms[name]`` and weight
    ``weights[name]`` (both keyed by the names of :data:`GAIT_TERMS`)."""
    missing = [k for k in GAIT_TERMS if k not in terms or k not in weights]
    if missing:
        raise KeyError(f"gait_reward needs a value and a weight for every term; missing {missing}")
    total = sum(weights[k] * terms[k] for k in GAIT_TERMS)
    return GaitRewardTerms(**{k: float(terms[k]) for k in GAIT_TERMS}, total=float(total))
