"""UnderPressure's 23-joint skeleton (underpressure §4.1, SPEC "Data") on our humanoids.

The vGRF network reads 3D joint positions ``(T, 23, 3)`` (world frame, z up, m) in UnderPressure's
joint order (:data:`JOINTS`, parents in :data:`PARENTS`), so a network trained on our simulated
data reads UnderPressure's Xsens sequences too. On our MJCF humanoids each joint is a point fixed
in one body (:class:`JointMap`): the body origins for the hips, knees, ankles, shoulders, elbows,
wrists, clavicles, spine, neck and head; ``spine_4`` halfway up the chest towards the neck; each
``foot`` joint (Xsens' toe joint, the ball of the foot) above the sole's toe point.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from reference_motion import rotations as rot
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion

JOINTS = ("pelvis", "spine_1", "spine_2", "spine_3", "spine_4", "neck", "head",
          "right_clavicle", "right_shoulder", "right_elbow", "right_wrist",
          "left_clavicle", "left_shoulder", "left_elbow", "left_wrist",
          "right_hip", "right_knee", "right_ankle", "right_foot",
          "left_hip", "left_knee", "left_ankle", "left_foot")
"""UnderPressure's joint order (its ``data.TOPOLOGY``)."""

PARENTS = (-1, 0, 1, 2, 3, 4, 5, 4, 7, 8, 9, 4, 11, 12, 13, 0, 15, 16, 17, 0, 19, 20, 21)
"""Parent index of each joint of :data:`JOINTS` (``-1`` for the pelvis)."""

N_JOINTS = len(JOINTS)

MIRROR = tuple(JOINTS.index(j.replace("left", "#").replace("right", "left").replace("#", "right")) for j in JOINTS)
"""Joint permutation of a left/right mirror."""

FOOT_JOINTS = tuple(JOINTS.index(j) for j in ("left_foot", "right_foot", "left_ankle", "right_ankle"))
"""Joints above the four contact regions, in CONTACT_CHANNELS order (left_toe, right_toe,
left_heel, right_heel): the OT baseline thresholds their height and speed."""

BALL_HEIGHT_M = 0.03
"""Height of the ``foot`` joint (ball of the foot) above the sole."""

_BODY_OF = {"pelvis": "pelvis", "spine_1": "spine_lower", "spine_2": "spine_mid", "spine_3": "chest",
            "neck": "neck", "head": "head"}
for _side, _s in (("right", "r"), ("left", "l")):
    _BODY_OF.update({f"{_side}_clavicle": f"{_s}_clavicle", f"{_side}_shoulder": f"{_s}_upper_arm",
                     f"{_side}_elbow": f"{_s}_forearm", f"{_side}_wrist": f"{_s}_hand",
                     f"{_side}_hip": f"{_s}_thigh", f"{_side}_knee": f"{_s}_shin", f"{_side}_ankle": f"{_s}_foot"})


@dataclass(frozen=True)
class JointMap:
    """Where each of the 23 joints sits on one MJCF humanoid.

    Attributes:
        model: humanoid model name.
        body: ``(23,)`` index (into the model's bodies, world excluded) of the body carrying each joint.
        offset: ``(23, 3)`` the joint's position in that body's frame (m).
    """

    model: str
    body: np.ndarray
    offset: np.ndarray

    def positions(self, body_pos: np.ndarray, body_quat: np.ndarray) -> np.ndarray:
        """Joint positions ``(..., 23, 3)`` from body origins ``(..., nbody, 3)`` and orientations
        ``(..., nbody, 4)`` (world frame, world body excluded)."""
        return body_pos[..., self.body, :] + rot.rotate(body_quat[..., self.body, :], self.offset)


@functools.lru_cache(maxsize=None)
def joint_map(model_name: str) -> JointMap:
    """The :class:`JointMap` of ``humanoid_1seg`` or ``humanoid_2seg`` (cached)."""
    hm = load_model(model_name)
    m = hm.model
    body_ids = {name: i for i, name in enumerate(hm.body_names)}
    bodies, offsets = [], []
    for joint in JOINTS:
        if joint == "spine_4":  # halfway from the chest origin to the neck origin
            bodies.append(body_ids["chest"])
            offsets.append(0.5 * m.body_pos[m.body("neck").id])
        elif joint.endswith("_foot"):  # above the toe point on the sole, in the site's body
            site = m.site(f"{joint[0]}_toe_point")
            bodies.append(int(m.site_bodyid[site.id]) - 1)
            offsets.append(m.site_pos[site.id] + np.array([0.0, 0.0, BALL_HEIGHT_M]))
        else:
            bodies.append(body_ids[_BODY_OF[joint]])
            offsets.append(np.zeros(3))
    return JointMap(model_name, np.array(bodies), np.array(offsets, dtype=float))


def motion_joint_positions(motion: Motion) -> np.ndarray:
    """The 23 joint positions ``(T, 23, 3)`` of every frame of ``motion`` (world, m)."""
    kin = load_model(motion.model).forward_kinematics(motion.qpos)
    return joint_map(motion.model).positions(kin.body_pos, kin.body_quat)


def mirror_positions(positions: np.ndarray) -> np.ndarray:
    """Joint positions ``(..., 23, 3)`` of the left/right mirrored motion (world y negated)."""
    out = positions[..., MIRROR, :].copy()
    out[..., 1] *= -1.0
    return out


def check_positions(positions: np.ndarray, what: str) -> np.ndarray:
    """``positions`` as float32 ``(T, 23, 3)``, or a ``ValueError`` naming ``what`` and the problem."""
    arr = np.asarray(positions)
    if arr.ndim != 3 or arr.shape[1:] != (N_JOINTS, 3):
        raise ValueError(f"{what}: joint positions must have shape (frames, {N_JOINTS}, 3) in UnderPressure's "
                         f"joint order, got {arr.shape}")
    if arr.shape[0] == 0:
        raise ValueError(f"{what}: the clip is empty (0 frames)")
    if not np.isfinite(arr).all():
        bad = int(np.argwhere(~np.isfinite(arr))[0, 0])
        raise ValueError(f"{what}: joint positions contain NaN or inf (first at frame {bad})")
    return arr.astype(np.float32)
