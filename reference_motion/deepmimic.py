"""Loader for the DeepMimic mocap clips shipped inside the ``pybullet`` wheel.

Files: ``pybullet_data/data/motions/humanoid3d_*.txt`` and ``.../walker/*.txt``, JSON
``{"Loop": "wrap"|"none", "Frames": [[44 floats], ...]}``. Per frame: duration (s), root position
(y up), root quaternion, then chest, neck, right hip, knee, ankle, shoulder, elbow, left hip, knee,
ankle, shoulder, elbow (4 values per spherical joint, 1 angle about local z for knees/elbows).
Clip names: ``deepmimic:walk`` (= ``humanoid3d_walk.txt``), ``deepmimic:walker/turn_left0``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from reference_motion import rotations as rot
from reference_motion.motion import MotionError, read_text
from reference_motion.source import CANONICAL_JOINTS, SourceClip, uniform_timing, y_up_quats, y_up_vectors

FRAME_WIDTH = 44

_LAYOUT = (
    # canonical joint, number of values
    ("chest", 4), ("neck", 4),
    ("right_hip", 4), ("right_knee", 1), ("right_ankle", 4), ("right_shoulder", 4), ("right_elbow", 1),
    ("left_hip", 4), ("left_knee", 1), ("left_ankle", 4), ("left_shoulder", 4), ("left_elbow", 1),
)

# Rest offsets of pybullet's humanoid.urdf (loaded with globalScaling=0.25), y-up, metres.
_URDF_SCALE = 0.25
_OFFSETS_Y_UP = {
    "chest": (0.0, 0.944604, 0.0), "neck": (0.0, 0.895576, 0.0), "head_end": (0.0, 0.7, 0.0),
    "right_hip": (0.0, 0.0, 0.339548), "right_knee": (0.0, -1.686184, 0.0),
    "right_ankle": (0.0, -1.63948, 0.0), "right_toe_end": (0.534, -0.2, 0.0),
    "right_shoulder": (-0.0962, 0.974, 0.73244), "right_elbow": (0.0, -1.099152, 0.0),
    "right_wrist": (0.0, -1.035788, 0.0),
}
"""``right_toe_end`` is the front-bottom edge of the foot box (centre 0.18, -0.09; size 0.708 × 0.22)."""


def _offsets() -> np.ndarray:
    out = np.zeros((len(CANONICAL_JOINTS), 3))
    for j, name in enumerate(CANONICAL_JOINTS):
        if name == "root":
            continue
        key = name.replace("left_", "right_")
        off = np.array(_OFFSETS_Y_UP[key]) * _URDF_SCALE
        if name.startswith("left_"):
            off[2] = -off[2]  # the source's right side is +z
        out[j] = y_up_vectors(off)
    return out


def data_dir() -> Path:
    """Folder of the DeepMimic clips in the installed ``pybullet_data``."""
    try:
        import pybullet_data
    except ImportError as err:  # pragma: no cover - dependency of the project
        raise RuntimeError("the DeepMimic clips come from the 'pybullet' package: pip install pybullet") from err
    return Path(pybullet_data.getDataPath()) / "data" / "motions"


def clip_names() -> list[str]:
    """All 20 humanoid clip names, e.g. ``["backflip", ..., "walker/turn_right1"]``."""
    root = data_dir()
    names = sorted(p.stem.removeprefix("humanoid3d_") for p in root.glob("humanoid3d_*.txt"))
    names += sorted(f"walker/{p.stem}" for p in (root / "walker").glob("*.txt"))
    return names


def clip_path(name: str) -> Path:
    """File of clip ``name`` (``walk``, ``walker/turn_left0``); ``KeyError`` lists the valid names."""
    root = data_dir()
    path = root / f"{name}.txt" if name.startswith("walker/") else root / f"humanoid3d_{name}.txt"
    if not path.is_file():
        raise KeyError(f"unknown DeepMimic clip {name!r}; available: {', '.join(clip_names())}")
    return path


def parse(text: str, where: str) -> tuple[np.ndarray, bool]:
    """Validate DeepMimic JSON; returns frames ``(T, 44)`` and the loop flag. ``where`` names the
    file in :class:`MotionError`'s messages (empty, not JSON, wrong frame widths, non-numbers,
    NaN/inf, bad ``Loop`` or durations)."""
    if not text.strip():
        raise MotionError(f"{where}: file is empty")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as err:
        raise MotionError(f"{where}: not valid JSON (truncated or corrupt?): {err}") from err
    if not isinstance(doc, dict) or "Frames" not in doc:
        raise MotionError(f"{where}: expected a JSON object with a 'Frames' list")
    frames = doc["Frames"]
    if not isinstance(frames, list) or len(frames) < 2:
        raise MotionError(f"{where}: 'Frames' must be a list of at least 2 frames")
    for i, f in enumerate(frames):
        if not isinstance(f, list) or len(f) != FRAME_WIDTH:
            n = len(f) if isinstance(f, list) else type(f).__name__
            raise MotionError(f"{where}: frame {i} has {n} values, expected {FRAME_WIDTH}")
    try:
        arr = np.array(frames, dtype=float)
    except (TypeError, ValueError) as err:
        raise MotionError(f"{where}: frames must contain only numbers ({err})") from err
    if not np.all(np.isfinite(arr)):
        i, k = np.argwhere(~np.isfinite(arr))[0]
        raise MotionError(f"{where}: frame {i} value {k} is not finite ({arr[i, k]})")
    loop = doc.get("Loop", "none")
    if loop not in ("wrap", "none"):
        raise MotionError(f"{where}: 'Loop' must be 'wrap' or 'none', got {loop!r}")
    if np.any(arr[:-1, 0] <= 0):
        raise MotionError(f"{where}: frame durations (value 0 of each frame) must be positive")
    return arr, loop == "wrap"


def source_clip_from_frames(frames: np.ndarray, name: str, loop: bool, source: dict) -> SourceClip:
    """Build a :class:`SourceClip` (z-up) from parsed DeepMimic frames ``(T, 44)``.

    Clips whose frame durations vary (``roll``) are resampled to the rate of their shortest frame.
    """
    T = frames.shape[0]
    J = len(CANONICAL_JOINTS)
    local = np.tile(np.array([1.0, 0, 0, 0]), (T, J, 1))
    local[:, 0] = rot.normalize(y_up_quats(frames[:, 4:8]))
    col = 8
    hinge_axis = y_up_vectors(np.array([0.0, 0.0, 1.0]))  # knees/elbows turn about local z (y-up)
    for joint, width in _LAYOUT:
        j = CANONICAL_JOINTS.index(joint)
        values = frames[:, col:col + width]
        if width == 4:
            local[:, j] = rot.normalize(y_up_quats(values))
        else:
            local[:, j] = rot.from_axis_angle(hinge_axis, values[:, 0])
        col += width
    times = np.concatenate([[0.0], np.cumsum(frames[:-1, 0])])
    fps = float(1.0 / frames[:-1, 0].min())
    root_pos, local = uniform_timing(times, y_up_vectors(frames[:, 1:4]), local, fps)
    return SourceClip(name=name, fps=fps, offsets=_offsets(), root_pos=root_pos, local_quats=local,
                      loop=loop, source=source)


def load(name_or_path: str | Path) -> SourceClip:
    """Load a DeepMimic clip by name (``walk``, ``walker/turn_left0``) or from a file path;
    :class:`MotionError` names a malformed file, ``KeyError`` lists the names for an unknown one."""
    path = Path(name_or_path)
    if path.suffix != ".txt" or not path.exists():
        path = clip_path(str(name_or_path))
        name = f"deepmimic:{name_or_path}"
    else:
        name = f"deepmimic:{path.stem}"
    frames, loop = parse(read_text(path, "DeepMimic clip"), str(path))
    return source_clip_from_frames(frames, name, loop, {"format": "deepmimic", "file": str(path)})
