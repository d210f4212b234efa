"""The humanoid's body table: the single source of truth for both MJCF models.

Everything the MJCF builder writes comes from :data:`SEGMENTS` and the dataclasses below.
Frames: z up, x forward, y to the character's left; every body frame is parallel to the world
frame in the rest pose (standing, arms hanging, feet flat), so a joint rotation equals the
body's rotation relative to its parent.

Mass fractions, centre-of-mass positions and radii of gyration follow de Leva (1996), "Adjustments
to Zatsiorsky-Seluyanov's segment inertia parameters", J. Biomech. 29(9) (male values), scaled to a
1.75 m, 70 kg subject; the trunk is split into pelvis (lower trunk), two spine bodies (middle
trunk) and chest (upper trunk less the clavicles).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

HEIGHT_M = 1.75
"""Standing height of the model (m), sole to vertex."""

MASS_KG = 70.0
"""Total mass (kg)."""

SOLE_Z = -0.07
"""Height of the sole below the ankle joint (m), in the foot body frame."""

FOOT_HEEL_X = -0.055
"""Heel end of the foot, in the foot frame (m, x forward of the ankle)."""

FOOT_LENGTH = 0.26
"""Foot length heel to toe tip (m)."""

FOOT_HALF_WIDTH = 0.045
"""Half of the foot width (m)."""

TOE_JOINT_FRACTION = 0.8
"""Toe joint of the two-segment foot, as a fraction of foot length from the heel (contactvision §6.4)."""

# Collision bits: geoms collide if (contype_a & conaffinity_b) or (contype_b & conaffinity_a).
FLOOR_BIT, LEFT_LEG_BIT, RIGHT_LEG_BIT, ARM_BIT, TORSO_BIT, SOLE_BIT, OTHER_BIT = 1, 2, 4, 8, 16, 32, 64

COLLISION_GROUPS: dict[str, tuple[int, int]] = {
    # group: (contype, conaffinity)
    "left_leg": (LEFT_LEG_BIT, RIGHT_LEG_BIT | FLOOR_BIT),
    "right_leg": (RIGHT_LEG_BIT, LEFT_LEG_BIT | FLOOR_BIT),
    "left_foot": (LEFT_LEG_BIT, RIGHT_LEG_BIT),  # the sole spheres touch the floor, not the box
    "right_foot": (RIGHT_LEG_BIT, LEFT_LEG_BIT),
    "arm": (ARM_BIT, TORSO_BIT | FLOOR_BIT),
    "torso": (TORSO_BIT, ARM_BIT | FLOOR_BIT),
    "sole": (SOLE_BIT, FLOOR_BIT),
    "other": (OTHER_BIT, FLOOR_BIT),
}
"""Leg–leg and arm–torso contacts are on; everything else among body parts is filtered out."""


@dataclass(frozen=True)
class JointSpec:
    """Hinge chain of one body (1 or 3 hinges in series).

    Attributes:
        axes: hinge axes in order, e.g. ``"yxz"`` (flexion, ab/adduction, twist) or ``"y"``.
        sign: +1 or -1 per axis; a hinge about ``-y`` has sign -1 so that positive = flexion.
        range_deg: (low, high) per hinge, degrees.
        gains: key into :data:`PD_GAINS`.
    """

    axes: str
    range_deg: tuple[tuple[float, float], ...]
    gains: str
    sign: tuple[int, ...] | None = None

    def axis_vectors(self) -> np.ndarray:
        """Unit axes ``(n, 3)`` in the body frame, signs applied."""
        sign = self.sign or (1,) * len(self.axes)
        out = np.zeros((len(self.axes), 3))
        for i, (a, s) in enumerate(zip(self.axes, sign)):
            out[i, "xyz".index(a)] = s
        return out


@dataclass(frozen=True)
class Geom:
    """One geom: ``kind`` is capsule (``fromto``), sphere (``pos``) or box (``pos``, ``half``)."""

    kind: str
    collision: str
    fromto: tuple[float, ...] = ()
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    size: tuple[float, ...] = ()


@dataclass(frozen=True)
class Segment:
    """One rigid body.

    Attributes:
        name: body name (ADAPT topology, adapt §3.2.1).
        parent: parent body name, ``None`` for the root.
        pos: body origin in the parent frame (m).
        mass_fraction: share of :data:`MASS_KG`.
        com: centre of mass in the body frame (m).
        gyration: radii of gyration (m) about the body x, y, z axes.
        joint: hinge chain, or ``None`` (free root, or rigid like the hands).
        geoms: collision/visual geometry.
    """

    name: str
    parent: str | None
    pos: tuple[float, float, float]
    mass_fraction: float
    com: tuple[float, float, float]
    gyration: tuple[float, float, float]
    joint: JointSpec | None
    geoms: tuple[Geom, ...] = field(default_factory=tuple)


PD_GAINS: dict[str, tuple[float, float, float]] = {
    # name: (kp N·m/rad, kd N·m·s/rad, torque limit N·m); DeepMimic's humanoid gains, scaled.
    "spine": (1000.0, 100.0, 400.0),
    "neck": (300.0, 30.0, 100.0),
    "clavicle": (300.0, 30.0, 100.0),
    "shoulder": (400.0, 40.0, 150.0),
    "elbow": (300.0, 30.0, 100.0),
    "hip": (600.0, 60.0, 400.0),
    "knee": (600.0, 60.0, 400.0),
    "ankle": (400.0, 40.0, 200.0),
    "toe": (100.0, 10.0, 60.0),
}
"""The one PD gain table of both models (MuJoCo position actuators with damping)."""

JOINT_ARMATURE = 0.05
"""Rotor inertia (kg·m²) added to every hinge. The PD stiffness is integrated explicitly; with
0.01 the three-hinge shoulders and spine of a walking character went unstable within 0.2 s at the
1/120 s timestep, 0.05 keeps every locomotion clip stable in open-loop replay."""

_SPINE = JointSpec("xyz", ((-30, 30), (-40, 45), (-30, 30)), "spine")
_NECK = JointSpec("xyz", ((-40, 40), (-50, 50), (-60, 60)), "neck")


def _side(name: str, side: str) -> str:
    return f"{side}_{name}"


def _limb_segments(side: str) -> list[Segment]:
    """Arm and leg bodies of one side; ``side`` is ``"l"`` (+y) or ``"r"`` (-y)."""
    s = 1.0 if side == "l" else -1.0
    leg = "left_leg" if side == "l" else "right_leg"
    foot = "left_foot" if side == "l" else "right_foot"
    # Ab/adduction and twist ranges flip sign between sides; flexion does not.
    def lr(lo: float, hi: float) -> tuple[float, float]:
        return (lo, hi) if s > 0 else (-hi, -lo)

    foot_center_x = FOOT_HEEL_X + FOOT_LENGTH / 2
    return [
        Segment(_side("clavicle", side), "chest", (0.0, s * 0.03, 0.17), 0.010, (0.0, s * 0.08, 0.0),
                (0.03, 0.015, 0.03), JointSpec("xyz", (lr(-15, 15), (-20, 20), lr(-20, 20)), "clavicle"),
                (Geom("capsule", "other", fromto=(0, 0, 0, 0, s * 0.15, 0), size=(0.035,)),)),
        Segment(_side("upper_arm", side), _side("clavicle", side), (0.0, s * 0.17, 0.0), 0.0271,
                (0.0, 0.0, -0.168), (0.078, 0.083, 0.046),
                JointSpec("xzy", (lr(-30, 180), lr(-90, 90), (-180, 70)), "shoulder"),
                (Geom("capsule", "arm", fromto=(0, 0, -0.04, 0, 0, -0.25), size=(0.045,)),)),
        Segment(_side("forearm", side), _side("upper_arm", side), (0.0, 0.0, -0.29), 0.0162,
                (0.0, 0.0, -0.119), (0.069, 0.072, 0.031),
                JointSpec("y", ((-5, 150),), "elbow", sign=(-1,)),
                (Geom("capsule", "arm", fromto=(0, 0, -0.03, 0, 0, -0.22), size=(0.038,)),)),
        Segment(_side("hand", side), _side("forearm", side), (0.0, 0.0, -0.26), 0.0061,
                (0.0, 0.0, -0.068), (0.058, 0.066, 0.034), None,
                (Geom("capsule", "arm", fromto=(0, 0, -0.03, 0, 0, -0.11), size=(0.035,)),)),
        Segment(_side("thigh", side), "pelvis", (0.0, s * 0.09, 0.0), 0.1416, (0.0, 0.0, -0.176),
                (0.141, 0.141, 0.064), JointSpec("yxz", ((-125, 40), lr(-30, 50), lr(-45, 45)), "hip"),
                (Geom("capsule", leg, fromto=(0, 0, -0.06, 0, 0, -0.37), size=(0.065,)),)),
        Segment(_side("shin", side), _side("thigh", side), (0.0, 0.0, -0.43), 0.0433, (0.0, 0.0, -0.192),
                (0.107, 0.110, 0.044), JointSpec("y", ((-5, 155),), "knee"),
                (Geom("capsule", leg, fromto=(0, 0, -0.04, 0, 0, -0.37), size=(0.05,)),)),
        Segment(_side("foot", side), _side("shin", side), (0.0, 0.0, -0.43), 0.0137,
                (FOOT_HEEL_X + 0.4415 * FOOT_LENGTH, 0.0, SOLE_Z / 2), (0.032, 0.067, 0.064),
                JointSpec("yxz", ((-55, 45), lr(-35, 35), lr(-35, 35)), "ankle"),
                (Geom("box", foot, pos=(foot_center_x, 0.0, SOLE_Z + 0.025),
                      size=(FOOT_LENGTH / 2, FOOT_HALF_WIDTH, 0.025)),)),
    ]


def segments() -> list[Segment]:
    """All 20 bodies of the one-segment-foot model, parents before children."""
    core = [
        Segment("pelvis", None, (0.0, 0.0, 0.0), 0.1117, (0.0, 0.0, 0.04), (0.090, 0.080, 0.086), None,
                (Geom("capsule", "torso", fromto=(0, -0.04, 0.03, 0, 0.04, 0.03), size=(0.09,)),)),
        Segment("spine_lower", "pelvis", (0.0, 0.0, 0.10), 0.080, (0.0, 0.0, 0.05),
                (0.104, 0.083, 0.101), _SPINE,
                (Geom("capsule", "torso", fromto=(0, -0.04, 0.05, 0, 0.04, 0.05), size=(0.08,)),)),
        Segment("spine_mid", "spine_lower", (0.0, 0.0, 0.10), 0.0833, (0.0, 0.0, 0.05),
                (0.104, 0.083, 0.101), _SPINE,
                (Geom("capsule", "torso", fromto=(0, -0.04, 0.05, 0, 0.04, 0.05), size=(0.085,)),)),
        Segment("chest", "spine_mid", (0.0, 0.0, 0.11), 0.1396, (0.0, 0.0, 0.09),
                (0.086, 0.055, 0.079), _SPINE,
                (Geom("capsule", "torso", fromto=(0, -0.035, 0.09, 0, 0.035, 0.09), size=(0.10,)),)),
        Segment("neck", "chest", (0.0, 0.0, 0.20), 0.020, (0.0, 0.0, 0.05), (0.03, 0.03, 0.02), _NECK,
                (Geom("capsule", "other", fromto=(0, 0, 0.0, 0, 0, 0.08), size=(0.045,)),)),
        Segment("head", "neck", (0.0, 0.0, 0.10), 0.0494, (0.0, 0.0, 0.10), (0.074, 0.076, 0.063), _NECK,
                (Geom("sphere", "other", pos=(0.01, 0.0, 0.10), size=(0.10,)),)),
    ]
    return core + _limb_segments("l") + _limb_segments("r")


TOE_JOINT = JointSpec("y", ((-30, 60),), "toe", sign=(-1,))
"""Toe joint of the two-segment foot; about -y so that positive = toe dorsiflexion (push-off)."""

TOE_MASS_SHARE = 0.2
"""Share of the foot mass in the toe segment (heel:toe length 8:2)."""
