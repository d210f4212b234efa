"""Per-body kinematic state read from MuJoCo, the same way for the simulation and the reference.

The environments need, for every body, its origin position and velocity, orientation and angular
velocity, plus the whole-body centre of mass (CoM) and its velocity. :func:`read_body_state`
reads them from an ``MjData`` whose position- and velocity-dependent quantities are current
(``mj_kinematics``, ``mj_comPos``, ``mj_comVel``, ``mj_subtreeVel``; :func:`update_kinematics`
calls exactly these, which is far cheaper than ``mj_forward``). The reference track is
precomputed with the same two functions, so simulated and reference quantities are defined
identically.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from reference_motion import rotations as rot


@dataclass(frozen=True)
class BodyState:
    """Kinematic state of all ``B`` bodies (world frame, SI); a batch of states has a leading
    axis (one per environment) on every array.

    Attributes:
        pos: ``(B, 3)`` body origins (m).
        quat: ``(B, 4)`` orientations (w, x, y, z).
        axes: ``(B, 3, 3)`` row ``i`` is the body's ``i``-th axis in world coordinates.
        linvel: ``(B, 3)`` velocity of each body origin (m/s).
        angvel: ``(B, 3)`` angular velocity (rad/s).
        com: ``(3,)`` whole-body centre of mass (m).
        com_vel: ``(3,)`` its velocity (m/s).
    """

    pos: np.ndarray
    quat: np.ndarray
    axes: np.ndarray
    linvel: np.ndarray
    angvel: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray


def update_kinematics(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Bring positions, orientations and com-based velocities of ``data`` up to date with its
    ``qpos``/``qvel`` (after ``mj_step`` they lag one substep behind)."""
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    mujoco.mj_comVel(model, data)
    mujoco.mj_subtreeVel(model, data)


def read_body_state(model: mujoco.MjModel, data: mujoco.MjData) -> BodyState:
    """:class:`BodyState` of every body but the world, from an up-to-date ``data``."""
    return body_state(data.xpos[1:].copy(), data.xquat[1:].copy(), data.xmat[1:].copy(), data.cvel[1:].copy(),
                      data.subtree_com[1].copy(), data.subtree_linvel[1].copy())


def body_state(xpos: np.ndarray, xquat: np.ndarray, xmat: np.ndarray, cvel: np.ndarray, com: np.ndarray,
               com_vel: np.ndarray) -> BodyState:
    """:class:`BodyState` from MuJoCo's arrays of the bodies but the world (optionally with leading
    axes, e.g. one per environment; the arrays are kept, not copied).

    Args:
        xpos: ``(..., B, 3)`` body origins (``data.xpos[1:]``).
        xquat: ``(..., B, 4)`` orientations (``data.xquat[1:]``).
        xmat: ``(..., B, 9)`` rotation matrices, row-major (``data.xmat[1:]``).
        cvel: ``(..., B, 6)`` spatial velocities about the tree's CoM (``data.cvel[1:]``).
        com, com_vel: ``(..., 3)`` the pelvis subtree's CoM and its velocity (``data.subtree_com[1]``,
            ``data.subtree_linvel[1]``).

    MuJoCo's ``cvel`` is each body's spatial velocity (angular; linear of the point at the
    tree's CoM ``c``), so the velocity of a point ``p`` on the body is ``v_c + ω × (p − c)``. The
    humanoid is one kinematic tree rooted at the pelvis, so ``c`` (``subtree_com`` of the pelvis)
    is the whole-body CoM and the pelvis ``subtree_linvel`` its velocity.
    """
    omega = cvel[..., :3]
    linvel = cvel[..., 3:] + rot.cross(omega, xpos - com[..., None, :])
    axes = np.swapaxes(xmat.reshape(*xmat.shape[:-1], 3, 3), -1, -2)
    return BodyState(pos=xpos, quat=xquat, axes=axes, linvel=linvel, angvel=omega, com=com, com_vel=com_vel)


def floor_contact_geoms(data: mujoco.MjData, floor: int) -> np.ndarray:
    """Geoms touching geom ``floor`` in ``data``'s current contacts (one entry per contact)."""
    return geoms_touching(data.contact.geom, floor)


def geoms_touching(pairs: np.ndarray, floor: int, owner: np.ndarray | None = None):
    """The other geom of each contact pair ``pairs`` ``(n, 2)`` (MuJoCo's ``contact.geom``) that
    involves geom ``floor``: ``(k,)``, one entry per such contact. With ``owner`` (``(n,)``, the
    simulation each pair comes from, for the pairs of several simulations concatenated), also the
    owner of each entry: ``(touching, owner)``."""
    on_floor = (pairs == floor).any(axis=1)
    touching = np.where(pairs[:, 0] == floor, pairs[:, 1], pairs[:, 0])[on_floor]
    return touching if owner is None else (touching, owner[on_floor])


def region_contacts(touching: np.ndarray, geom_channel: np.ndarray, owner: np.ndarray | None = None,
                    n_owners: int = 1) -> np.ndarray:
    """Contact states ``(4,)`` bool (LT, RT, LH, RH): any sole sphere of that region among the
    floor-touching geoms ``touching``; ``geom_channel`` is each geom's channel or -1
    (:attr:`reference_motion.humanoid.model.HumanoidModel.geom_contact_channel`). With ``owner``
    (``(k,)``, which of ``n_owners`` simulations each entry of ``touching`` comes from) the states
    of each, ``(n_owners, 4)``."""
    channels = geom_channel[touching]
    sole = channels >= 0
    if owner is None:
        out = np.zeros(4, dtype=bool)
        out[channels[sole]] = True
        return out
    out = np.zeros((n_owners, 4), dtype=bool)
    out[owner[sole], channels[sole]] = True
    return out


def bodies_touching(touching: np.ndarray, geom_body: np.ndarray, owner: np.ndarray | None = None,
                    n_owners: int = 1) -> int | np.ndarray:
    """How many distinct bodies of interest the floor-touching geoms ``touching`` belong to;
    ``geom_body`` is each geom's body, or -1 for geoms of no interest. With ``owner`` (``(k,)``,
    which of ``n_owners`` simulations each entry comes from) the count of each, ``(n_owners,)`` int."""
    bodies = geom_body[touching]
    mine = bodies >= 0
    if owner is None:
        return len(set(bodies[mine].tolist()))
    stride = max(int(geom_body.max()), 0) + 1
    pairs = np.unique(owner[mine] * stride + bodies[mine])
    return np.bincount(pairs // stride, minlength=n_owners)
