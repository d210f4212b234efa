"""Loaded humanoid model: names, qpos layout, batched forward kinematics and contact readouts.

qpos layout of both models: ``[0:3]`` pelvis position (world, m), ``[3:7]`` pelvis quaternion
(w, x, y, z), ``[7:]`` one angle (rad) per hinge, in MJCF order. qvel: ``[0:3]`` linear velocity
(world), ``[3:6]`` angular velocity (pelvis frame), ``[6:]`` hinge rates.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import mujoco
import numpy as np

from reference_motion.humanoid import anthropometry as A
from reference_motion.humanoid.builder import ASSET_DIR, HEEL_CELLS, MODEL_NAMES, TOE_CELLS

CONTACT_CHANNELS = ("left_toe", "right_toe", "left_heel", "right_heel")
"""Order of every 4-channel contact array in the project (ContactVision order)."""
FOOT_CHANNELS = ((0, 2), (1, 3))
"""Per foot (left, right): the (toe, heel) columns of a CONTACT_CHANNELS array."""


@dataclass(frozen=True)
class BodyJoints:
    """Hinges of one body: qpos indices ``(n,)`` and unit axes ``(n, 3)`` in the body frame."""

    body: str
    axes: str
    qpos_index: np.ndarray
    axis_vectors: np.ndarray


class HumanoidModel:
    """A compiled ``humanoid_1seg`` / ``humanoid_2seg`` with the lookups the project needs.

    Args:
        name: ``"humanoid_1seg"`` or ``"humanoid_2seg"``.
    """

    def __init__(self, name: str):
        if name not in MODEL_NAMES:
            raise ValueError(f"unknown humanoid model {name!r}; expected one of {', '.join(MODEL_NAMES)}")
        self.name = name
        self.path = ASSET_DIR / f"{name}.xml"
        self.model = mujoco.MjModel.from_xml_path(str(self.path))
        self._data = mujoco.MjData(self.model)
        m = self.model
        self.nq, self.nv = m.nq, m.nv
        self.body_names = [m.body(i).name for i in range(1, m.nbody)]
        """Body names in MJCF order, world excluded (20 or 22)."""
        self.hinge_names = [m.joint(i).name for i in range(1, m.njnt)]
        """Hinge joint names in qpos order (qpos index = 7 + position in this list)."""
        self.total_mass = float(m.body_subtreemass[1])
        self.body_joints: dict[str, BodyJoints] = {}
        for b in range(1, m.nbody):
            jids = [j for j in range(m.njnt) if m.jnt_bodyid[j] == b and m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
            if not jids:
                continue
            axes = "".join("xyz"[int(np.argmax(np.abs(m.jnt_axis[j])))] for j in jids)
            self.body_joints[m.body(b).name] = BodyJoints(
                m.body(b).name, axes, np.array([m.jnt_qposadr[j] for j in jids]),
                np.array([m.jnt_axis[j] for j in jids]))
        self.foot_point_sites = np.array([m.site(f"{s}_{p}_point").id
                                          for p, s in (("toe", "l"), ("toe", "r"), ("heel", "l"), ("heel", "r"))])
        """Site ids of the four foot points, in :data:`CONTACT_CHANNELS` order."""
        self._floor_geom = m.geom("floor").id
        f = self._floor_geom
        self._floor_colliding_geoms = np.array([
            g for g in range(m.ngeom) if g != f
            and (m.geom_contype[g] & m.geom_conaffinity[f] or m.geom_conaffinity[g] & m.geom_contype[f])])
        """Geoms that can touch the floor: the sole spheres and the body (not the foot boxes)."""
        self._sole_cell = self._sole_geom_cells()
        self.geom_contact_channel = self._geom_contact_channels()
        """Per geom: its :data:`CONTACT_CHANNELS` index if it is a heel- or toe-cell sole sphere, else -1."""
        self._body_cell_sites = self._cell_sites_by_body()
        self._collision_group = self._geom_groups()

    # ------------------------------------------------------------------ layout
    def qpos_index(self, joint: str) -> int:
        """qpos index of hinge ``joint``; raises ``KeyError`` naming the model."""
        try:
            return int(self.model.jnt_qposadr[self.model.joint(joint).id])
        except KeyError as err:
            raise KeyError(f"model {self.name} has no joint {joint!r}") from err

    @property
    def leg_qpos_columns(self) -> np.ndarray:
        """qpos indices of the hinges from the hips down (thighs, shins, feet and toes)."""
        legs = ("thigh", "shin", "foot", "toe")
        return np.concatenate([j.qpos_index for name, j in self.body_joints.items() if name[2:] in legs])

    @property
    def hinge_ranges(self) -> tuple[np.ndarray, np.ndarray]:
        """The limited hinges: their qpos indices ``(n,)`` and ranges ``(n, 2)`` (rad; lower, upper)."""
        m = self.model
        limited = [j for j in range(1, m.njnt) if m.jnt_limited[j]]
        return m.jnt_qposadr[limited].copy(), m.jnt_range[limited].copy()

    def hinge_range(self, joint: str) -> tuple[float, float]:
        """The range ``(lower, upper)`` (rad) of the limited hinge ``joint`` (one of :attr:`hinge_ranges`)."""
        limited, ranges = self.hinge_ranges
        index = self.qpos_index(joint)
        if index not in limited:
            raise KeyError(f"model {self.name}: joint {joint!r} has no range")
        low, high = ranges[list(limited).index(index)]
        return float(low), float(high)

    def body_id(self, body: str) -> int:
        try:
            return self.model.body(body).id
        except KeyError as err:
            raise KeyError(f"model {self.name} has no body {body!r}") from err

    def rest_qpos(self) -> np.ndarray:
        """Rest pose ``(nq,)``: standing, arms hanging, soles on the floor, facing +x."""
        return self.model.qpos0.copy()

    # ------------------------------------------------------------ kinematics
    def forward_kinematics(self, qpos: np.ndarray) -> "Kinematics":
        """World-frame body and foot-point positions, lowest points and centre of mass for every
        frame of ``qpos (T, nq)``."""
        qpos = np.atleast_2d(np.asarray(qpos, dtype=float))
        if qpos.shape[1] != self.nq:
            raise ValueError(f"qpos has {qpos.shape[1]} columns but model {self.name} has nq={self.nq}")
        m, d = self.model, self._data
        T = qpos.shape[0]
        body_pos = np.empty((T, m.nbody - 1, 3))
        body_quat = np.empty((T, m.nbody - 1, 4))
        points = np.empty((T, 4, 3))
        geoms = self._floor_colliding_geoms
        geom_z = np.empty((T, len(geoms)))
        geom_zrow = np.empty((T, len(geoms), 3))  # third row of each geom's rotation matrix
        com = np.empty((T, 3))
        mass = m.body_mass / m.body_mass.sum()
        for t in range(T):
            d.qpos[:] = qpos[t]
            mujoco.mj_kinematics(m, d)
            body_pos[t] = d.xpos[1:]
            body_quat[t] = d.xquat[1:]
            points[t] = d.site_xpos[self.foot_point_sites]
            geom_z[t] = d.geom_xpos[geoms, 2]
            geom_zrow[t] = d.geom_xmat[geoms, 6:9]
            com[t] = mass @ d.xipos
        return Kinematics(body_pos, body_quat, points, self._lowest_geom_points(geom_z, geom_zrow), com)

    def _lowest_geom_points(self, geom_z: np.ndarray, geom_zrow: np.ndarray) -> np.ndarray:
        """Lowest z (m) per frame over the floor-colliding geoms, analytic per geom type, from their
        centres' heights ``(T, G)`` and the third rows of their rotation matrices ``(T, G, 3)``."""
        m = self.model
        geoms = self._floor_colliding_geoms
        size, typ = m.geom_size[geoms], m.geom_type[geoms]
        sphere = size[:, 0]
        capsule = np.abs(geom_zrow[..., 2]) * size[:, 1] + size[:, 0]  # the capsule axis is local z
        box = np.einsum("tgk,gk->tg", np.abs(geom_zrow), size)  # lowest corner
        reach = np.where(typ == mujoco.mjtGeom.mjGEOM_SPHERE, sphere,
                         np.where(typ == mujoco.mjtGeom.mjGEOM_CAPSULE, capsule, box))
        return np.min(geom_z - reach, axis=1)

    # ------------------------------------------------------- self-collision
    def _geom_groups(self) -> np.ndarray:
        """Per geom: 0 other, 1 left leg, 2 right leg, 3 arm, 4 torso."""
        groups = np.zeros(self.model.ngeom, dtype=int)
        for g in range(self.model.ngeom):
            ct = self.model.geom_contype[g]
            groups[g] = {A.LEFT_LEG_BIT: 1, A.RIGHT_LEG_BIT: 2, A.ARM_BIT: 3, A.TORSO_BIT: 4}.get(int(ct), 0)
        return groups

    def self_penetration(self, qpos: np.ndarray, tolerance: float = 0.005) -> np.ndarray:
        """Per frame, whether any leg–leg or arm–torso geom pair overlaps by more than
        ``tolerance`` (m). ``qpos (T, nq)`` → bool ``(T,)``."""
        qpos = np.atleast_2d(np.asarray(qpos, dtype=float))
        m, d = self.model, self._data
        out = np.zeros(qpos.shape[0], dtype=bool)
        grp = self._collision_group
        for t in range(qpos.shape[0]):
            d.qpos[:] = qpos[t]
            mujoco.mj_fwdPosition(m, d)
            for c in d.contact[: d.ncon]:
                pair = {int(grp[c.geom1]), int(grp[c.geom2])}
                if c.dist < -tolerance and pair in ({1, 2}, {3, 4}):
                    out[t] = True
                    break
        return out

    # ---------------------------------------------------------------- insole
    def _cell_sites_by_body(self) -> dict[int, list[tuple[int, int]]]:
        """Map of foot/toe body id → [(cell index, cell site id), ...] for the cells on that body."""
        out: dict[int, list[tuple[int, int]]] = {}
        for side in ("l", "r"):
            for cell in range(16):
                sid = self.model.site(f"{side}_cell{cell:02d}").id
                out.setdefault(int(self.model.site_bodyid[sid]), []).append((cell, sid))
        return out

    def _sole_geom_cells(self) -> dict[int, tuple[int, int]]:
        """Map of sole geom id → (foot index 0 left / 1 right, cell index)."""
        out = {}
        for g in range(self.model.ngeom):
            name = self.model.geom(g).name
            if "_sole" in name:
                out[g] = (0 if name[0] == "l" else 1, int(name[-2:]))
        return out

    def _geom_contact_channels(self) -> np.ndarray:
        out = np.full(self.model.ngeom, -1)
        for geom, (foot, cell) in self._sole_cell.items():
            region = "heel" if cell in HEEL_CELLS else "toe" if cell in TOE_CELLS else None
            if region:
                out[geom] = CONTACT_CHANNELS.index(f"{('left', 'right')[foot]}_{region}")
        return out

    def cell_forces(self, data: mujoco.MjData) -> np.ndarray:
        """Vertical ground reaction force per insole cell, ``(2, 16)`` (left, right) in body weights.

        The normal force of each floor contact is added to the cell whose site rectangle contains
        the contact point (in the cell's body frame); a point outside every rectangle goes to
        the nearest cell of the same foot.
        """
        out = np.zeros((2, 16))
        force = np.zeros(6)
        weight = self.total_mass * -self.model.opt.gravity[2]
        for i in range(data.ncon):
            c = data.contact[i]
            if self._floor_geom not in (c.geom1, c.geom2):
                continue
            other = c.geom2 if c.geom1 == self._floor_geom else c.geom1
            if other not in self._sole_cell:
                continue
            mujoco.mj_contactForce(self.model, data, i, force)
            foot, _ = self._sole_cell[other]
            out[foot, self.cell_of_point(data, other, c.pos)] += force[0]
        return out / weight

    def cell_of_point(self, data: mujoco.MjData, geom: int, point: np.ndarray) -> int:
        """Insole cell (0–15) of a world ``point`` (3,) touching sole geom ``geom``: the cell whose
        site rectangle on that geom's body contains it, else the nearest such cell."""
        best, best_d = 0, np.inf
        for cell, sid in self._body_cell_sites[int(self.model.geom_bodyid[geom])]:
            local = data.site_xmat[sid].reshape(3, 3).T @ (point - data.site_xpos[sid])
            excess = np.maximum(np.abs(local[:2]) - self.model.site_size[sid][:2], 0.0)
            dist = float(np.linalg.norm(excess))
            if dist < best_d:
                best, best_d = cell, dist
        return best

    def foot_contacts(self, data: mujoco.MjData, cells: np.ndarray | None = None,
                      threshold: float = 0.05) -> np.ndarray:
        """Physics contact state ``(4,)`` bool in :data:`CONTACT_CHANNELS` order: a region is in
        contact when its cells carry at least ``threshold`` body weights (heel cells 0–3, toe
        cells 8–15)."""
        cells = self.cell_forces(data) if cells is None else cells
        toe = cells[:, list(TOE_CELLS)].sum(1)
        heel = cells[:, list(HEEL_CELLS)].sum(1)
        return np.array([toe[0], toe[1], heel[0], heel[1]]) >= threshold


@dataclass(frozen=True)
class Kinematics:
    """Forward kinematics of a clip (world frame, m).

    Attributes:
        body_pos: ``(T, nbody, 3)`` body origins.
        body_quat: ``(T, nbody, 4)`` body orientations (w, x, y, z).
        foot_points: ``(T, 4, 3)`` sole points in :data:`CONTACT_CHANNELS` order.
        lowest: ``(T,)`` lowest z of the geometry that can touch the floor (the sole spheres stand
            in for the soles; the foot boxes only collide with the other leg).
        com: ``(T, 3)`` the whole body's centre of mass.
    """

    body_pos: np.ndarray
    body_quat: np.ndarray
    foot_points: np.ndarray
    lowest: np.ndarray
    com: np.ndarray


@functools.lru_cache(maxsize=None)
def load_model(name: str) -> HumanoidModel:
    """Cached :class:`HumanoidModel` (one compile per process and model)."""
    return HumanoidModel(name)
