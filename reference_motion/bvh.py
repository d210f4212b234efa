"""BVH loader: hierarchy + motion → :class:`SourceClip` on the canonical joints.

BVH as found in the wild: 3 or 6 channels on any joint, rotation channels in any order, any rest
pose. Every joint's world position is computed by forward kinematics; the rig (which joint plays
each canonical joint), the length unit and the up axis are detected from those positions
(:mod:`reference_motion.rigs`, each with an override), and the clip is rebuilt from the canonical
joints' positions (:func:`~reference_motion.source.clip_from_joint_positions`), so joint
orientations and rest poses of the file never matter. End Sites are joints named ``<parent>_end``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from reference_motion import rotations as rot
from reference_motion.motion import MotionError, read_text
from reference_motion.rigs import MocapOptions, canonical_positions, match_rig
from reference_motion.source import SourceClip, clip_from_joint_positions

_AXIS = {"Xrotation": np.array([1.0, 0, 0]), "Yrotation": np.array([0, 1.0, 0]), "Zrotation": np.array([0, 0, 1.0])}


@dataclass
class _Joint:
    name: str
    parent: int
    offset: np.ndarray
    channels: list[str] = field(default_factory=list)
    children: list[int] = field(default_factory=list)


def _malformed(where: str, reason: str) -> MotionError:
    """The error for a BVH file that cannot be parsed, ``reason`` saying where it goes wrong."""
    return MotionError(f"{where}: malformed or truncated BVH ({reason})")


def _parse(text: str, where: str) -> tuple[list[_Joint], np.ndarray, float]:
    tokens = text.split()
    if not tokens or tokens[0] != "HIERARCHY":
        raise MotionError(f"{where}: not a BVH file (expected 'HIERARCHY' first)")
    if "MOTION" not in tokens:
        raise _malformed(where, "the file ends inside its HIERARCHY, before MOTION")
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
                raise MotionError(f"{where}: unexpected token {tok!r} in HIERARCHY")
    except IndexError:  # the tokens hold MOTION, so only the joint stack can run out
        raise _malformed(where, f"{tokens[i]!r} outside any joint's braces in HIERARCHY") from None
    except MotionError:  # an unexpected token, already named
        raise
    except ValueError as err:
        raise _malformed(where, f"a HIERARCHY value is not a number: {err}") from err
    header = tokens[i + 1:i + 6]
    if len(header) < 5 or header[0] != "Frames:" or header[2:4] != ["Frame", "Time:"]:
        raise _malformed(where, f"expected 'Frames: N' and 'Frame Time: S' after MOTION, found {' '.join(header)!r}")
    try:
        n_frames, frame_time = int(header[1]), float(header[4])
        values = np.array([float(v) for v in tokens[i + 6:]])
    except ValueError as err:
        raise _malformed(where, f"a MOTION value is not a number: {err}") from err
    width = sum(len(j.channels) for j in joints)
    if n_frames < 2 or values.size != n_frames * width:
        raise MotionError(f"{where}: expected {n_frames} frames × {width} channels = {n_frames * width} values, "
                          f"found {values.size} (truncated file?)")
    if not np.all(np.isfinite(values)):
        raise MotionError(f"{where}: motion data contains NaN/inf")
    return joints, values.reshape(n_frames, width), frame_time


def joint_positions(joints: list[_Joint], frames: np.ndarray, where: str) -> np.ndarray:
    """World positions ``(T, N, 3)`` (file units and axes) of every joint and End Site by forward
    kinematics: each joint's channels, in the order listed, are its translation (position
    channels replace the offset) and intrinsic rotations (degrees)."""
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
            elif ch in ("Xposition", "Yposition", "Zposition"):
                local_pos[:, "XYZ".index(ch[0])] = v
            else:
                raise MotionError(f"{where}: joint {joint.name} has unknown channel {ch!r}")
        if joint.parent < 0:
            world_pos[:, k] = local_pos
            world_rot[:, k] = local_rot
        else:
            world_pos[:, k] = world_pos[:, joint.parent] + rot.rotate(world_rot[:, joint.parent], local_pos)
            world_rot[:, k] = rot.multiply(world_rot[:, joint.parent], local_rot)
    return world_pos


def load(path: str | Path, options: MocapOptions = MocapOptions()) -> SourceClip:
    """Load a BVH file as a :class:`SourceClip`.

    Args:
        path: the ``.bvh`` file.
        options: joint map, units and up axis where detection is not wanted (:class:`MocapOptions`).

    Raises:
        FileNotFoundError: no such file.
        MotionError: not a BVH file, malformed or truncated, NaN/inf, an unknown channel, 'Frame Time'
            not > 0 (a ``ValueError``).
        ValueError: an unknown rig (the message lists the file's joints and the canonical joints
            still needed), undetectable units or axes.
    """
    path = Path(path)
    where = str(path)
    joints, frames, frame_time = _parse(read_text(path, "BVH file"), where)
    if not frame_time > 0:
        raise MotionError(f"{where}: 'Frame Time' must be > 0 s, got {frame_time}")
    names = [j.name for j in joints]
    positions = joint_positions(joints, frames, where)
    match = match_rig(names, positions, where, options.joint_map)
    world, axes = canonical_positions(positions, match, where, units=options.units, up=options.up)
    return clip_from_joint_positions(f"bvh:{path.stem}", 1.0 / frame_time, world,
                                     source={"format": "bvh", "file": where, "rig": match.rig, **axes})
