"""Video front end: MediaPipe Pose landmarks → the 13 ContactVision keypoints (``video`` extra).

MediaPipe's 33 landmarks (``model_complexity=1``, the model inside the ``mediapipe==0.10.14``
wheel, so it runs offline) map onto :data:`~perception.keypoints.KEYPOINTS`: the hips, knees,
ankles and heels directly, the mid hip as the hips' mean, and both toes as MediaPipe's single
``foot_index`` point (it has no small toe). Points below ``min_visibility`` are dropped, and
gaps of up to ``max_gap`` frames are filled by linear interpolation (:func:`fill_gaps`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from tqdm import tqdm

from perception.keypoints import KEYPOINTS

MEDIAPIPE_INDEX = {"right_hip": 24, "right_knee": 26, "right_ankle": 28, "left_hip": 23, "left_knee": 25,
                   "left_ankle": 27, "left_big_toe": 31, "left_small_toe": 31, "left_heel": 29,
                   "right_big_toe": 32, "right_small_toe": 32, "right_heel": 30}
"""Landmark index (MediaPipe Pose's 33) of each keypoint but the mid hip."""

VIDEO_SUFFIXES = (".mp4", ".avi", ".mov", ".mkv", ".webm")


def landmarks_to_keypoints(landmarks: np.ndarray, width: int, height: int, min_visibility: float = 0.5) -> np.ndarray:
    """Keypoints ``(T, 13, 3)`` (u, v in pixels, confidence) from MediaPipe landmarks
    ``(T, 33, 3)`` = (x, y normalised to the image, visibility); frames without a detection are
    NaN rows. Points less visible than ``min_visibility`` are dropped (all zero)."""
    lm = np.asarray(landmarks, dtype=float)
    if lm.ndim != 3 or lm.shape[1:] != (33, 3):
        raise ValueError(f"MediaPipe landmarks must have shape (frames, 33, 3) = (x, y, visibility), got {lm.shape}")
    out = np.zeros((len(lm), len(KEYPOINTS), 3))
    pixels = lm[..., :2] * np.array([width, height])
    for k, name in enumerate(KEYPOINTS):
        if name == "mid_hip":
            uv, vis = pixels[:, [23, 24]].mean(1), lm[:, [23, 24], 2].min(1)
        else:
            uv, vis = pixels[:, MEDIAPIPE_INDEX[name]], lm[:, MEDIAPIPE_INDEX[name], 2]
        keep = np.isfinite(vis) & (vis >= min_visibility)
        out[:, k, :2] = np.where(keep[:, None], uv, 0.0)
        out[:, k, 2] = np.where(keep, vis, 0.0)
    return out


def fill_gaps(keypoints: np.ndarray, max_gap: int = 3) -> np.ndarray:
    """Keypoints ``(T, K, 3)`` with each point's runs of up to ``max_gap`` missing frames
    (confidence 0) between two seen frames filled by linear interpolation (confidence too)."""
    out = np.array(keypoints, dtype=float, copy=True)
    seen = out[..., 2] > 0
    for k in range(out.shape[1]):
        t = 0
        while t < len(out):
            if seen[t, k]:
                t += 1
                continue
            stop = t
            while stop < len(out) and not seen[stop, k]:
                stop += 1
            if t > 0 and stop < len(out) and stop - t <= max_gap:
                w = (np.arange(t, stop) - (t - 1))[:, None] / (stop - (t - 1))
                out[t:stop, k] = (1 - w) * out[t - 1, k] + w * out[stop, k]
            t = stop
    return out


def _mediapipe():
    try:
        import mediapipe as mp
    except ImportError:
        raise ImportError("the video front end needs MediaPipe: pip install -e \".[video]\" "
                          "(mediapipe==0.10.14)") from None
    return mp


def detect_landmarks(frames: np.ndarray | list, progress: bool = False) -> np.ndarray:
    """MediaPipe Pose landmarks ``(T, 33, 3)`` = (x, y normalised, visibility) of RGB frames
    ``(T, H, W, 3)`` uint8, NaN where no person is found (video mode: tracking across frames)."""
    mp = _mediapipe()
    out = np.full((len(frames), 33, 3), np.nan)
    with mp.solutions.pose.Pose(static_image_mode=False, model_complexity=1) as pose:
        for t, frame in enumerate(tqdm(frames, desc="MediaPipe", unit="frame", disable=not progress)):
            result = pose.process(np.ascontiguousarray(frame))
            if result.pose_landmarks is not None:
                out[t] = [(p.x, p.y, p.visibility) for p in result.pose_landmarks.landmark]
    return out


def read_video(path: Path) -> tuple[np.ndarray, float]:
    """RGB frames ``(T, H, W, 3)`` and frame rate of a video file."""
    import imageio.v3 as iio

    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such video")
    try:
        frames = iio.imread(path)
        fps = float(iio.immeta(path).get("fps", 0.0))
    except Exception as err:  # noqa: BLE001 (the readers raise many types for a bad file)
        raise ValueError(f"{path}: not a readable video ({err.__class__.__name__}: {err})") from None
    if frames.ndim != 4 or not len(frames):
        raise ValueError(f"{path}: no frames")
    if fps <= 0:
        raise ValueError(f"{path}: the video does not state its frame rate")
    return frames[..., :3], fps


def video_keypoints(path: Path, min_visibility: float = 0.5, max_gap: int = 3,
                    progress: bool = False) -> tuple[np.ndarray, float]:
    """The 13 keypoints ``(T, 13, 3)`` (pixels, confidence) of the person in a video, and its fps."""
    frames, fps = read_video(path)
    landmarks = detect_landmarks(frames, progress)
    if np.isnan(landmarks[:, 0, 0]).all():
        raise ValueError(f"{path}: MediaPipe found no person in any of the {len(frames)} frames")
    h, w = frames.shape[1:3]
    return fill_gaps(landmarks_to_keypoints(landmarks, w, h, min_visibility), max_gap), fps
