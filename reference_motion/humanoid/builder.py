"""Writes ``assets/mjcf/humanoid_1seg.xml`` and ``humanoid_2seg.xml`` from the body table.

Usage: ``python -m reference_motion.humanoid.builder [--check]``. ``--check`` exits non-zero if the
committed files differ from what this module generates (the test suite does the same).

Both models share everything but the feet. Each sole carries the 16 insole cells of the Moticon
layout (underpressure Fig. 2) as box sites ``{l,r}_cell{00..15}``, plus one small contact sphere at
each cell centre: the spheres are the only foot geoms that touch the floor, so ground contact
points land inside the cells and the pressure distribution is spatially resolved.
"""

from __future__ import annotations

import argparse
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from reference_motion.humanoid import anthropometry as A

ASSET_DIR = Path(__file__).resolve().parents[2] / "assets" / "mjcf"
MODEL_NAMES = ("humanoid_1seg", "humanoid_2seg")

TIMESTEP_S = 1.0 / 120.0
"""Physics timestep (s): two substeps per 60 Hz simulation frame (adapt Table 3)."""

SOLE_SPHERE_RADIUS = 0.012
"""Radius (m) of the contact sphere at each insole cell centre."""

STANDING_PELVIS_Z = 0.43 + 0.43 - A.SOLE_Z
"""Pelvis height (m) in the rest pose with the soles on the floor."""


@dataclass(frozen=True)
class InsoleCell:
    """One insole cell on a sole: ``u`` from heel (0) to toe tip (1), ``medial`` column or not."""

    index: int
    u0: float
    u1: float
    medial: bool


def insole_cells() -> list[InsoleCell]:
    """The 16 cells, Moticon numbering minus one: heel 0–3, midfoot 4–7, forefoot/toes 8–15."""
    rows = [(0.0, 0.125), (0.125, 0.25), (0.25, 0.375), (0.375, 0.5),
            (0.5, 0.6), (0.6, 0.7), (0.7, 0.8), (0.8, 1.0)]
    cells = []
    for r, (u0, u1) in enumerate(rows):
        for c, medial in enumerate((True, False)):
            cells.append(InsoleCell(2 * r + c, u0, u1, medial))
    return cells


HEEL_CELLS = (0, 1, 2, 3)
TOE_CELLS = tuple(range(8, 16))


def _f(values) -> str:
    """Compact numeric formatting for XML attributes."""
    return " ".join(f"{float(v):.6g}" for v in np.atleast_1d(values))


def _geom_element(parent: ET.Element, name: str, geom: A.Geom, mass: float | None = None) -> ET.Element:
    contype, conaffinity = A.COLLISION_GROUPS[geom.collision]
    attrs = {"name": name, "type": geom.kind, "contype": str(contype), "conaffinity": str(conaffinity),
             "class": "body_geom"}
    if geom.kind == "capsule":
        attrs["fromto"] = _f(geom.fromto)
        attrs["size"] = _f(geom.size)
    else:
        attrs["pos"] = _f(geom.pos)
        attrs["size"] = _f(geom.size)
    if mass is not None:
        attrs["mass"] = _f(mass)
    return ET.SubElement(parent, "geom", attrs)


def _inertial(parent: ET.Element, mass: float, com, gyration) -> None:
    diag = mass * np.square(np.asarray(gyration))
    ET.SubElement(parent, "inertial", {"pos": _f(com), "mass": _f(mass), "diaginertia": _f(diag)})


def _joints(parent: ET.Element, body: str, spec: A.JointSpec, actuated: list[tuple[str, str]]) -> None:
    for axis_name, axis_vec, (lo, hi) in zip(spec.axes, spec.axis_vectors(), spec.range_deg):
        name = f"{body}_{axis_name}"
        ET.SubElement(parent, "joint", {"name": name, "type": "hinge", "axis": _f(axis_vec),
                                        "range": _f((lo, hi)), "class": spec.gains})
        actuated.append((name, spec.gains))


def _cell_x(u: float) -> float:
    return A.FOOT_HEEL_X + u * A.FOOT_LENGTH


def _sole(body: ET.Element, side: str, cells: list[InsoleCell], x_offset: float, z_offset: float) -> None:
    """Cell sites and contact spheres of the cells in ``cells``, in a body whose origin is at
    (x_offset, 0, z_offset) of the foot frame."""
    s = 1.0 if side == "l" else -1.0
    contype, conaffinity = A.COLLISION_GROUPS["sole"]
    for cell in cells:
        x0, x1 = _cell_x(cell.u0), _cell_x(cell.u1)
        y_center = (-s if cell.medial else s) * A.FOOT_HALF_WIDTH / 2
        center = np.array([(x0 + x1) / 2 - x_offset, y_center, A.SOLE_Z - z_offset])
        ET.SubElement(body, "site", {"name": f"{side}_cell{cell.index:02d}", "type": "box",
                                     "pos": _f(center),
                                     "size": _f(((x1 - x0) / 2, A.FOOT_HALF_WIDTH / 2, 0.004)),
                                     "class": "cell"})
        ET.SubElement(body, "geom", {"name": f"{side}_sole{cell.index:02d}", "type": "sphere",
                                     "pos": _f(center + [0, 0, SOLE_SPHERE_RADIUS]),
                                     "size": _f(SOLE_SPHERE_RADIUS), "contype": str(contype),
                                     "conaffinity": str(conaffinity), "class": "sole", "mass": "0"})


def _foot_points(body: ET.Element, side: str) -> None:
    """Heel and toe reference points on the sole (used by metrics and contact labels)."""
    for name, u in (("heel", 0.1), ("toe", A.TOE_JOINT_FRACTION)):
        ET.SubElement(body, "site", {"name": f"{side}_{name}_point", "pos": _f((_cell_x(u), 0, A.SOLE_Z)),
                                     "size": "0.01", "class": "point"})


def _two_segment_foot(body: ET.Element, seg: A.Segment, side: str, actuated: list) -> None:
    """Heel segment (the foot body) and a toe body on a 1-DoF hinge at 80% of the foot length."""
    cells = insole_cells()
    foot_mass = seg.mass_fraction * A.MASS_KG
    toe_x = _cell_x(A.TOE_JOINT_FRACTION)
    heel_len = toe_x - A.FOOT_HEEL_X
    toe_len = A.FOOT_LENGTH - heel_len
    toe_z = A.SOLE_Z + 0.015
    box = seg.geoms[0]
    heel_geom = A.Geom("box", box.collision, pos=(A.FOOT_HEEL_X + heel_len / 2, 0.0, box.pos[2]),
                       size=(heel_len / 2, A.FOOT_HALF_WIDTH, box.size[2]))
    heel_mass = foot_mass * (1 - A.TOE_MASS_SHARE)
    _inertial(body, heel_mass, (A.FOOT_HEEL_X + 0.45 * heel_len, 0, A.SOLE_Z / 2), seg.gyration)
    _geom_element(body, f"{seg.name}_geom", heel_geom)
    _sole(body, side, [c for c in cells if c.u0 < A.TOE_JOINT_FRACTION], 0.0, 0.0)
    _foot_points(body, side)
    toe = ET.SubElement(body, "body", {"name": f"{side}_toe", "pos": _f((toe_x, 0, toe_z))})
    toe_mass = foot_mass * A.TOE_MASS_SHARE
    _inertial(toe, toe_mass, (toe_len / 2, 0, 0), (0.01, 0.015, 0.015))
    _joints(toe, f"{side}_toe", A.TOE_JOINT, actuated)
    toe_geom = A.Geom("box", box.collision, pos=(toe_len / 2, 0, 0),
                      size=(toe_len / 2, A.FOOT_HALF_WIDTH, 0.015))
    _geom_element(toe, f"{side}_toe_geom", toe_geom)
    _sole(toe, side, [c for c in cells if c.u0 >= A.TOE_JOINT_FRACTION], toe_x, toe_z)


def build(model_name: str) -> str:
    """MJCF text of ``humanoid_1seg`` or ``humanoid_2seg``."""
    if model_name not in MODEL_NAMES:
        raise ValueError(f"unknown model {model_name!r}; expected one of {MODEL_NAMES}")
    two_segment = model_name == "humanoid_2seg"
    root = ET.Element("mujoco", {"model": model_name})
    ET.SubElement(root, "compiler", {"angle": "degree", "autolimits": "true"})
    # jacobian="sparse": the same solution as the dense Jacobian MuJoCo picks for nv < 60 (qpos within
    # 1e-14 after a frame), mj_step 1.21x / 1.27x as fast on these 49 / 51-dof bodies (bench/physics_options.py)
    ET.SubElement(root, "option", {"timestep": _f(TIMESTEP_S), "integrator": "implicitfast", "jacobian": "sparse"})
    size = ET.SubElement(root, "visual")
    ET.SubElement(size, "global", {"offwidth": "1280", "offheight": "720"})
    ET.SubElement(size, "quality", {"shadowsize": "2048"})

    default = ET.SubElement(root, "default")
    ET.SubElement(default, "joint", {"damping": "0", "armature": _f(A.JOINT_ARMATURE), "limited": "true"})
    ET.SubElement(default, "geom", {"friction": "1.0 0.005 0.0001", "solref": "0.01 1"})
    body_geom = ET.SubElement(default, "default", {"class": "body_geom"})
    ET.SubElement(body_geom, "geom", {"rgba": "0.55 0.6 0.7 1", "mass": "0"})
    sole = ET.SubElement(default, "default", {"class": "sole"})
    ET.SubElement(sole, "geom", {"rgba": "0.3 0.3 0.35 1", "group": "3"})
    cell = ET.SubElement(default, "default", {"class": "cell"})
    ET.SubElement(cell, "site", {"group": "4", "rgba": "0.9 0.3 0.2 0.4"})
    point = ET.SubElement(default, "default", {"class": "point"})
    ET.SubElement(point, "site", {"group": "4", "rgba": "0.2 0.9 0.2 1"})
    for gains, (kp, kd, limit) in A.PD_GAINS.items():
        cls = ET.SubElement(default, "default", {"class": gains})
        ET.SubElement(cls, "joint", {"damping": "0"})
        ET.SubElement(cls, "position", {"kp": _f(kp), "kv": _f(kd), "forcerange": _f((-limit, limit)),
                                        "inheritrange": "1"})

    asset = ET.SubElement(root, "asset")
    ET.SubElement(asset, "texture", {"name": "grid", "type": "2d", "builtin": "checker", "width": "512",
                                     "height": "512", "rgb1": "0.25 0.27 0.3", "rgb2": "0.35 0.37 0.4"})
    ET.SubElement(asset, "material", {"name": "grid", "texture": "grid", "texrepeat": "1 1",
                                      "texuniform": "true", "reflectance": "0.1"})
    ET.SubElement(asset, "texture", {"name": "sky", "type": "skybox", "builtin": "gradient",
                                     "rgb1": "0.6 0.7 0.8", "rgb2": "0.1 0.1 0.15", "width": "64",
                                     "height": "64"})

    world = ET.SubElement(root, "worldbody")
    ET.SubElement(world, "light", {"name": "sun", "pos": "0 0 5", "dir": "0 0 -1", "directional": "true"})
    ET.SubElement(world, "geom", {"name": "floor", "type": "plane", "size": "0 0 0.05", "material": "grid",
                                  "contype": str(A.FLOOR_BIT), "conaffinity": "0"})

    bodies: dict[str, ET.Element] = {}
    actuated: list[tuple[str, str]] = []
    for seg in A.segments():
        if seg.parent is None:
            el = ET.SubElement(world, "body", {"name": seg.name, "pos": _f((0, 0, STANDING_PELVIS_Z))})
            ET.SubElement(el, "freejoint", {"name": "root"})
            ET.SubElement(el, "camera", {"name": "track", "mode": "trackcom", "pos": "0.4 -3.2 0.3",
                                         "xyaxes": "1 0 0 0 0.1 1"})
        else:
            el = ET.SubElement(bodies[seg.parent], "body", {"name": seg.name, "pos": _f(seg.pos)})
        bodies[seg.name] = el
        side = seg.name[0]
        if two_segment and seg.name.endswith("_foot"):
            _joints(el, seg.name, seg.joint, actuated)
            _two_segment_foot(el, seg, side, actuated)
            continue
        _inertial(el, seg.mass_fraction * A.MASS_KG, seg.com, seg.gyration)
        if seg.joint is not None:
            _joints(el, seg.name, seg.joint, actuated)
        for i, geom in enumerate(seg.geoms):
            _geom_element(el, f"{seg.name}_geom" + (f"{i}" if i else ""), geom)
        if seg.name.endswith("_foot"):
            _sole(el, side, insole_cells(), 0.0, 0.0)
            _foot_points(el, side)

    actuator = ET.SubElement(root, "actuator")
    for joint, gains in actuated:
        ET.SubElement(actuator, "position", {"name": joint, "joint": joint, "class": gains})

    ET.indent(root, space="  ")
    header = ("<!-- Generated by `python -m reference_motion.humanoid.builder`; do not edit by hand.\n"
              "     Body table: reference_motion/humanoid/anthropometry.py -->\n")
    return header + ET.tostring(root, encoding="unicode") + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if committed files are stale")
    parser.add_argument("--out-dir", type=Path, default=ASSET_DIR, help="where to write (default: %(default)s)")
    args = parser.parse_args(argv)
    stale = []
    for name in MODEL_NAMES:
        path = args.out_dir / f"{name}.xml"
        text = build(name)
        if args.check:
            if not path.exists() or path.read_text() != text:
                stale.append(str(path))
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
            print(f"wrote {path}")
    if stale:
        print("stale generated models (run python -m reference_motion.humanoid.builder): " + ", ".join(stale))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
