"""Differentiable forward kinematics of our MJCF humanoids in PyTorch (for footskate cleanup).

Mirrors MuJoCo's kinematics for these models, whose bodies carry no rest rotation and whose
hinges sit at the body origins: a body's rotation is its parent's times the rotations of its
hinges in MJCF order; its origin is the parent's origin plus the parent's rotation applied to
the body's offset. A test checks it against ``mj_kinematics``.
"""

from __future__ import annotations

import functools

import mujoco
import numpy as np
import torch

from perception.skeleton import joint_map
from reference_motion.humanoid.model import load_model


def _axis_rotation(axis: int, angle: torch.Tensor) -> torch.Tensor:
    """Rotation matrices ``(T, 3, 3)`` about coordinate ``axis`` (0, 1, 2) by ``angle (T,)`` rad."""
    c, s = torch.cos(angle), torch.sin(angle)
    one, zero = torch.ones_like(angle), torch.zeros_like(angle)
    rows = {0: [[one, zero, zero], [zero, c, -s], [zero, s, c]],
            1: [[c, zero, s], [zero, one, zero], [-s, zero, c]],
            2: [[c, -s, zero], [s, c, zero], [zero, zero, one]]}[axis]
    return torch.stack([torch.stack(r, dim=-1) for r in rows], dim=-2)


def quat_to_matrix(q: torch.Tensor) -> torch.Tensor:
    """Rotation matrices ``(..., 3, 3)`` of quaternions ``(..., 4)`` (w, x, y, z; normalised here)."""
    w, x, y, z = (q / q.norm(dim=-1, keepdim=True)).unbind(-1)
    return torch.stack([
        torch.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        torch.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        torch.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


class TorchKinematics:
    """Body frames, the 23 UnderPressure joints and the four sole points of one humanoid model
    as differentiable functions of ``qpos (T, nq)``."""

    def __init__(self, model_name: str):
        hm = load_model(model_name)
        m = hm.model
        if np.abs(m.body_quat[1:] - np.array([1.0, 0.0, 0.0, 0.0])).max() > 1e-9 or np.abs(m.jnt_pos).max() > 1e-9:
            raise ValueError(f"{model_name}: TorchKinematics needs bodies without rest rotation and hinges at "
                             "the body origins")
        self.model_name = model_name
        self.parent = [int(m.body_parentid[b]) - 1 for b in range(1, m.nbody)]   # -1: the world
        self.offset = torch.tensor(m.body_pos[1:], dtype=torch.float32)
        hinges = [j for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
        axes = {j: int(np.argmax(np.abs(m.jnt_axis[j]))) for j in hinges}
        self.hinges = [[(int(m.jnt_qposadr[j]), axes[j], float(m.jnt_axis[j][axes[j]]))
                        for j in hinges if m.jnt_bodyid[j] == b] for b in range(1, m.nbody)]
        """Per body: (qpos column, coordinate axis, ±1) of its hinges in MJCF order."""
        jm = joint_map(model_name)
        self.joint_body, self.joint_offset = list(jm.body), torch.tensor(jm.offset, dtype=torch.float32)
        sites = hm.foot_point_sites
        self.point_body = [int(m.site_bodyid[s]) - 1 for s in sites]
        self.point_offset = torch.tensor(m.site_pos[sites], dtype=torch.float32)

    def bodies(self, qpos: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Body origins ``(T, nbody, 3)`` and rotations ``(T, nbody, 3, 3)`` (world body excluded)."""
        pos, rots = [], []
        for b, parent in enumerate(self.parent):
            if parent < 0:  # the free-floating pelvis
                p, r = qpos[:, :3], quat_to_matrix(qpos[:, 3:7])
            else:
                p = pos[parent] + torch.einsum("tij,j->ti", rots[parent], self.offset[b])
                r = rots[parent]
            for column, axis, sign in self.hinges[b]:
                r = r @ _axis_rotation(axis, sign * qpos[:, column])
            pos.append(p)
            rots.append(r)
        return torch.stack(pos, dim=1), torch.stack(rots, dim=1)

    def points(self, qpos: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """The 23 joints ``(T, 23, 3)`` and the four sole points ``(T, 4, 3)`` (CONTACT_CHANNELS
        order: left_toe, right_toe, left_heel, right_heel) in world coordinates."""
        pos, rot = self.bodies(qpos)
        joints = pos[:, self.joint_body] + torch.einsum("tjab,jb->tja", rot[:, self.joint_body], self.joint_offset)
        soles = pos[:, self.point_body] + torch.einsum("tjab,jb->tja", rot[:, self.point_body], self.point_offset)
        return joints, soles


@functools.lru_cache(maxsize=None)
def torch_kinematics(model_name: str) -> TorchKinematics:
    """Cached :class:`TorchKinematics`."""
    return TorchKinematics(model_name)
