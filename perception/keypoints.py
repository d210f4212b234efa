"""Synthetic 2D lower-body keypoints from 3D motion (contactvision §4, Fig. 2; neural_physcap §3.2).

The 13 keypoints (:data:`KEYPOINTS`, OpenPose BODY_25's lower body: mid hip, right hip/knee/ankle,
left hip/knee/ankle, left big toe/small toe/heel, right big toe/small toe/heel) are points fixed
in our humanoid's bodies, projected through pinhole cameras that follow the subject: fixed views
around it (:func:`ring_cameras`, ContactVision's eight), random views (:func:`random_camera`) and
hand-held cameras with lag and shake (:func:`handheld_camera`). :func:`observe` adds pixel noise,
confidences and dropped points. Image coordinates are pixels, u right, v down; cameras look along
their +z axis (x right, y down).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter1d

from perception.skeleton import JointMap
from reference_motion import rotations as rot
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion

KEYPOINTS = ("mid_hip", "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee", "left_ankle",
             "left_big_toe", "left_small_toe", "left_heel", "right_big_toe", "right_small_toe", "right_heel")
"""The 13 lower-body keypoints ContactVision reads (mid hip first: inputs are relative to it)."""

FULL_BODY_KEYPOINTS = KEYPOINTS + ("nose", "neck", "right_shoulder", "right_elbow", "right_wrist", "left_shoulder",
                                   "left_elbow", "left_wrist", "right_eye", "left_eye", "right_ear", "left_ear")
"""All 25 of OpenPose BODY_25 (lower body first), for ContactVision's full-body ablation."""

KEYPOINT_SETS = {"lower": KEYPOINTS, "full": FULL_BODY_KEYPOINTS}

# foot keypoints in the foot body's rest frame (m): toe tip 2 cm above the sole, medial / lateral
# edge; heel 1 cm in front of the back of the sole
_TOE_TIP_X, _TOE_EDGE_Y, _HEEL_X, _ABOVE_SOLE = 0.205, 0.03, -0.045, 0.02
# upper-body keypoints: (body, offset in its frame, m); the head is a 10 cm sphere centred
# (0.01, 0, 0.1) in the head frame, x forward
_UPPER_BODY = {"nose": ("head", (0.11, 0.0, 0.1)), "neck": ("neck", (0.0, 0.0, 0.0)),
               "right_eye": ("head", (0.09, -0.035, 0.13)), "left_eye": ("head", (0.09, 0.035, 0.13)),
               "right_ear": ("head", (0.01, -0.1, 0.1)), "left_ear": ("head", (0.01, 0.1, 0.1))}
for _side, _s in (("right", "r"), ("left", "l")):
    _UPPER_BODY.update({f"{_side}_shoulder": (f"{_s}_upper_arm", (0.0, 0.0, 0.0)),
                        f"{_side}_elbow": (f"{_s}_forearm", (0.0, 0.0, 0.0)),
                        f"{_side}_wrist": (f"{_s}_hand", (0.0, 0.0, 0.0))})


@functools.lru_cache(maxsize=None)
def keypoint_map(model_name: str, keypoints: tuple[str, ...] = KEYPOINTS) -> JointMap:
    """Where each of ``keypoints`` (names from :data:`FULL_BODY_KEYPOINTS`) sits on
    ``humanoid_1seg`` or ``humanoid_2seg`` (body and offset)."""
    hm = load_model(model_name)
    m = hm.model
    names = hm.body_names
    kin = hm.forward_kinematics(hm.rest_qpos())
    bodies, offsets = [], []
    for key in keypoints:
        if key in _UPPER_BODY:
            body, offset = _UPPER_BODY[key]
            bodies.append(names.index(body))
            offsets.append(np.array(offset))
            continue
        if key == "mid_hip":
            bodies.append(names.index("pelvis"))
            offsets.append(0.5 * (m.body_pos[m.body("l_thigh").id] + m.body_pos[m.body("r_thigh").id]))
            continue
        side, part = key.split("_", 1)
        s = side[0]
        if part in ("hip", "knee", "ankle"):
            bodies.append(names.index({"hip": f"{s}_thigh", "knee": f"{s}_shin", "ankle": f"{s}_foot"}[part]))
            offsets.append(np.zeros(3))
            continue
        foot = names.index(f"{s}_foot")
        medial = -1.0 if s == "l" else 1.0  # the left foot's inner edge is towards -y
        sole_z = m.site_pos[m.site(f"{s}_heel_point").id][2]
        local = {"big_toe": (_TOE_TIP_X, medial * _TOE_EDGE_Y, sole_z + _ABOVE_SOLE),
                 "small_toe": (_TOE_TIP_X, -medial * _TOE_EDGE_Y, sole_z + _ABOVE_SOLE),
                 "heel": (_HEEL_X, 0.0, sole_z + _ABOVE_SOLE)}[part]
        carrier = foot
        if part != "heel":  # on the two-segment foot the toes ride on the toe segment
            carrier = int(m.site_bodyid[m.site(f"{s}_toe_point").id]) - 1
        world = kin.body_pos[0, foot] + rot.rotate(kin.body_quat[0, foot], np.array(local))
        bodies.append(carrier)
        offsets.append(rot.rotate(rot.conjugate(kin.body_quat[0, carrier]), world - kin.body_pos[0, carrier]))
    return JointMap(model_name, np.array(bodies), np.array(offsets, dtype=float))


def motion_keypoints(motion: Motion, keypoints: tuple[str, ...] = KEYPOINTS) -> np.ndarray:
    """The ``keypoints`` ``(T, K, 3)`` of every frame of ``motion`` (world, m)."""
    kin = load_model(motion.model).forward_kinematics(motion.qpos)
    return keypoint_map(motion.model, keypoints).positions(kin.body_pos, kin.body_quat)


# ----------------------------------------------------------------------------- cameras
@dataclass(frozen=True)
class Camera:
    """A pinhole camera per frame: ``position (T, 3)`` and ``rotation (T, 3, 3)`` (rows: the
    camera's x right, y down, z forward axes in world coordinates), focal length in pixels, image
    size in pixels, principal point at the image centre."""

    position: np.ndarray
    rotation: np.ndarray
    focal_px: float
    width: int
    height: int

    @property
    def centre(self) -> tuple[float, float]:
        return self.width / 2.0, self.height / 2.0

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixels ``(T, K, 2)`` and depths ``(T, K)`` (m along the view axis) of world points
        ``(T, K, 3)``."""
        cam = np.einsum("tij,tkj->tki", self.rotation, points - self.position[:, None, :])
        depth = cam[..., 2]
        safe = np.where(depth > 1e-6, depth, np.nan)
        cx, cy = self.centre
        uv = np.stack([cx + self.focal_px * cam[..., 0] / safe, cy + self.focal_px * cam[..., 1] / safe], -1)
        return uv, depth


def look_at(position: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Rotations ``(T, 3, 3)`` of cameras at ``position (T, 3)`` looking at ``target (T, 3)``, level
    (no roll; world z up appears as image up)."""
    forward = target - position
    forward /= np.linalg.norm(forward, axis=-1, keepdims=True)
    right = np.cross(forward, np.array([0.0, 0.0, 1.0]))
    right /= np.linalg.norm(right, axis=-1, keepdims=True)
    down = np.cross(forward, right)
    return np.stack([right, down, forward], axis=1)


def _follow(pelvis: np.ndarray, azimuth: float, distance: float, height: float, aim_height: float
            ) -> tuple[np.ndarray, np.ndarray]:
    target = np.concatenate([pelvis[:, :2], np.full((len(pelvis), 1), aim_height)], axis=1)
    offset = np.array([np.cos(azimuth) * distance, np.sin(azimuth) * distance, 0.0])
    position = target + offset
    position[:, 2] = height
    return position, target


def follow_camera(pelvis: np.ndarray, azimuth: float, distance: float = 4.0, height: float = 1.0,
                  aim_height: float = 0.6, focal_px: float = 1000.0, width: int = 1280, height_px: int = 720) -> Camera:
    """A camera ``distance`` m from the subject horizontally, in world direction ``azimuth`` (rad,
    from +x towards +y), ``height`` m above the floor, aimed at ``aim_height`` above the pelvis'
    ground point, following the pelvis trajectory ``(T, 3)`` horizontally (a dolly, not a pan)."""
    position, target = _follow(pelvis, azimuth, distance, height, aim_height)
    return Camera(position, look_at(position, target), focal_px, width, height_px)


def ring_cameras(pelvis: np.ndarray, n: int = 8, distance: float = 4.0, height: float = 1.0,
                 focal_px: float = 1000.0, width: int = 1280, height_px: int = 720) -> list[Camera]:
    """``n`` :func:`follow_camera` views at azimuths 0, 360/n, ... degrees around the subject
    (ContactVision Fig. 2), aimed at the lower body (0.6 m)."""
    return [follow_camera(pelvis, 2 * np.pi * k / n, distance, height, 0.6, focal_px, width, height_px)
            for k in range(n)]


def _random_view(rng: np.random.Generator, azimuth: float | None) -> dict:
    """Azimuth (rad; uniform unless given), distance (2.5–6 m), height (0.3–2 m), aim height
    (0.3–0.9 m), focal length (700–1500 px)."""
    return {"azimuth": rng.uniform(0, 2 * np.pi) if azimuth is None else azimuth, "distance": rng.uniform(2.5, 6.0),
            "height": rng.uniform(0.3, 2.0), "aim_height": rng.uniform(0.3, 0.9), "focal_px": float(rng.uniform(700, 1500))}


def random_camera(pelvis: np.ndarray, rng: np.random.Generator, azimuth: float | None = None, width: int = 1280,
                  height_px: int = 720) -> Camera:
    """A random view (:func:`_random_view`; at ``azimuth`` rad when given) following the pelvis
    trajectory ``(T, 3)``."""
    v = _random_view(rng, azimuth)
    return follow_camera(pelvis, v["azimuth"], v["distance"], v["height"], v["aim_height"], v["focal_px"], width,
                         height_px)


def handheld_camera(pelvis: np.ndarray, rng: np.random.Generator, azimuth: float | None = None, fps: float = 60.0,
                    lag_s: float = 0.5, shake_m: float = 0.03, shake_rad: float = 0.01, width: int = 1280,
                    height_px: int = 720, view: dict | None = None) -> Camera:
    """A hand-held random view (at ``azimuth`` rad when given; ``view`` fixes any of
    :func:`_random_view`'s ``distance``, ``height``, ``aim_height``, ``focal_px``): the operator
    walks after the subject with ``lag_s`` of smoothing and keeps it aimed, with positional
    (``shake_m``, m) and angular (``shake_rad``) hand shake varying over ~0.1 s."""
    v = {**_random_view(rng, azimuth), **(view or {})}
    lagged = gaussian_filter1d(pelvis, sigma=lag_s * fps, axis=0, mode="nearest")
    position, _ = _follow(lagged, v["azimuth"], v["distance"], v["height"], v["aim_height"])
    _, target = _follow(pelvis, v["azimuth"], v["distance"], v["height"], v["aim_height"])
    sigma = 0.1 * fps
    gain = np.sqrt(2.0 * np.sqrt(np.pi) * sigma)  # unit standard deviation after smoothing
    position = position + shake_m * gain * gaussian_filter1d(rng.standard_normal(position.shape), sigma, axis=0)
    aim_jitter = shake_rad * v["distance"] * gain * gaussian_filter1d(rng.standard_normal(target.shape), sigma, axis=0)
    return Camera(position, look_at(position, target + aim_jitter), v["focal_px"], width, height_px)


# ----------------------------------------------------------------------------- observing
def observe(points: np.ndarray, camera: Camera, rng: np.random.Generator, noise_px: float = 2.0,
            drop_prob: float = 0.02) -> np.ndarray:
    """Detector-like keypoints ``(T, K, 3)`` = (u, v, confidence) of world points ``(T, K, 3)``:
    Gaussian pixel noise of ``noise_px``, confidence falling with the noise drawn (0.5–1), and
    points dropped (confidence 0, u = v = 0) with probability ``drop_prob`` or when behind the
    camera or outside the image."""
    uv, depth = camera.project(points)
    noise = rng.normal(0.0, noise_px, uv.shape)
    uv = uv + noise
    conf = np.clip(1.0 - 0.25 * np.linalg.norm(noise, axis=-1) / max(noise_px, 1e-9) / 2.0, 0.5, 1.0)
    visible = (depth > 0.1) & np.isfinite(uv).all(-1) & (uv[..., 0] >= 0) & (uv[..., 0] < camera.width) \
        & (uv[..., 1] >= 0) & (uv[..., 1] < camera.height)
    keep = visible & (rng.random(visible.shape) >= drop_prob)
    out = np.concatenate([np.where(keep[..., None], uv, 0.0), np.where(keep, conf, 0.0)[..., None]], axis=-1)
    return out


def normalize_image(keypoints: np.ndarray, width: int, height: int) -> np.ndarray:
    """(u, v) divided by the image size and made relative to the mid hip (dropped points stay 0)."""
    out = keypoints.copy()
    out[..., 0] /= width
    out[..., 1] /= height
    return _pelvis_relative(out)


def canonicalize(keypoints: np.ndarray, camera: Camera) -> np.ndarray:
    """Neural PhysCap eq. 6: [(u − c_x)/f_x, (v − c_y)/f_y], then relative to the mid hip."""
    out = keypoints.copy()
    cx, cy = camera.centre
    out[..., 0] = (out[..., 0] - cx) / camera.focal_px
    out[..., 1] = (out[..., 1] - cy) / camera.focal_px
    return _pelvis_relative(out)


def _pelvis_relative(keypoints: np.ndarray) -> np.ndarray:
    out = keypoints.copy()
    seen = out[..., 2] > 0
    root = out[:, :1, :2]
    out[..., :2] = np.where(seen[..., None], out[..., :2] - root, 0.0)
    return out
