"""Writing a :class:`Motion` as BVH, for animation tools (Blender, MotionBuilder, Maya).

The hierarchy is the humanoid's own: one BVH joint per body (named as the body), offsets from the
model in centimetres, y up (the inverse of :data:`reference_motion.source.Y_UP_TO_Z_UP`), the
root with position and rotation channels and every other joint with ``Zrotation Xrotation
Yrotation`` (degrees). Leaf bodies end in an End Site: the top of the head, the end of the hand and
the toe tip. Welded bodies (hands) carry their (constant) rotation like any other joint.

``reference_motion.bvh.load`` reads the file back with no options (the rig is detected as
``physmimic``; a test checks that joint positions survive the round trip).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from reference_motion import rotations as rot
from reference_motion.atomic import atomic_write
from reference_motion.humanoid import anthropometry as A
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion
from reference_motion.source import Y_UP_TO_Z_UP

CM_PER_M = 100.0

HEAD_TOP = (0.01, 0.0, 0.10)
"""End Site of the head, in the head frame (m): the same head-top point retargeting uses."""

HAND_END = (0.0, 0.0, -0.08)
"""End Site of the hands, in the hand frame (m): the fingertips of the hanging rest pose."""


def _end_site(body: str, rest: np.ndarray, names: list[str]) -> np.ndarray:
    """End Site offset (m, body frame) of leaf ``body``, given all bodies' rest positions ``(B, 3)``."""
    if body == "head":
        return np.array(HEAD_TOP)
    if body.endswith("_hand"):
        return np.array(HAND_END)
    toe_tip = rest[names.index(f"{body[0]}_foot")] + [A.FOOT_HEEL_X + A.FOOT_LENGTH, 0.0, A.SOLE_Z]
    return toe_tip - rest[names.index(body)]


def _to_y_up(v: np.ndarray) -> np.ndarray:
    return np.asarray(v, dtype=float) @ Y_UP_TO_Z_UP  # inverse (transpose) of the y-up → z-up map


def write_bvh(motion: Motion, path: str | Path) -> Path:
    """Write ``motion`` to ``path`` (.bvh), atomically; returns the path."""
    path = Path(path)
    hm = load_model(motion.model)
    m = hm.model
    names = hm.body_names
    parent = m.body_parentid[1:] - 1
    children = {b: [c for c in range(len(names)) if parent[c] == b] for b in range(len(names))}
    rest = hm.forward_kinematics(hm.rest_qpos()).body_pos[0]

    lines, order = ["HIERARCHY"], []

    def joint(b: int, depth: int) -> None:
        order.append(b)
        pad = "  " * depth
        offset = rest[b] - (rest[parent[b]] if parent[b] >= 0 else rest[b])
        head = f"ROOT {names[b]}" if parent[b] < 0 else f"JOINT {names[b]}"
        channels = ("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation" if parent[b] < 0
                    else "CHANNELS 3 Zrotation Xrotation Yrotation")
        lines.extend([pad + head, pad + "{", f"{pad}  OFFSET {_fmt(_to_y_up(offset) * CM_PER_M)}", f"{pad}  {channels}"])
        for c in children[b]:
            joint(c, depth + 1)
        if not children[b]:
            end = _to_y_up(_end_site(names[b], rest, names)) * CM_PER_M
            lines.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET {_fmt(end)}", f"{pad}  }}"])
        lines.append(pad + "}")

    joint(0, 0)
    kin = hm.forward_kinematics(motion.qpos)
    local = rot.relative_to_parent(kin.body_quat, parent)
    local_y_up = np.concatenate([local[..., :1], _to_y_up(local[..., 1:])], axis=-1)
    euler = np.degrees(rot.to_hinges(local_y_up, "zxy"))[:, order]  # (T, B, 3): BVH's Z X Y channel order
    root = _to_y_up(kin.body_pos[:, 0]) * CM_PER_M
    lines += ["MOTION", f"Frames: {motion.n_frames}", f"Frame Time: {1.0 / motion.fps:.8f}"]
    for t in range(motion.n_frames):
        lines.append(_fmt(np.concatenate([root[t], euler[t].ravel()])))
    with atomic_write(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return path


def _fmt(values: np.ndarray) -> str:
    return " ".join(f"{v:.6f}" for v in np.ravel(values))
