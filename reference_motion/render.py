"""Offscreen rendering of motions (kinematic replay) to MP4, GIF or PNG.

Uses MuJoCo's renderer; on a machine without a display set ``MUJOCO_GL=egl`` (software EGL works).
Several motions render as panels side by side (e.g. reference | result), each panel following its
own character with the same camera angle.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np
from tqdm import tqdm

from reference_motion.atomic import atomic_write
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion

SUPPORTED = (".mp4", ".gif", ".png")
"""Output types :func:`render` writes."""

CLOTHES = {"skin": (0.87, 0.72, 0.6, 1.0), "shirt": (0.75, 0.15, 0.15, 1.0), "trousers": (0.15, 0.2, 0.45, 1.0),
           "shoes": (0.1, 0.1, 0.1, 1.0)}
"""Colours of a dressed character: person detectors (MediaPipe) find it in almost every frame,
where they miss the grey mannequin most of the time."""

MARK_RGB, MARK_BORDER_PX = (230, 20, 20), 10
"""Colour and width of the border drawn around a marked frame (:func:`render_frames`' ``marked``)."""


def _garment(geom_name: str) -> str:
    if any(k in geom_name for k in ("head", "neck", "forearm", "hand")):
        return "skin"
    if any(k in geom_name for k in ("thigh", "shin")):
        return "trousers"
    if any(k in geom_name for k in ("foot", "sole", "toe")):
        return "shoes"
    return "shirt"


def render_frames(motion: Motion, width: int = 480, height: int = 360, fps: float | None = None,
                  azimuth: float = 90.0, elevation: float = -12.0, distance: float = 3.2,
                  clothed: bool = False, marked: np.ndarray | None = None, progress: bool = False,
                  lookat_height: float = 0.9) -> np.ndarray:
    """RGB frames ``(N, height, width, 3)`` uint8 of ``motion`` replayed kinematically.

    ``fps`` (default: the motion's) picks frames by nearest time; the camera tracks the pelvis
    at MuJoCo's free-camera ``azimuth`` / ``elevation`` (degrees; azimuth 90° looks along +y, from
    the character's right when it walks along +x) and ``distance`` (m), aimed at the point
    ``lookat_height`` (m) above the floor under the pelvis. ``clothed`` dresses the
    character in :data:`CLOTHES`. ``marked`` ``(motion.n_frames,)`` bool: frames showing a marked
    motion frame get a red border (:data:`MARK_RGB`). ``progress`` shows a progress bar.
    """
    hm = load_model(motion.model)
    model = hm.model
    if clothed:
        saved = model.geom_rgba.copy(), model.geom_matid.copy()
        try:
            for g in range(model.ngeom):
                if model.geom(g).name != "floor":
                    model.geom_rgba[g], model.geom_matid[g] = CLOTHES[_garment(model.geom(g).name)], -1
            return render_frames(motion, width, height, fps, azimuth, elevation, distance, clothed=False,
                                 marked=marked, progress=progress, lookat_height=lookat_height)
        finally:
            model.geom_rgba[:], model.geom_matid[:] = saved
    data = mujoco.MjData(model)
    fps = fps or motion.fps
    n_out = max(1, int(round(motion.duration * fps)) + 1)
    index = np.clip(np.round(np.arange(n_out) * motion.fps / fps).astype(int), 0, motion.n_frames - 1)
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.azimuth, cam.elevation, cam.distance = azimuth, elevation, distance
    frames = np.empty((n_out, height, width, 3), dtype=np.uint8)
    with mujoco.Renderer(model, height=height, width=width) as renderer:
        for k, t in enumerate(tqdm(index, desc=f"rendering {motion.name}", unit="frame", disable=not progress)):
            data.qpos[:] = motion.qpos[t]
            mujoco.mj_forward(model, data)
            cam.lookat[:] = [data.qpos[0], data.qpos[1], lookat_height]
            renderer.update_scene(data, camera=cam)
            frames[k] = renderer.render()
    if marked is not None:
        b = MARK_BORDER_PX
        for k in np.flatnonzero(np.asarray(marked, bool)[index]):
            frames[k, :b], frames[k, -b:], frames[k, :, :b], frames[k, :, -b:] = (MARK_RGB,) * 4
    return frames


def render(motions: Motion | list[Motion], out: str | Path, fps: float = 30.0, width: int = 480,
           height: int = 360, marked: Sequence[np.ndarray | None] | None = None, progress: bool = False,
           footer: np.ndarray | None = None) -> Path:
    """Render one motion, or several side by side, to ``out`` (.mp4, .gif, or .png = first frame).

    Panels are padded to the longest motion by holding their last frame; the file is written
    atomically. ``marked`` (one entry per motion, ``None`` or see :func:`render_frames`) draws a red
    border around the marked frames of each panel; ``progress`` shows a progress bar per panel.
    ``footer`` ``(h, len(motions)·width, 3)`` uint8: an image shown under the panels (e.g. a
    timeline whose x axis spans the clip), with a cursor moving across it from the first frame
    to the last.
    """
    out = Path(out)
    if out.suffix.lower() not in SUPPORTED:
        raise ValueError(f"{out}: unsupported output type {out.suffix!r}; use one of {', '.join(SUPPORTED)}")
    motions = [motions] if isinstance(motions, Motion) else list(motions)
    marked = [None] * len(motions) if marked is None else list(marked)
    if len(marked) != len(motions):
        raise ValueError(f"marked has {len(marked)} entries for {len(motions)} motions")
    panels = [render_frames(m, width, height, fps, marked=k, progress=progress) for m, k in zip(motions, marked)]
    n = max(len(p) for p in panels)
    panels = [np.concatenate([p, np.repeat(p[-1:], n - len(p), axis=0)]) for p in panels]
    video = np.concatenate(panels, axis=2)
    if footer is not None:
        video = _with_footer(video, footer)
    import imageio.v2 as imageio

    with atomic_write(out) as tmp:
        if out.suffix.lower() == ".png":
            imageio.imwrite(tmp, video[0])
        elif out.suffix.lower() == ".gif":
            imageio.mimsave(tmp, video, duration=1000.0 / fps, loop=0)
        else:
            imageio.mimsave(tmp, video, fps=fps, macro_block_size=1)
    return out


CURSOR_RGB = (230, 20, 20)
"""Colour of the time cursor drawn on a :func:`render` footer."""


def _with_footer(video: np.ndarray, footer: np.ndarray) -> np.ndarray:
    """``video (N, H, W, 3)`` with ``footer (h, W, 3)`` under every frame and a 2-pixel cursor at
    the frame's time (frame 0 at the left edge, frame N − 1 at the right)."""
    n, _, w, _ = video.shape
    footer = np.asarray(footer)
    if footer.ndim != 3 or footer.shape[1:] != (w, 3) or footer.dtype != np.uint8:
        raise ValueError(f"footer must be a (h, {w}, 3) uint8 image for panels {w} pixels wide, got "
                         f"{footer.shape} {footer.dtype}")
    strips = np.repeat(footer[None], n, axis=0)
    x = np.round(np.arange(n) * (w - 2) / max(n - 1, 1)).astype(int)
    for k in range(n):
        strips[k, :, x[k]:x[k] + 2] = CURSOR_RGB
    return np.concatenate([video, strips], axis=1)
