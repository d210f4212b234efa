"""ASF/AMC loader (the CMU Graphics Lab Motion Capture Database format) → :class:`SourceClip`.

An ``.asf`` file describes the skeleton: per bone a direction and length in the parent's
coordinates at rest, an ``axis`` (the bone's local frame, Euler angles in the given order) and its
degrees of freedom; ``:units`` gives the length unit (metres = value / ``length`` × 0.0254) and
whether angles are in degrees. An ``.amc`` file lists, per frame, the root translation and
rotation and each bone's dof values. Forward kinematics (CMU's convention): a bone's world
rotation is ``parent · C · R(dofs) · C⁻¹`` and its end sits ``length · rotation · direction`` past
its parent's end. The canonical joints are bone ends (:data:`reference_motion.rigs.RIGS`
``cmu_asf``); the clip is rebuilt from their positions like a BVH's.

AMC carries no frame rate: CMU captured at 120 Hz (:data:`CMU_FPS`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from reference_motion import rotations as rot
from reference_motion.motion import MotionError, read_text
from reference_motion.rigs import MocapOptions, canonical_positions, match_rig
from reference_motion.source import SourceClip, clip_from_joint_positions

CMU_FPS = 120.0
"""Capture rate of the CMU database (Hz)."""

INCH_M = 0.0254

_AXES = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}


@dataclass
class _Bone:
    name: str
    direction: np.ndarray
    length: float
    axis: np.ndarray  # (3,) degrees or radians as the file says
    order: str  # e.g. "XYZ"
    dofs: list[str] = field(default_factory=list)
    parent: str = ""


@dataclass
class Skeleton:
    """An ASF skeleton.

    Attributes:
        bones: bone name → bone (``root`` included, with its ``order`` of AMC channels).
        order: bone names parents first.
        length_m: metres per ASF length unit.
        degrees: angles in degrees (else radians).
        root_channels: the root's AMC channels, e.g. ``["TX", "TY", "TZ", "RX", "RY", "RZ"]``.
    """

    bones: dict[str, _Bone]
    order: list[str]
    length_m: float
    degrees: bool
    root_channels: list[str]


def _euler(angles: np.ndarray, order: str, degrees: bool) -> np.ndarray:
    """Rotation ``(..., 4)`` of Euler ``angles (..., 3)`` about fixed axes applied in ``order``
    (``"XYZ"``: x first, so R = Rz·Ry·Rx)."""
    angles = np.radians(angles) if degrees else np.asarray(angles, dtype=float)
    q = np.zeros(angles.shape[:-1] + (4,))
    q[..., 0] = 1.0
    for k, axis in enumerate(order.lower()):
        q = rot.multiply(rot.from_axis_angle(_AXES[axis], angles[..., k]), q)
    return q


def parse_asf(path: Path) -> Skeleton:
    """Read an ``.asf`` skeleton; :class:`MotionError` names the file and what is wrong."""
    where = str(path)
    lines = [ln.split("#", 1)[0].strip() for ln in read_text(path, "ASF file").splitlines()]
    length_unit, degrees = 1.0, True
    bones: dict[str, _Bone] = {}
    root_channels = ["TX", "TY", "TZ", "RX", "RY", "RZ"]
    root_axis = "XYZ"
    section, bone, children = "", None, {}
    try:
        for ln in lines:
            if not ln:
                continue
            tok = ln.split()
            if tok[0].startswith(":"):
                section = tok[0]
                continue
            if section == ":units":
                if tok[0] == "length":
                    length_unit = float(tok[1])
                elif tok[0] == "angle":
                    degrees = tok[1].startswith("deg")
            elif section == ":root":
                if tok[0] == "order":
                    root_channels = [t.upper() for t in tok[1:]]
                elif tok[0] == "axis":
                    root_axis = tok[1].upper()
            elif section == ":bonedata":
                if tok[0] == "begin":
                    bone = _Bone("", np.zeros(3), 0.0, np.zeros(3), "XYZ")
                elif tok[0] == "end":
                    bones[bone.name] = bone
                    bone = None
                elif tok[0] == "name":
                    bone.name = tok[1]
                elif tok[0] == "direction":
                    bone.direction = np.array([float(v) for v in tok[1:4]])
                elif tok[0] == "length":
                    bone.length = float(tok[1])
                elif tok[0] == "axis":
                    bone.axis, bone.order = np.array([float(v) for v in tok[1:4]]), tok[4].upper()
                elif tok[0] == "dof":
                    bone.dofs = [t.lower() for t in tok[1:]]
            elif section == ":hierarchy" and tok[0] not in ("begin", "end"):
                children[tok[0]] = tok[1:]
    except (IndexError, ValueError, AttributeError) as err:
        raise MotionError(f"{where}: malformed ASF ({err})") from None
    if not bones or not children:
        raise MotionError(f"{where}: not an ASF file (no :bonedata or :hierarchy)")
    bones["root"] = _Bone("root", np.zeros(3), 0.0, np.zeros(3), root_axis)
    order, stack = [], ["root"]
    while stack:
        name = stack.pop(0)
        order.append(name)
        for child in children.get(name, []):
            if child not in bones:
                raise MotionError(f"{where}: :hierarchy names bone {child!r}, not in :bonedata")
            bones[child].parent = name
            stack.append(child)
    return Skeleton(bones, order, INCH_M / length_unit, degrees, root_channels)


def parse_amc(path: Path, skeleton: Skeleton) -> dict[str, np.ndarray]:
    """Read an ``.amc`` file: bone name → ``(T, n_values)`` channel values (file units);
    :class:`MotionError` names the line, frame and bone of what is malformed."""
    where = str(path)
    text = read_text(path, "AMC file")
    frames: list[dict[str, list[float]]] = []
    for number, ln in enumerate(text.splitlines(), start=1):
        ln = ln.strip()
        if not ln or ln.startswith(("#", ":")):
            continue
        tok = ln.split()
        if len(tok) == 1 and tok[0].isdigit():
            frames.append({})
        elif not frames:
            raise MotionError(f"{where}: malformed AMC (line {number}, {ln!r}, comes before the first frame number)")
        else:
            try:
                frames[-1][tok[0]] = [float(v) for v in tok[1:]]
            except ValueError as err:
                raise MotionError(f"{where}: malformed AMC (line {number}, frame {len(frames)}, bone {tok[0]!r}: "
                                  f"{err})") from None
    if len(frames) < 2:
        raise MotionError(f"{where}: {len(frames)} frame(s); a clip needs at least 2")
    expected = {name: len(b.dofs) for name, b in skeleton.bones.items() if b.dofs}
    expected["root"] = len(skeleton.root_channels)
    if frames and not frames[-1]:
        frames.pop()  # a trailing frame number with no data: a cut-off file's last line
    for t, frame in enumerate(frames):
        for name, n in expected.items():
            if len(frame.get(name, ())) != n:
                raise MotionError(f"{where}: frame {t + 1} has {len(frame.get(name, ()))} values for {name!r}, "
                                  f"expected {n} (truncated file, or another subject's ASF?)")
    out = {name: np.array([f[name] for f in frames]) for name in expected}
    if not all(np.all(np.isfinite(v)) for v in out.values()):
        raise MotionError(f"{where}: motion data contains NaN/inf")
    return out


def bone_end_positions(skeleton: Skeleton, values: dict[str, np.ndarray]) -> tuple[list[str], np.ndarray]:
    """Names (``root`` and every bone) and world positions ``(T, N, 3)`` (m, file axes) of the
    root and of every bone's end."""
    T = values["root"].shape[0]
    root = dict(zip(skeleton.root_channels, values["root"].T))
    root_angles = np.stack([root.get(f"R{a}", np.zeros(T)) for a in "XYZ"], axis=-1)
    world_rot = {"root": _euler(root_angles, skeleton.bones["root"].order, skeleton.degrees)}
    world_pos = {"root": np.stack([root.get(f"T{a}", np.zeros(T)) for a in "XYZ"], axis=-1) * skeleton.length_m}
    for name in skeleton.order[1:]:
        bone = skeleton.bones[name]
        c = _euler(bone.axis, bone.order, skeleton.degrees)
        angles = np.zeros((T, 3))
        for k, dof in enumerate(bone.dofs):
            if dof in ("rx", "ry", "rz"):
                angles[:, "xyz".index(dof[1])] = values[name][:, k]
        local = rot.multiply(rot.multiply(c, _euler(angles, bone.order, skeleton.degrees)), rot.conjugate(c))
        world_rot[name] = rot.multiply(world_rot[bone.parent], local)
        world_pos[name] = world_pos[bone.parent] + rot.rotate(world_rot[name], bone.direction * bone.length
                                                              * skeleton.length_m)
    names = list(skeleton.order)
    return names, np.stack([world_pos[n] for n in names], axis=1)


def find_asf(amc: Path) -> Path:
    """The skeleton of ``amc``: ``SUBJECT.asf`` beside ``SUBJECT_TAKE.amc``, else the only ``.asf``
    in its folder."""
    beside = amc.with_name(amc.stem.split("_")[0] + ".asf")
    if beside.exists():
        return beside
    found = sorted(amc.parent.glob("*.asf"))
    if len(found) == 1:
        return found[0]
    raise FileNotFoundError(f"{amc}: no skeleton found ({beside.name} is not beside it"
                            f"{'' if not found else ', and several .asf files are'}); pass --asf FILE.asf")


def load(path: str | Path, options: MocapOptions = MocapOptions(), fps: float = CMU_FPS) -> SourceClip:
    """Load ``path`` (``.amc``) with its skeleton (``options.asf``, default :func:`find_asf`) at ``fps``.

    ``options.joint_map`` (canonical joint → bone whose END is that joint) overrides the CMU bone
    names; lengths come from the ASF's ``:units`` block and the up axis is detected unless
    ``options.up`` says it.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such AMC file")
    asf_path = Path(options.asf) if options.asf is not None else find_asf(path)
    skeleton = parse_asf(asf_path)
    names, positions = bone_end_positions(skeleton, parse_amc(path, skeleton))
    where = str(path)
    match = match_rig(names, positions, where, options.joint_map)
    world, axes = canonical_positions(positions, match, where, units="m", up=options.up)
    return clip_from_joint_positions(f"amc:{path.stem}", fps, world,
                                     source={"format": "asf/amc", "file": where, "asf": str(asf_path),
                                             "rig": match.rig, **axes})
