"""Retargeting a :class:`SourceClip` onto ``humanoid_1seg`` / ``humanoid_2seg``.

Method (per frame, all rotations in the z-up world):

1. The source rig is turned so that its rest pose faces +x like ours.
2. Each canonical joint's world rotation ``G_src`` is composed with a rest alignment ``A`` (the
   shortest arc taking our rest bone direction onto the source's), so ``G = G_src·A`` points our
   bone where the source bone points — identity for rigs with our rest pose (DeepMimic), the
   T-pose → arms-down correction for most BVH rigs.
3. Rotations become joint angles down our tree: the chest rotation is spread evenly over
   ``spine_lower``, ``spine_mid`` and ``chest``; the neck rotation over ``neck`` and ``head``;
   knees and elbows keep the twist about their hinge axis; clavicles, wrists and toes (which the
   sources lack) stay at rest.
4. Root translation is scaled (:func:`fit_root_scale`): our legs and feet have other proportions
   than the source's, so no single length ratio keeps planted feet planted; the scale is the
   least-squares one for which the foot points in contact move least, starting from (and kept
   within ±20% of) the ratio of leg lengths. The clip is turned to start facing +x at the origin.
5. Soles level in stance (:func:`stance_sole_pitch`): a rig whose foot bone ends elsewhere than
   ours leaves our feet pitched by a constant angle: Bandai Namco's takes walked on tiptoe, soles
   21 degrees down and heels 7 cm up, CMU's on their heels, soles 7 degrees up. For a rig whose
   rest foot bone is not ours, where the soles' most common pitch over their stance frames is beyond
   :data:`FOOT_LEVEL_TOLERANCE_DEG`, both feet are turned about their ankles by the opposite angle
   (``source["foot_level_deg"]``) and the root is fitted again. This assumes feet flat in stance,
   as in walking and running; a clip without such stance (crawling) from such a rig may be
   mis-levelled.
6. Feet on the floor (:func:`floor_lift`): the clip is moved vertically so its support level
   (:func:`support_level`) is z = 0, and where a frame would still reach below the floor (mocap
   landings often do: DeepMimic's run lands 5 cm deep) the root is raised just enough, with a
   short Gaussian blend into the neighbouring frames.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import gaussian_filter1d

from reference_motion import rotations as rot
from reference_motion.humanoid import anthropometry as A
from reference_motion.humanoid.model import HumanoidModel, Kinematics, load_model
from reference_motion.motion import Motion
from reference_motion.source import BONES, CANONICAL_JOINTS, SourceClip

MODEL_POINTS: dict[str, tuple[str, tuple[float, float, float]]] = {
    # canonical joint: (model body, offset in that body's frame)
    "root": ("pelvis", (0, 0, 0)), "chest": ("chest", (0, 0, 0)), "neck": ("neck", (0, 0, 0)),
    "head_end": ("head", (0.01, 0, 0.10)),
    **{f"{side}_{joint}": (f"{side[0]}_{body}", (0, 0, 0)) for side in ("left", "right")
       for joint, body in (("hip", "thigh"), ("knee", "shin"), ("ankle", "foot"), ("shoulder", "upper_arm"),
                           ("elbow", "forearm"), ("wrist", "hand"))},
    **{f"{side}_toe_end": (f"{side[0]}_foot", (A.FOOT_HEEL_X + A.FOOT_LENGTH, 0, A.SOLE_Z))
       for side in ("left", "right")},
}
"""Where each canonical joint sits on our humanoid (for rest alignment and bone comparisons)."""

_SPREAD = {"chest": ("spine_lower", "spine_mid", "chest"), "neck": ("neck", "head")}


def model_joint_positions(model: HumanoidModel, kin: Kinematics, foot_level_rad: float = 0.0) -> np.ndarray:
    """Canonical joint positions ``(T, J, 3)`` (world, m) on the humanoid, from its kinematics.
    ``foot_level_rad``: the toe ends as they would be without the retargeter's foot levelling of
    that angle (``source["foot_level_deg"]``), i.e. where the source's foot bones point."""
    out = np.zeros((kin.body_pos.shape[0], len(CANONICAL_JOINTS), 3))
    unlevel = _toe_up(-foot_level_rad)
    for j, name in enumerate(CANONICAL_JOINTS):
        body, offset = MODEL_POINTS[name]
        offset = np.asarray(offset, float)
        if name.endswith("toe_end") and foot_level_rad:
            offset = rot.rotate(unlevel, offset)
        b = model.body_names.index(body)
        out[:, j] = kin.body_pos[:, b] + rot.rotate(kin.body_quat[:, b], offset)
    return out


def bone_directions(joint_pos: np.ndarray) -> np.ndarray:
    """Unit bone directions ``(T, len(BONES), 3)`` from canonical joint positions ``(T, J, 3)``."""
    idx = CANONICAL_JOINTS.index
    d = np.stack([joint_pos[:, idx(end)] - joint_pos[:, idx(j)] for j, end in BONES.items()], axis=1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def _rest_facing_yaw(clip: SourceClip) -> float:
    """Heading (rad) of the source rig's rest pose: forward = (left hip − right hip) × up."""
    lateral = clip.offsets[CANONICAL_JOINTS.index("left_hip")] - clip.offsets[CANONICAL_JOINTS.index("right_hip")]
    fwd = np.cross(lateral, [0.0, 0.0, 1.0])
    return float(np.arctan2(fwd[1], fwd[0]))


def _face_plus_x(clip: SourceClip) -> SourceClip:
    """Change the rig's basis by a yaw so that its rest pose faces +x (animation unchanged)."""
    yaw = _rest_facing_yaw(clip)
    if abs(yaw) < 1e-6:
        return clip
    q = rot.from_axis_angle(np.array([0.0, 0.0, 1.0]), -yaw)
    qc = rot.conjugate(q)
    local = rot.multiply(rot.multiply(q, clip.local_quats), qc)
    return SourceClip(clip.name, clip.fps, rot.rotate(q, clip.offsets), rot.rotate(q, clip.root_pos),
                      local, clip.loop, clip.source)


def model_leg_length(model: HumanoidModel) -> float:
    """Hip-to-ankle length (m) of the humanoid in its rest pose."""
    pos = model_joint_positions(model, model.forward_kinematics(model.rest_qpos()))[0]
    idx = CANONICAL_JOINTS.index
    return float(np.linalg.norm(pos[idx("left_hip")] - pos[idx("left_ankle")]))


def _model_rest_directions(model: HumanoidModel) -> dict[str, np.ndarray]:
    pos = model_joint_positions(model, model.forward_kinematics(model.rest_qpos()))
    dirs = bone_directions(pos)[0]
    return dict(zip(BONES, dirs))


SUPPORT_BAND_M = 0.02
"""Width (m) of the height band in which :func:`support_level` looks for the most frames."""

FLOOR_BLEND_S = 0.03
"""Standard deviation (s) of the Gaussian that blends a local penetration fix into neighbouring frames."""


def support_level(lowest: np.ndarray, band: float = SUPPORT_BAND_M) -> float:
    """Height (m) at which a clip stands: the median of the densest ``band``-wide cluster of the
    per-frame lowest body point ``(T,)`` among its lower half. Stance frames cluster; landing
    dips and flight frames are sparse, so neither moves it."""
    values = np.sort(np.asarray(lowest, dtype=float))
    lower = values[: max(1, (len(values) + 1) // 2)]
    counts = np.searchsorted(values, lower + band, side="right") - np.arange(len(lower))
    start = int(np.argmax(counts))
    return float(np.median(values[start:start + counts[start]]))


def floor_lift(lowest: np.ndarray, fps: float) -> np.ndarray:
    """Vertical root offset ``(T,)`` (m) that puts a clip's support level on z = 0 and removes the
    floor penetration left after that, given the per-frame lowest body point ``(T,)`` (m)."""
    base = support_level(lowest)
    depth = np.maximum(base - lowest, 0.0)
    local = gaussian_filter1d(depth, sigma=max(FLOOR_BLEND_S * fps, 0.5), mode="nearest")
    return np.maximum(local, depth) - base


ROOT_SCALE_LIMITS = (0.8, 1.25)
"""Bounds of the fitted root scale, relative to the ratio of leg lengths."""

CONTACT_FIT_HEIGHT = 0.02
"""Foot points within this height (m) of the support level count as planted for the scale fit."""


def fit_root_scale(root_xy: np.ndarray, points_xy: np.ndarray, planted: np.ndarray, initial: float) -> float:
    """Scale ``s`` minimising the horizontal motion of planted foot points.

    Args:
        root_xy: ``(T, 2)`` source root trajectory (m), heading-normalised.
        points_xy: ``(T, P, 2)`` foot points computed with the root at ``initial * root_xy``.
        planted: ``(T, P)`` bool, point on the ground.
        initial: starting scale (ratio of leg lengths).

    A point's position is ``s·root + offset(pose)``; over consecutive planted frames we minimise
    ``Σ |s·Δroot + Δoffset|²`` in closed form. Returns ``initial`` when nothing is planted.
    """
    offsets = points_xy - initial * root_xy[:, None, :]
    d_root = np.diff(root_xy, axis=0)[:, None, :]
    d_off = np.diff(offsets, axis=0)
    held = planted[1:] & planted[:-1]
    a = np.broadcast_to(d_root, d_off.shape)[held]
    b = d_off[held]
    denom = float(np.sum(a * a))
    if denom < 1e-12:
        return initial
    s = -float(np.sum(a * b)) / denom
    lo, hi = ROOT_SCALE_LIMITS
    return float(np.clip(s, lo * initial, hi * initial))


def _set_hinges(qpos: np.ndarray, model: HumanoidModel, body: str, local: np.ndarray) -> np.ndarray:
    """Write the hinge angles of ``body`` reproducing ``local (T, 4)``; returns the rotation the
    hinges actually realise (differs from ``local`` for 1-DoF bodies)."""
    bj = model.body_joints[body]
    if len(bj.axes) == 3:
        qpos[:, bj.qpos_index] = rot.to_hinges(local, bj.axes)
        return local
    angle = rot.twist_angle(local, bj.axis_vectors[0])
    qpos[:, bj.qpos_index[0]] = angle
    return rot.from_axis_angle(bj.axis_vectors[0], angle)


def retarget(clip: SourceClip, model_name: str = "humanoid_1seg") -> Motion:
    """Retarget ``clip`` onto ``model_name``; returns a Motion at the clip's frame rate."""
    model = load_model(model_name)
    clip = _face_plus_x(clip)
    _, g_src = clip.global_pose()
    rest_src = clip.rest_bone_directions()
    rest_model = _model_rest_directions(model)
    idx = CANONICAL_JOINTS.index
    target = {j: rot.multiply(g_src[:, idx(j)], rot.between_vectors(rest_model[j], rest_src[j])) for j in BONES}

    T = clip.n_frames
    qpos = np.tile(model.rest_qpos(), (T, 1))
    qpos[:, 3:7] = target["root"]
    world = {"root": target["root"]}  # world rotation each canonical joint actually gets
    for joint in ("chest", "neck"):
        parent = "root" if joint == "chest" else "chest"
        rel = rot.multiply(rot.conjugate(world[parent]), target[joint])
        bodies = _SPREAD[joint]
        part = rot.power(rel, 1.0 / len(bodies))
        for body in bodies:
            _set_hinges(qpos, model, body, part)
        world[joint] = target[joint]
    for side, s in (("left", "l"), ("right", "r")):
        chain = ((f"{side}_hip", "root", f"{s}_thigh"), (f"{side}_knee", f"{side}_hip", f"{s}_shin"),
                 (f"{side}_ankle", f"{side}_knee", f"{s}_foot"),
                 (f"{side}_shoulder", "chest", f"{s}_upper_arm"),
                 (f"{side}_elbow", f"{side}_shoulder", f"{s}_forearm"))
        for joint, parent, body in chain:
            local = rot.multiply(rot.conjugate(world[parent]), target[joint])
            world[joint] = rot.multiply(world[parent], _set_hinges(qpos, model, body, local))

    qpos[:, 7:] = np.unwrap(qpos[:, 7:], axis=0)
    heading = float(rot.yaw(qpos[0, 3:7]))
    turn = rot.from_axis_angle(np.array([0.0, 0.0, 1.0]), -heading)
    root = rot.rotate(turn, clip.root_pos - clip.root_pos[0] * [1.0, 1.0, 0.0])
    qpos[:, 3:7] = rot.normalize(rot.multiply(turn, qpos[:, 3:7]))

    leg_ratio = model_leg_length(model) / clip.leg_length()
    scale, lift = _place_root(qpos, root, model, leg_ratio, clip.fps)
    level = 0.0
    foot_bones_differ = any(_angle(rest_model[f"{side}_ankle"], rest_src[f"{side}_ankle"]) > FOOT_REST_MATCH_RAD
                            for side in ("left", "right"))
    if foot_bones_differ:  # a rig with our rest pose (DeepMimic's) has our feet: its pitch is the motion's
        pitch = stance_sole_pitch(model.forward_kinematics(qpos).foot_points, clip.fps)
        level = -pitch if abs(np.nan_to_num(pitch)) > np.radians(FOOT_LEVEL_TOLERANCE_DEG) else 0.0
    if level:
        toe_up = _toe_up(level)
        for side, s in (("left", "l"), ("right", "r")):
            local = rot.multiply(rot.conjugate(world[f"{side}_knee"]), rot.multiply(target[f"{side}_ankle"], toe_up))
            _set_hinges(qpos, model, f"{s}_foot", local)
        qpos[:, 7:] = np.unwrap(qpos[:, 7:], axis=0)
        scale, lift = _place_root(qpos, root, model, leg_ratio, clip.fps)

    source = dict(clip.source, retargeted_to=model_name, heading_offset_rad=-heading, root_scale=scale,
                  leg_length_ratio=leg_ratio, foot_level_deg=round(float(np.degrees(level)), 2),
                  floor_lift_m=[float(lift.min()), float(lift.max())], source_fps=clip.fps)
    return Motion(name=clip.name, fps=clip.fps, qpos=qpos, model=model_name, loop=clip.loop, source=source)


FOOT_LEVEL_TOLERANCE_DEG = 5.0
"""Soles pitched by more than this (degrees) in stance (:func:`stance_sole_pitch`) are taken for
a mismatch between the source's foot bone and ours and levelled; less is the clip's own style
(DeepMimic's clips, whose rig is ours, have -4 to +5 degrees)."""

FOOT_REST_MATCH_RAD = np.radians(5.0)
"""Rigs whose rest foot bones point within this of ours (DeepMimic's, our rest pose: 1.7 degrees; Bandai Namco's and
CMU's: 18.9) are not levelled."""

STANCE_SPEED_MPS = 0.5
"""A foot is in stance when its lower sole point is planted (:data:`CONTACT_FIT_HEIGHT`) and its
sole's midpoint moves slower than this horizontally (m/s)."""

PITCH_BIN_DEG = 2.0
"""Width (degrees) of the bins in which :func:`stance_sole_pitch` finds the most common stance pitch."""

MIN_STANCE_S = 0.3
"""A clip with less stance than this (s, both feet together) is not levelled (its pitch is not known)."""


def stance_sole_pitch(foot_points: np.ndarray, fps: float) -> float:
    """Most common pitch (rad, toe above heel positive) of the soles over the frames their foot is
    in stance, both feet pooled (a mismatch of rigs pitches both alike), from the sole points
    ``(T, 4, 3)`` (world, m; LT, RT, LH, RH as :attr:`Kinematics.foot_points`); NaN for a clip with
    less than :data:`MIN_STANCE_S` of stance. The mode (:data:`PITCH_BIN_DEG` bins, smoothed over
    three) is the flat-foot phase; a median drifts in bouncy styles that spend long on the forefoot
    (Bandai Namco's `happy` walks: median 30 degrees down, mode 21 like every other take)."""
    lowest = foot_points[..., 2].min(axis=1)
    planted_level = support_level(lowest) + CONTACT_FIT_HEIGHT
    pitches = []
    for toe, heel in ((0, 2), (1, 3)):
        sole = foot_points[:, toe] - foot_points[:, heel]
        pitch = np.arctan2(sole[:, 2], np.linalg.norm(sole[:, :2], axis=1))
        middle = 0.5 * (foot_points[:, toe, :2] + foot_points[:, heel, :2])
        speed = np.linalg.norm(np.gradient(middle, axis=0), axis=1) * fps
        stance = (np.minimum(foot_points[:, toe, 2], foot_points[:, heel, 2]) <= planted_level) & (
            speed < STANCE_SPEED_MPS)
        pitches.append(pitch[stance])
    pooled = np.degrees(np.concatenate(pitches))
    if len(pooled) < MIN_STANCE_S * fps:
        return float("nan")
    edges = np.arange(-90.0, 90.0 + PITCH_BIN_DEG, PITCH_BIN_DEG)
    counts = np.convolve(np.histogram(pooled, bins=edges)[0], [1, 2, 1], mode="same")
    return float(np.radians(edges[np.argmax(counts)] + PITCH_BIN_DEG / 2))


def _toe_up(angle: float) -> np.ndarray:
    """Rotation ``(4,)`` of a foot about its own lateral axis (y) that raises its toe by ``angle`` (rad)."""
    return rot.from_axis_angle(np.array([0.0, 1.0, 0.0]), -angle)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """Angle (rad) between vectors ``a`` and ``b`` (3,)."""
    cos = np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.arccos(np.clip(cos, -1.0, 1.0)))


def _place_root(qpos: np.ndarray, root: np.ndarray, model: HumanoidModel, leg_ratio: float,
                fps: float) -> tuple[float, np.ndarray]:
    """Write the root translation into ``qpos`` (:func:`fit_root_scale`, then :func:`floor_lift`)
    for the root path ``root (T, 3)`` (source units × 1); returns the scale and the lift ``(T,)``."""
    qpos[:, :3] = root * leg_ratio
    kin = model.forward_kinematics(qpos)
    planted = kin.foot_points[..., 2] <= support_level(kin.lowest) + CONTACT_FIT_HEIGHT
    scale = fit_root_scale(root[:, :2], kin.foot_points[..., :2], planted, leg_ratio)
    qpos[:, :3] = root * scale
    lift = floor_lift(model.forward_kinematics(qpos).lowest, fps)
    qpos[:, 2] += lift
    return scale, lift


def bone_direction_error(clip: SourceClip, motion: Motion) -> np.ndarray:
    """Angle (degrees) between each bone of the retargeted ``motion`` and the same bone of the
    source ``clip``, per frame: ``(T, len(BONES))``. Both must have the same frames (the
    retargeter's output before resampling). Levelled feet are compared as they were before
    levelling (:func:`model_joint_positions`), so the error measures the retargeting alone."""
    model = load_model(motion.model)
    level = np.radians(motion.source.get("foot_level_deg", 0.0))
    ours = bone_directions(model_joint_positions(model, model.forward_kinematics(motion.qpos), level))
    src_pos, _ = clip.global_pose()
    turn = rot.from_axis_angle(np.array([0.0, 0.0, 1.0]), motion.source["heading_offset_rad"])
    theirs = rot.rotate(turn, bone_directions(src_pos))
    return np.degrees(np.arccos(np.clip(np.sum(ours * theirs, -1), -1.0, 1.0)))
