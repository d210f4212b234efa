"""Reference tracks: everything the reward and observation need from a clip, computed once.

A :class:`ReferenceTrack` is built per clip (and per corrupted variant of a clip) when the
environment first needs it; each step then only indexes arrays.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields

import mujoco
import numpy as np

from envs.bodies import read_body_state, update_kinematics
from envs.observations import heading_rotation
from envs.rewards import cube_face_points, cube_face_velocities
from reference_motion import rotations as rot
from reference_motion.humanoid.model import HumanoidModel
from reference_motion.motion import Motion


@dataclass(frozen=True)
class ReferenceQuantities:
    """The per-body reference quantities the reward and observation compare against (``B`` bodies,
    ``J`` jointed bodies; world frame, SI), each with the leading axes of its holder: ``(T, ...)``
    in a :class:`ReferenceTrack`, none in a :class:`ReferenceFrame`, ``(N, ...)`` in a batch of frames.

    Attributes:
        pos: ``(B, 3)`` body origins.
        pos_rel_com: ``(B, 3)`` body origins relative to the reference CoM.
        com: ``(3,)`` the reference's centre of mass.
        linvel: ``(B, 3)`` body origin velocities.
        com_vel: ``(3,)`` CoM velocity.
        local: ``(J, 4)`` rotations of the jointed bodies relative to their parents.
        faces_rel_root: ``(B, 6, 3)`` cube face points relative to the root body's origin.
        face_vel: ``(B, 6, 3)`` cube face point velocities.
        to_heading: ``(3, 3)`` world → the reference root's heading axes, a turn about z
            (:func:`envs.observations.heading_rotation`; the ``"reference"`` observation frame).
    """

    pos: np.ndarray
    pos_rel_com: np.ndarray
    com: np.ndarray
    linvel: np.ndarray
    com_vel: np.ndarray
    local: np.ndarray
    faces_rel_root: np.ndarray
    face_vel: np.ndarray
    to_heading: np.ndarray


@dataclass(frozen=True)
class ReferenceFrame(ReferenceQuantities):
    """One frame of a :class:`ReferenceTrack`, or a batch of frames (:meth:`gather`)."""

    @classmethod
    def gather(cls, tracks: Sequence["ReferenceTrack"], frames: Sequence[int]) -> "ReferenceFrame":
        """Frame ``frames[i]`` of ``tracks[i]`` for each of ``N`` tracks, as one batch: every field
        ``(N, ...)``."""
        return cls(*(np.stack([getattr(t, name)[f] for t, f in zip(tracks, frames)]) for name in _QUANTITIES))


_QUANTITIES = tuple(f.name for f in fields(ReferenceQuantities))


@dataclass(frozen=True)
class ReferenceTrack(ReferenceQuantities):
    """Per-frame reference quantities of one clip on one model (``T`` frames): those of
    :class:`ReferenceQuantities` with a leading time axis (the per-body arrays other than ``pos``
    float32), and:

    Attributes:
        motion: the clip.
        ctrl: ``(T, nu)`` each actuator's hinge angle (rad): the open-loop PD targets, led by
            the hinge's velocity when the env feeds it forward (:func:`pd_targets`).
        qvel: ``(T, nv)`` generalised velocities, for reference state initialisation and the
            velocity feed-forward.
    """

    motion: Motion
    ctrl: np.ndarray
    qvel: np.ndarray

    @property
    def n_frames(self) -> int:
        return self.motion.n_frames

    def frame(self, f: int) -> ReferenceFrame:
        """The per-body quantities of frame ``f`` that the reward and observation compare against."""
        return ReferenceFrame(*(getattr(self, name)[f] for name in _QUANTITIES))

    @classmethod
    def build(cls, motion: Motion, model: HumanoidModel, actuator_qpos: np.ndarray, jointed: np.ndarray,
              parent: np.ndarray, cube_size: float) -> "ReferenceTrack":
        """Replay ``motion`` kinematically on ``model`` and collect every per-frame quantity.

        Args:
            actuator_qpos: ``(nu,)`` qpos index of each actuator's hinge.
            jointed: ``(J,)`` indices of the bodies whose local rotation the pose reward compares.
            parent: ``(B,)`` parent index of each body (``-1`` for the root).
            cube_size: edge (m) of the cube of the face-point rewards.
        """
        m = model.model
        data = mujoco.MjData(m)
        qvel = motion.qvel
        T, B = motion.n_frames, m.nbody - 1
        pos, linvel, angvel = np.empty((T, B, 3)), np.empty((T, B, 3)), np.empty((T, B, 3))
        quat, axes = np.empty((T, B, 4)), np.empty((T, B, 3, 3))
        com, com_vel = np.empty((T, 3)), np.empty((T, 3))
        for t in range(T):
            data.qpos[:] = motion.qpos[t]
            data.qvel[:] = qvel[t]
            update_kinematics(m, data)
            s = read_body_state(m, data)
            pos[t], linvel[t], angvel[t], quat[t], axes[t], com[t], com_vel[t] = (
                s.pos, s.linvel, s.angvel, s.quat, s.axes, s.com, s.com_vel)
        faces = cube_face_points(pos, axes, cube_size) - pos[:, :1, None, :]
        f32 = np.float32  # the bulky per-body arrays: half the memory, errors ~1e-6 m
        return cls(motion=motion, ctrl=motion.qpos[:, actuator_qpos], qvel=qvel, pos=pos,
                   pos_rel_com=(pos - com[:, None, :]).astype(f32), com=com, linvel=linvel.astype(f32), com_vel=com_vel,
                   local=rot.relative_to_parent(quat, parent)[:, jointed].astype(f32), faces_rel_root=faces.astype(f32),
                   face_vel=cube_face_velocities(linvel, angvel, axes, cube_size).astype(f32),
                   to_heading=heading_rotation(axes[:, 0, 0]))


def pd_targets(angles: np.ndarray, rates: np.ndarray, lead_s: np.ndarray | None) -> np.ndarray:
    """The position targets ``(..., nu)`` (rad) of MuJoCo PD actuators tracking reference hinge
    ``angles (..., nu)`` (rad) moving at ``rates (..., nu)`` (rad/s) (one frame, or several).

    A MuJoCo position actuator applies ``kp·(ctrl − q) − kv·q̇``: with ``ctrl`` the reference angle
    its damping pulls the joint towards rest, so a joint following a moving reference trails it.
    With ``lead_s`` = ``kv / kp`` per actuator (s) the target leads by ``lead_s · rates``, and the
    force becomes ``kp·(q_ref − q) + kv·(q̇_ref − q̇)``: PD on the reference's angle and velocity.
    ``lead_s=None`` returns ``angles`` (ADAPT's targets)."""
    return angles if lead_s is None else angles + lead_s * rates
