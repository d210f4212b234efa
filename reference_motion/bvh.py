"""BVH loader: hierarchy + motion → :class:`SourceClip` on the canonical joints.

A *name map* says which BVH joint plays each canonical joint (``right_hip → RightUpLeg`` ...).
Canonical end points (``head_end``, ``*_toe_end``, ``*_wrist``) may name a joint or be left out, in
which case the first child (or End Site) of the joint they hang from is used. BVH joints between
mapped ones (extra spine links, clavicles) are folded in by forward kinematics: the canonical
rotation is the relative world rotation of the mapped joints.

Units: BVH offsets are scaled by ``scale`` (default: centimetres → metres when the rig is taller
than 3 units). Axes: y up (converted to the project's z up).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from reference_motion import rotations as rot
from reference_motion.source import CANONICAL_JOINTS, CANONICAL_PARENTS, SourceClip, y_up_quats, y_up_vectors

CMU_NAME_MAP = {
    "root": "Hips", "chest": "Spine1", "neck": "Neck", "head_end": "Head",
    "right_hip": "RightUpLeg", "right_knee": "RightLeg", "right_ankle": "RightFoot", "right_toe_end": "RightToeBase",
    "right_shoulder": "RightArm", "right_elbow": "RightForeArm", "right_wrist": "RightHand",
    "left_hip": "LeftUpLeg", "left_knee": "LeftLeg", "left_ankle": "LeftFoot", "left_toe_end": "LeftToeBase",
    "left_shoulder": "LeftArm", "left_elbow": "LeftForeArm", "left_wrist": "LeftHand",
}
"""CMU / Mixamo / Xsens-style names (Xsens: pass ``chest="Chest"`` etc. in a custom map)."""

_AXIS = {"Xrotation": np.array([1.0, 0, 0]), "Yrotation": np.array([0, 1.0, 0]), "Zrotation": np.array([0, 0, 1.0])}


@dataclass
class _Joint:
    name: str
    parent: int
    offset: np.ndarray
    channels: list[str] = field(default_factory=list)
    children: list[int] = field(default_factory=list)


def _parse(text: str, where: str) -> tuple[list[_Joint], np.ndarray, float]:
    tokens = text.split()
    if not tokens or tokens[0] != "HIERARCHY":
        raise ValueError(f"{where}: not a BVH file (expected 'HIERARCHY' first)")
    joints: list[_Joint] = []
    stack: list[int] = []
    i = 1
    try:
        while tokens[i] != "MOTION":
            tok = tokens[i]
            if tok in ("ROOT", "JOINT"):
                joints.append(_Joint(tokens[i + 1], stack[-1] if stack else -1, np.zeros(3)))
                if stack:
                    joints[stack[-1]].children.append(len(joints) - 1)
                i += 2
            elif tok == "End":  # End Site
                joints.append(_Joint(f"{joints[stack[-1]].name}_end", stack[-1], np.zeros(3)))
                joints[stack[-1]].children.append(len(joints) - 1)
                i += 2
            elif tok == "{":
                stack.append(len(joints) - 1)
                i += 1
            elif tok == "}":
                stack.pop()
                i += 1
            elif tok == "OFFSET":
                joints[stack[-1]].offset = np.array([float(v) for v in tokens[i + 1:i + 4]])
                i += 4
            elif tok == "CHANNELS":
                n = int(tokens[i + 1])
                joints[stack[-1]].channels = tokens[i + 2:i + 2 + n]
                i += 2 + n
            else:
                raise ValueError(f"{where}: unexpected token {tok!r} in HIERARCHY")
        n_frames = int(tokens[i + 2])
        frame_time = float(tokens[i + 5])
        values = np.array([float(v) for v in tokens[i + 6:]])
    except (IndexError, ValueError) as err:
        if isinstance(err, ValueError) and str(err).startswith(where):
            raise
        raise ValueError(f"{where}: malformed or truncated BVH ({err})") from err
    width = sum(len(j.channels) for j in joints)
    if n_frames < 2 or values.size != n_frames * width:
        raise ValueError(f"{where}: expected {n_frames} frames × {width} channels = {n_frames * width} values, "
                         f"found {values.size} (truncated file?)")
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{where}: motion data contains NaN/inf")
    return joints, values.reshape(n_frames, width), frame_time


def load(path: str | Path, name_map: dict[str, str] | None = None, scale: float | None = None) -> SourceClip:
    """Load a BVH file as a :class:`SourceClip` using ``name_map`` (default :data:`CMU_NAME_MAP`)."""
    path = Path(path)
    where = str(path)
    if not path.exists():
        raise FileNotFoundError(f"{where}: no such BVH file")
    joints, frames, frame_time = _parse(path.read_text(), where)
    names = [j.name for j in joints]
    name_map = dict(CMU_NAME_MAP if name_map is None else name_map)
    for canon in CANONICAL_JOINTS:
        if canon.endswith(("_end", "_wrist")) and name_map.get(canon) not in names:
            parent = name_map.get(CANONICAL_PARENTS[canon])
            if parent in names and joints[names.index(parent)].children:
                name_map[canon] = names[joints[names.index(parent)].children[0]]
        if name_map.get(canon) not in names:
            raise ValueError(f"{where}: joint {name_map.get(canon)!r} (for {canon}) is not in the file; "
                             f"fix the name map. Joints in the file: {', '.join(n for n in names if not n.endswith('_end'))}")

    T = frames.shape[0]
    world_pos = np.zeros((T, len(joints), 3))
    world_rot = np.tile([1.0, 0, 0, 0], (T, len(joints), 1))
    col = 0
    for k, joint in enumerate(joints):
        local_pos = np.broadcast_to(joint.offset, (T, 3)).copy()
        local_rot = np.tile([1.0, 0, 0, 0], (T, 1))
        for ch in joint.channels:
            v = frames[:, col]
            col += 1
            if ch in _AXIS:
                local_rot = rot.multiply(local_rot, rot.from_axis_angle(_AXIS[ch], np.radians(v)))
            elif ch.endswith("position"):
                local_pos[:, "XYZ".index(ch[0])] = v
            else:
                raise ValueError(f"{where}: joint {joint.name} has unknown channel {ch!r}")
        if joint.parent < 0:
            world_pos[:, k] = local_pos
            world_rot[:, k] = local_rot
        else:
            world_pos[:, k] = world_pos[:, joint.parent] + rot.rotate(world_rot[:, joint.parent], local_pos)
            world_rot[:, k] = rot.multiply(world_rot[:, joint.parent], local_rot)

    rest = np.zeros((len(joints), 3))
    for k, joint in enumerate(joints):
        rest[k] = joint.offset + (rest[joint.parent] if joint.parent >= 0 else 0)
    if scale is None:
        height = np.ptp(rest[:, 1])
        scale = 0.01 if height > 3.0 else 1.0

    idx = {c: names.index(name_map[c]) for c in CANONICAL_JOINTS}
    offsets = np.zeros((len(CANONICAL_JOINTS), 3))
    local = np.tile([1.0, 0, 0, 0], (T, len(CANONICAL_JOINTS), 1))
    for j, canon in enumerate(CANONICAL_JOINTS):
        b = idx[canon]
        if canon == "root":
            local[:, j] = world_rot[:, b]
            continue
        p = idx[CANONICAL_PARENTS[canon]]
        offsets[j] = (rest[b] - rest[p]) * scale  # mapped joints are connected through rest offsets
        if not canon.endswith(("_end", "_wrist")):
            local[:, j] = rot.multiply(rot.conjugate(world_rot[:, p]), world_rot[:, b])
    # Unmapped joints in between (extra spine links, clavicles) are folded into the relative world
    # rotations above; the offsets are the rest-pose ones, which is all retargeting uses.
    return SourceClip(name=f"bvh:{path.stem}", fps=float(1.0 / frame_time), offsets=y_up_vectors(offsets),
                      root_pos=y_up_vectors(world_pos[:, idx["root"]] * scale),
                      local_quats=rot.normalize(y_up_quats(local)), loop=False,
                      source={"format": "bvh", "file": where, "scale": scale})
