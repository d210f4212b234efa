"""Mocap rigs: which joint of a file plays each canonical joint, and the file's units and axes.

Loaders (BVH, ASF/AMC) compute the world position of every joint of the file by forward
kinematics, then this module turns those into positions of the :data:`CANONICAL_JOINTS` in the
project's world (m, z up), from which :func:`~reference_motion.source.clip_from_joint_positions`
builds the clip. Nothing here depends on a rig's rest pose or joint orientations.

* **Name maps** (:data:`RIGS`): for each known rig, the candidate file joints of each canonical
  joint; the rig is detected as the one whose names resolve (names compared case-insensitively,
  with any ``namespace:`` prefix such as Mixamo's ``mixamorig:`` removed). ``joint_map`` (a dict,
  or ``--joint-map FILE.json`` on the command line) names joints for anything else.
* **Units** (:func:`unit_scale`): from the height of the rig, head end above the ankles.
* **Up axis** (:func:`up_axis`): the file axis along which the head is above the feet.
* **Handedness** (:func:`canonical_positions`): a mirrored (left-handed) file bends its knees
  forwards; it is detected so and mirrored back.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from reference_motion.source import CANONICAL_JOINTS, CANONICAL_PARENTS, Y_UP_TO_Z_UP

_LIMB_JOINTS = ("hip", "knee", "ankle", "toe_end", "shoulder", "elbow", "wrist")


def _sided(template: dict[str, tuple[str, ...]], sides: dict[str, str]) -> dict[str, tuple[str, ...]]:
    """Expand ``{S}`` in the limb candidates of ``template`` for ``sides`` (left/right → the rig's
    spelling of the side)."""
    out = {k: v for k, v in template.items() if k not in _LIMB_JOINTS}
    for side, spelling in sides.items():
        for limb in _LIMB_JOINTS:
            out[f"{side}_{limb}"] = tuple(c.format(S=spelling) for c in template[limb])
    return out


RIGS: dict[str, dict[str, tuple[str, ...]]] = {
    "physmimic": _sided({  # this project's BVH export (reference_motion.bvh_export)
        "root": ("pelvis",), "chest": ("chest",), "neck": ("neck",), "head_end": ("head_end",),
        "hip": ("{S}_thigh",), "knee": ("{S}_shin",), "ankle": ("{S}_foot",),
        "toe_end": ("{S}_toe_end", "{S}_foot_end"), "shoulder": ("{S}_upper_arm",), "elbow": ("{S}_forearm",),
        "wrist": ("{S}_hand",)}, {"left": "l", "right": "r"}),
    "deepmimic": _sided({  # DeepMimic's humanoid joint names (End Sites end the neck, ankles, elbows)
        "root": ("root",), "chest": ("chest",), "neck": ("neck",), "head_end": ("neck_end", "head"),
        "hip": ("{S}_hip",), "knee": ("{S}_knee",), "ankle": ("{S}_ankle",), "toe_end": ("{S}_ankle_end", "{S}_toe"),
        "shoulder": ("{S}_shoulder",), "elbow": ("{S}_elbow",), "wrist": ("{S}_elbow_end", "{S}_wrist")},
        {"left": "left", "right": "right"}),
    "cmu_mixamo": _sided({  # CMU BVH conversions, Mixamo (mixamorig:), MotionBuilder/HumanIK
        "root": ("Hips",), "chest": ("Spine1", "Spine2", "Chest", "Spine"), "neck": ("Neck",),
        "head_end": ("HeadTop_End", "Head_end", "Head"),
        "hip": ("{S}UpLeg",), "knee": ("{S}Leg",), "ankle": ("{S}Foot",),
        "toe_end": ("{S}Toe_End", "{S}ToeBase_end", "{S}ToeBase", "{S}Foot_end"),
        "shoulder": ("{S}Arm",), "elbow": ("{S}ForeArm",), "wrist": ("{S}Hand",)},
        {"left": "Left", "right": "Right"}),
    "unity_humanoid": _sided({  # Bandai Namco Research motion datasets, Unity humanoid avatars
        "root": ("Hips",), "chest": ("Chest", "Spine"), "neck": ("Neck",), "head_end": ("Head_end", "Head"),
        "hip": ("UpperLeg_{S}",), "knee": ("LowerLeg_{S}",), "ankle": ("Foot_{S}",),
        "toe_end": ("Toes_{S}_end", "Toes_{S}"), "shoulder": ("UpperArm_{S}",), "elbow": ("LowerArm_{S}",),
        "wrist": ("Hand_{S}",)}, {"left": "L", "right": "R"}),
    "smpl": _sided({  # SMPL / SMPL-X joint names (left_hip, spine3, left_foot, ...)
        "root": ("pelvis",), "chest": ("spine3", "spine2"), "neck": ("neck",), "head_end": ("head_end", "head"),
        "hip": ("{S}_hip",), "knee": ("{S}_knee",), "ankle": ("{S}_ankle",),
        "toe_end": ("{S}_foot_end", "{S}_foot"), "shoulder": ("{S}_shoulder",), "elbow": ("{S}_elbow",),
        "wrist": ("{S}_wrist",)}, {"left": "left", "right": "right"}),
    "smpl_short": _sided({  # SMPL names as some exporters abbreviate them (L_Hip, Spine3, ...)
        "root": ("Pelvis",), "chest": ("Spine3", "Spine2"), "neck": ("Neck",), "head_end": ("Head_end", "Head"),
        "hip": ("{S}_Hip",), "knee": ("{S}_Knee",), "ankle": ("{S}_Ankle",),
        "toe_end": ("{S}_Foot_end", "{S}_Foot"), "shoulder": ("{S}_Shoulder",), "elbow": ("{S}_Elbow",),
        "wrist": ("{S}_Wrist",)}, {"left": "L", "right": "R"}),
    "cmu_asf": _sided({  # CMU ASF/AMC bones; a point is the END of the named bone
        "root": ("root",), "chest": ("upperback",), "neck": ("thorax",), "head_end": ("head",),
        "hip": ("{S}hipjoint",), "knee": ("{S}femur",), "ankle": ("{S}tibia",), "toe_end": ("{S}toes", "{S}foot"),
        "shoulder": ("{S}clavicle",), "elbow": ("{S}humerus",), "wrist": ("{S}radius", "{S}wrist")},
        {"left": "l", "right": "r"}),
}
"""Canonical joint → candidate file joints (first present with a bone of non-zero length wins)
for each known rig. BVH End Sites are named ``<joint>_end``."""

MIN_BONE_FRACTION = 0.006
"""A candidate closer to its canonical parent's joint than this fraction of the rig's extent
(about 1 cm on an adult) is skipped: End Sites of zero offset, joints stacked at one place."""


def bare(name: str) -> str:
    """A joint name as compared: lower case, without a ``namespace:`` prefix."""
    return name.rsplit(":", 1)[-1].lower()


def load_joint_map(path: str | Path) -> dict[str, str]:
    """Read a ``--joint-map`` JSON file: an object from canonical joint names to file joint names.

    Raises:
        ValueError: unreadable JSON, not an object of strings, or keys that are not canonical joints.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such joint-map file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise ValueError(f"{path}: not a JSON joint map ({err})") from None
    if not isinstance(data, dict) or not all(isinstance(k, str) and isinstance(v, str) for k, v in data.items()):
        raise ValueError(f"{path}: a joint map is a JSON object {{canonical joint: file joint name}}")
    unknown = sorted(set(data) - set(CANONICAL_JOINTS))
    if unknown:
        raise ValueError(f"{path}: {', '.join(unknown)} are not canonical joints; expected some of "
                         f"{', '.join(CANONICAL_JOINTS)}")
    return data


@dataclass(frozen=True)
class MocapOptions:
    """How to read a mocap file whose rig, units or axes are not detected.

    Attributes:
        joint_map: canonical joint → file joint name (:func:`load_joint_map`), over the detected rig's.
        units: length unit of the file (one of :data:`UNITS`); ``None`` detects it.
        up: the file's up axis (one of :data:`UP_AXES`); ``None`` detects it.
        asf: the skeleton of an ``.amc`` take; ``None`` finds it beside the take.
    """

    joint_map: dict[str, str] | None = None
    units: str | None = None
    up: str | None = None
    asf: str | Path | None = None


@dataclass(frozen=True)
class RigMatch:
    """The file joint chosen for each canonical joint.

    Attributes:
        rig: name of the rig in :data:`RIGS` (``"joint map"`` when a joint map named every joint).
        joints: canonical joint → index into the file's joints, in :data:`CANONICAL_JOINTS` order.
    """

    rig: str
    joints: dict[str, int]


def _resolve(candidates: dict[str, tuple[str, ...]], names: list[str], positions: np.ndarray) -> dict[str, int]:
    """Canonical joints whose candidates are in ``names``; each must sit apart from the joint chosen
    for its parent (:data:`MIN_BONE_FRACTION`; ``positions (T, N, 3)`` in file units)."""
    index = {bare(n): i for i, n in enumerate(names)}
    min_length = MIN_BONE_FRACTION * float(np.max(np.ptp(positions[0], axis=0)))
    found: dict[str, int] = {}
    for canon in CANONICAL_JOINTS:
        parent = CANONICAL_PARENTS.get(canon)
        for cand in candidates.get(canon, ()):
            i = index.get(bare(cand))
            if i is None:
                continue
            if parent in found:
                length = np.median(np.linalg.norm(positions[:, i] - positions[:, found[parent]], axis=-1))
                if length < min_length:
                    continue
            found[canon] = i
            break
    return found


def match_rig(names: list[str], positions: np.ndarray, where: str,
              joint_map: dict[str, str] | None = None) -> RigMatch:
    """Detect the rig of a file from its joint ``names`` and positions ``(T, N, 3)`` (file units).

    ``joint_map`` (canonical → file joint) overrides the candidates of the joints it names.

    Raises:
        ValueError: no rig resolves every canonical joint; the message lists the joints in the file,
            the closest rig and the canonical joints it still needs.
    """
    joint_map = joint_map or {}
    missing_from_file = [v for v in joint_map.values() if bare(v) not in {bare(n) for n in names}]
    if missing_from_file:
        raise ValueError(f"{where}: the joint map names {', '.join(missing_from_file)}, not in the file; "
                         f"joints in the file: {', '.join(names)}")
    best: tuple[int, str, dict[str, int]] | None = None
    for rig, candidates in RIGS.items():
        merged = {**candidates, **{k: (v,) for k, v in joint_map.items()}}
        found = _resolve(merged, names, positions)
        if len(found) == len(CANONICAL_JOINTS):
            return RigMatch(rig if not joint_map else f"{rig} + joint map", found)
        if best is None or len(found) > best[0]:
            best = (len(found), rig, found)
    assert best is not None
    _, rig, found = best
    needed = [f"{c} (e.g. {'/'.join(RIGS[rig].get(c, ('?',)))})" for c in CANONICAL_JOINTS if c not in found]
    raise ValueError(f"{where}: unknown rig (closest: {rig}, {len(found)} of {len(CANONICAL_JOINTS)} joints); "
                     f"still needed: {', '.join(needed)}. Joints in the file: {', '.join(names)}. "
                     "Pass --joint-map FILE.json, a JSON object {canonical joint: joint in the file}")


UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}
"""Length units a file may be in (metres per unit)."""

_HEAD_ABOVE_ANKLES_M = (0.5, 2.6)
"""Plausible head-end height above the ankles (m), from small children to tall adults."""


def unit_scale(head_height: float, where: str) -> float:
    """Metres per file unit, from the rig's head-end height above its ankles in file units.

    The first of m, in, cm, mm for which the height is plausible (:data:`_HEAD_ABOVE_ANKLES_M`,
    inches only up to 95 units so that a 1 m child in centimetres is not read as inches).
    """
    lo, hi = _HEAD_ABOVE_ANKLES_M
    for unit in ("m", "in", "cm", "mm"):
        scale = UNITS[unit]
        if lo <= head_height * scale <= hi and not (unit == "in" and head_height > 95):
            return scale
    raise ValueError(f"{where}: cannot tell the length unit (head {head_height:g} units above the ankles); "
                     f"pass --units one of {', '.join(UNITS)}")


_TO_Z_UP = {
    "z": np.eye(3),
    "y": Y_UP_TO_Z_UP,  # (x, y, z) → (x, −z, y), as every y-up loader converts
    "x": np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]),  # (x, y, z) → (y, z, x)
}
"""Proper rotations taking a file whose up axis is the key to the z-up world."""

UP_AXES = tuple(_TO_Z_UP)


def up_axis(head_minus_ankles: np.ndarray, where: str) -> str:
    """The file's up axis (``"x"``, ``"y"`` or ``"z"``): the one along which the head end stands
    highest above the ankles, given that offset ``(T, 3)`` in file axes."""
    mean = np.mean(head_minus_ankles, axis=0)
    k = int(np.argmax(np.abs(mean)))
    if mean[k] <= 0:
        raise ValueError(f"{where}: the head is below the feet along the file's {'xyz'[k]} axis; "
                         f"pass --up one of {', '.join(UP_AXES)}")
    return "xyz"[k]


def canonical_positions(positions: np.ndarray, match: RigMatch, where: str, units: str | None = None,
                        up: str | None = None) -> tuple[np.ndarray, dict]:
    """Canonical joint positions ``(T, J, 3)`` in the world (m, z up) from a file's joint positions
    ``(T, N, 3)`` in file units and axes.

    Args:
        units: one of :data:`UNITS`, or ``None`` to detect (:func:`unit_scale`).
        up: one of :data:`UP_AXES`, or ``None`` to detect (:func:`up_axis`).

    Returns:
        The positions and what was used: ``{"units_m": scale, "up": axis, "mirrored": bool}``.
    """
    idx = [match.joints[c] for c in CANONICAL_JOINTS]
    pos = np.asarray(positions, dtype=float)[:, idx]
    j = CANONICAL_JOINTS.index
    head_minus_ankles = pos[:, j("head_end")] - 0.5 * (pos[:, j("left_ankle")] + pos[:, j("right_ankle")])
    if up is None:
        up = up_axis(head_minus_ankles, where)
    elif up not in _TO_Z_UP:
        raise ValueError(f"{where}: up axis {up!r} unknown; expected one of {', '.join(UP_AXES)}")
    if units is None:
        scale = unit_scale(float(np.median(np.abs(head_minus_ankles[:, "xyz".index(up)]))), where)
    elif units in UNITS:
        scale = UNITS[units]
    else:
        raise ValueError(f"{where}: unit {units!r} unknown; expected one of {', '.join(UNITS)}")
    world = pos @ _TO_Z_UP[up].T * scale
    mirrored = _bends_knees_forwards(world)
    if mirrored:
        world[..., 1] *= -1.0
    return world, {"units_m": scale, "up": up, "mirrored": mirrored}


def _bends_knees_forwards(world: np.ndarray) -> bool:
    """True for a mirrored (left-handed) clip: its knees, weighted by how far they bend, fold
    forwards relative to the facing given by the hips (left hip − right hip) × up."""
    j = CANONICAL_JOINTS.index
    lateral = world[:, j("left_hip")] - world[:, j("right_hip")]
    total = 0.0
    for side in ("left", "right"):
        thigh = world[:, j(f"{side}_knee")] - world[:, j(f"{side}_hip")]
        shin = world[:, j(f"{side}_ankle")] - world[:, j(f"{side}_knee")]
        total += float(np.sum(np.cross(thigh, shin) * lateral))
    return total < 0.0
