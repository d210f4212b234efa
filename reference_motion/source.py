"""Source rigs: skeleton animation as loaded from a mocap file, before retargeting.

Every loader (DeepMimic, BVH) produces a :class:`SourceClip` on the *canonical joints* below,
already converted to the project's world frame (z up, m). The retargeter maps canonical joints
onto the MJCF humanoids.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from reference_motion import rotations as rot

CANONICAL_JOINTS = (
    "root", "chest", "neck", "head_end",
    "right_hip", "right_knee", "right_ankle", "right_toe_end",
    "right_shoulder", "right_elbow", "right_wrist",
    "left_hip", "left_knee", "left_ankle", "left_toe_end",
    "left_shoulder", "left_elbow", "left_wrist",
)
"""Joints every source rig provides. ``*_end`` and ``*_wrist`` are bone end points (their own
rotation is unused)."""

CANONICAL_PARENTS = {
    "chest": "root", "neck": "chest", "head_end": "neck",
    "right_hip": "root", "right_knee": "right_hip", "right_ankle": "right_knee",
    "right_toe_end": "right_ankle", "right_shoulder": "chest", "right_elbow": "right_shoulder",
    "right_wrist": "right_elbow",
    "left_hip": "root", "left_knee": "left_hip", "left_ankle": "left_knee",
    "left_toe_end": "left_ankle", "left_shoulder": "chest", "left_elbow": "left_shoulder",
    "left_wrist": "left_elbow",
}

BONES = {
    # rotating joint: the joint at the far end of its bone (defines the bone direction)
    "root": "chest", "chest": "neck", "neck": "head_end",
    "right_hip": "right_knee", "right_knee": "right_ankle", "right_ankle": "right_toe_end",
    "right_shoulder": "right_elbow", "right_elbow": "right_wrist",
    "left_hip": "left_knee", "left_knee": "left_ankle", "left_ankle": "left_toe_end",
    "left_shoulder": "left_elbow", "left_elbow": "left_wrist",
}

Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""(x, y, z)_y-up → (x, −z, y)_z-up (SPEC "Data": source +x forward, +z right)."""


def y_up_vectors(v: np.ndarray) -> np.ndarray:
    """Convert y-up vectors ``(..., 3)`` to the z-up world."""
    return np.asarray(v, dtype=float) @ Y_UP_TO_Z_UP.T


def y_up_quats(q: np.ndarray) -> np.ndarray:
    """Convert y-up rotations ``(..., 4)`` (w, x, y, z) to the z-up world (conjugation by the
    proper rotation :data:`Y_UP_TO_Z_UP`)."""
    q = np.asarray(q, dtype=float)
    return np.concatenate([q[..., :1], y_up_vectors(q[..., 1:])], axis=-1)


@dataclass(frozen=True)
class SourceClip:
    """Skeleton animation on the canonical joints, z-up world, uniform frame rate.

    Attributes:
        name: clip name.
        fps: frames per second.
        offsets: ``(J, 3)`` rest offset of each canonical joint from its parent (m, parent frame).
        root_pos: ``(T, 3)`` root joint position (m, world).
        local_quats: ``(T, J, 4)`` rotation of each joint relative to its parent (the root's is
            its world orientation); end points carry identity.
        loop: cyclic clip whose last frame repeats the first (DeepMimic ``"wrap"``).
        source: metadata (file, format, ...).
    """

    name: str
    fps: float
    offsets: np.ndarray
    root_pos: np.ndarray
    local_quats: np.ndarray
    loop: bool = False
    source: dict = field(default_factory=dict)

    @property
    def n_frames(self) -> int:
        return int(self.root_pos.shape[0])

    def global_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """World joint positions ``(T, J, 3)`` and rotations ``(T, J, 4)`` by forward kinematics."""
        T, J = self.n_frames, len(CANONICAL_JOINTS)
        pos = np.zeros((T, J, 3))
        quat = np.zeros((T, J, 4))
        for j, name in enumerate(CANONICAL_JOINTS):
            if name == "root":
                pos[:, j] = self.root_pos
                quat[:, j] = self.local_quats[:, j]
                continue
            p = CANONICAL_JOINTS.index(CANONICAL_PARENTS[name])
            pos[:, j] = pos[:, p] + rot.rotate(quat[:, p], self.offsets[j])
            quat[:, j] = rot.multiply(quat[:, p], self.local_quats[:, j])
        return pos, quat

    def rest_bone_directions(self) -> dict[str, np.ndarray]:
        """Unit direction ``(3,)`` of each rotating joint's bone in the rest pose (world)."""
        pos = np.zeros((len(CANONICAL_JOINTS), 3))
        for j, name in enumerate(CANONICAL_JOINTS):
            if name != "root":
                pos[j] = pos[CANONICAL_JOINTS.index(CANONICAL_PARENTS[name])] + self.offsets[j]
        out = {}
        for joint, end in BONES.items():
            d = pos[CANONICAL_JOINTS.index(end)] - pos[CANONICAL_JOINTS.index(joint)]
            out[joint] = d / np.linalg.norm(d)
        return out

    def leg_length(self) -> float:
        """Hip-to-ankle length (m), mean of both legs, in the rest pose."""
        j = CANONICAL_JOINTS.index
        return float(np.mean([np.linalg.norm(self.offsets[j(f"{s}_knee")]) + np.linalg.norm(self.offsets[j(f"{s}_ankle")])
                              for s in ("left", "right")]))


def sample_poses(times: np.ndarray, positions: np.ndarray, quats: np.ndarray,
                 new_times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Interpolate poses at ``new_times (N,)`` (s): positions ``(T, ..., 3)`` linearly, quaternions
    ``(T, ..., 4)`` by slerp. ``times (T,)`` must increase; ``new_times`` must lie within them."""
    times = np.asarray(times, dtype=float)
    new_times = np.clip(np.asarray(new_times, dtype=float), times[0], times[-1])
    i = np.clip(np.searchsorted(times, new_times, side="right") - 1, 0, len(times) - 2)
    frac = (new_times - times[i]) / (times[i + 1] - times[i])
    shape = (-1,) + (1,) * (positions.ndim - 1)
    pos = positions[i] + (positions[i + 1] - positions[i]) * frac.reshape(shape)
    q_frac = np.broadcast_to(frac.reshape((-1,) + (1,) * (quats.ndim - 2)), (len(frac),) + quats.shape[1:-1])
    return pos, rot.slerp(quats[i], quats[i + 1], q_frac)


def uniform_timing(times: np.ndarray, root_pos: np.ndarray, local_quats: np.ndarray,
                   fps: float) -> tuple[np.ndarray, np.ndarray]:
    """Resample poses given at ``times (T,)`` to a uniform ``fps``; returns ``root_pos`` and
    ``local_quats``. Already-uniform input at that rate is returned unchanged."""
    if np.allclose(np.diff(times), 1.0 / fps, rtol=1e-4, atol=1e-6):
        return root_pos, local_quats
    n = int(np.floor(times[-1] * fps + 1e-6)) + 1
    return sample_poses(times, root_pos, local_quats, np.arange(n) / fps)


KNEE_AXIS_FALLBACK = 0.05
"""Weight of the parent's lateral axis in a limb's hinge axis (:func:`clip_from_joint_positions`):
the bend plane of a knee or elbow defines the limb's twist once the joint is bent a few degrees;
for a straight limb this weight keeps the axis on the parent's lateral direction."""

_LIMBS = {
    # upper joint: (middle joint, end joint, frame giving the fallback lateral axis, bend sign)
    # legs fold backwards, arms forwards: (upper × lower bone) is +lateral for a bent knee and
    # −lateral for a bent elbow in a body facing +x with lateral +y (left).
    "left_hip": ("left_knee", "left_ankle", "root", 1.0),
    "right_hip": ("right_knee", "right_ankle", "root", 1.0),
    "left_shoulder": ("left_elbow", "left_wrist", "chest", -1.0),
    "right_shoulder": ("right_elbow", "right_wrist", "chest", -1.0),
}


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.maximum(n, 1e-12)


def _frame(primary: np.ndarray, lateral: np.ndarray, primary_axis: int) -> np.ndarray:
    """Rotation matrices ``(T, 3, 3)`` whose column ``primary_axis`` (0 = x, 2 = z) is the unit
    ``primary ``(T, 3)`` and whose y column is ``lateral`` made orthogonal to it."""
    p = _unit(primary)
    y = _unit(lateral - np.sum(lateral * p, -1, keepdims=True) * p)
    if primary_axis == 2:
        x = np.cross(y, p)
        return np.stack([x, y, p], axis=-1)
    z = np.cross(p, y)
    return np.stack([p, y, z], axis=-1)


def clip_from_joint_positions(name: str, fps: float, positions: np.ndarray, loop: bool = False,
                              source: dict | None = None) -> SourceClip:
    """A :class:`SourceClip` from world positions of the canonical joints alone.

    Mocap rigs disagree on everything but where the joints are: rest poses (T-pose, A-pose, bones
    along each joint's local x), joint orientations, channel orders. This builds every segment's
    world frame from joint positions, in one convention whose rest pose (all frames = identity)
    stands upright facing +x with y to the left:

    * pelvis: z along root → chest, y along right hip → left hip;
    * chest: z along chest → neck, y along right shoulder → left shoulder; neck: z along
      neck → head end, y from the chest;
    * thigh and shin: −z along the bone, y along the knee's hinge axis (the normal of the plane
      of hip, knee and ankle; the pelvis's y while the leg is straight, see
      :data:`KNEE_AXIS_FALLBACK`), so the knee is a pure hinge; upper arm and forearm alike with
      the elbow and the chest's y;
    * foot: x along ankle → toe end, y from the shin.

    Rest offsets are each joint's mean position in its parent's frame. Twist about a limb's own
    axis other than what the hinge plane fixes (forearm pronation, foot inversion, head yaw
    relative to the neck line) is not recovered; the humanoids' retargeting does not use it.

    Args:
        name: clip name.
        fps: frame rate (Hz).
        positions: ``(T, J, 3)`` world positions (m, z up) in :data:`CANONICAL_JOINTS` order.
        loop: cyclic clip.
        source: metadata to keep.

    Raises:
        ValueError: wrong shape, NaN/inf, or a zero-length bone (two canonical joints mapped onto
            the same point).
    """
    pos = np.asarray(positions, dtype=float)
    where = (source or {}).get("file", name)
    if pos.ndim != 3 or pos.shape[1:] != (len(CANONICAL_JOINTS), 3):
        raise ValueError(f"{where}: joint positions must be (T, {len(CANONICAL_JOINTS)}, 3), got {pos.shape}")
    if not np.all(np.isfinite(pos)):
        raise ValueError(f"{where}: joint positions contain NaN/inf")
    j = CANONICAL_JOINTS.index
    p = {n: pos[:, j(n)] for n in CANONICAL_JOINTS}
    for child, parent in CANONICAL_PARENTS.items():
        if np.median(np.linalg.norm(p[child] - p[parent], axis=-1)) < 1e-4:
            raise ValueError(f"{where}: joints {parent!r} and {child!r} are at the same place (zero-length bone); "
                             "map one of them to another joint of the rig")
    frames: dict[str, np.ndarray] = {}
    frames["root"] = _frame(p["chest"] - p["root"], p["left_hip"] - p["right_hip"], 2)
    frames["chest"] = _frame(p["neck"] - p["chest"], p["left_shoulder"] - p["right_shoulder"], 2)
    frames["neck"] = _frame(p["head_end"] - p["neck"], frames["chest"][..., 1], 2)
    for upper, (middle, end, lateral_from, sign) in _LIMBS.items():
        bone_a, bone_b = p[middle] - p[upper], p[end] - p[middle]
        hinge = sign * np.cross(_unit(bone_a), _unit(bone_b))
        lateral = hinge + KNEE_AXIS_FALLBACK * frames[lateral_from][..., 1]
        frames[upper] = _frame(-bone_a, lateral, 2)
        frames[middle] = _frame(-bone_b, lateral, 2)
    for side in ("left", "right"):
        frames[f"{side}_ankle"] = _frame(p[f"{side}_toe_end"] - p[f"{side}_ankle"], frames[f"{side}_knee"][..., 1], 0)

    T = pos.shape[0]
    world = np.tile([1.0, 0.0, 0.0, 0.0], (T, len(CANONICAL_JOINTS), 1))
    for joint, matrix in frames.items():
        world[:, j(joint)] = rot.from_matrix(matrix)
    offsets = np.zeros((len(CANONICAL_JOINTS), 3))
    local = world.copy()  # end points keep identity
    for joint, parent in CANONICAL_PARENTS.items():
        offsets[j(joint)] = np.mean(rot.rotate(rot.conjugate(world[:, j(parent)]), p[joint] - p[parent]), axis=0)
        if joint in frames:
            local[:, j(joint)] = rot.multiply(rot.conjugate(world[:, j(parent)]), world[:, j(joint)])
    return SourceClip(name=name, fps=float(fps), offsets=offsets, root_pos=p["root"].copy(),
                      local_quats=rot.normalize(local), loop=loop, source=dict(source or {}))
