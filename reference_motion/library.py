"""Turning a SOURCE string into a :class:`Motion`: the one entry point every tool uses.

SOURCE forms:

* ``deepmimic:NAME`` — a DeepMimic clip in the installed ``pybullet_data`` (``deepmimic:walk``,
  ``deepmimic:walker/turn_left0``); ``deepmimic:all`` is not a clip (see :func:`named_set`).
* ``PATH.npz`` — a saved Motion (must have been saved for the requested model).
* ``PATH.bvh`` — a BVH file (CMU-style joint names unless a name map is given).
* ``PATH.txt`` — a DeepMimic-format JSON file.

Mocap sources are retargeted, looped if asked, resampled and then footskate-cleaned
(:func:`reference_motion.footskate.pin_contacts`) at the output rate; a saved ``.npz`` Motion is
returned as saved (resampled only if asked).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from reference_motion import bvh, deepmimic
from reference_motion.footskate import pin_contacts
from reference_motion.motion import Motion
from reference_motion.retarget import retarget
from reference_motion.transforms import ENV_FPS, loop, mirror, resample, time_warp

NAMED_SETS = {
    "deepmimic": lambda: [f"deepmimic:{n}" for n in deepmimic.clip_names()],
    "locomotion": lambda: ["deepmimic:walk", "deepmimic:run"]
    + [f"deepmimic:{n}" for n in deepmimic.clip_names() if n.startswith("walker/")],
}
"""Named clip sets: ``deepmimic`` (all 20), ``locomotion`` (walk, run and the five walker clips)."""


def named_set(name: str) -> list[str]:
    """The SOURCE strings of a named set; ``KeyError`` lists the sets."""
    if name not in NAMED_SETS:
        raise KeyError(f"unknown clip set {name!r}; available: {', '.join(NAMED_SETS)}")
    return NAMED_SETS[name]()


def load_motion(source: str | Path, model: str = "humanoid_1seg", fps: float | None = ENV_FPS,
                min_frames: int | None = None, bvh_name_map: dict[str, str] | None = None,
                pin_feet: bool = True) -> Motion:
    """Load, retarget and resample SOURCE for ``model``.

    Args:
        source: see the module docstring.
        model: ``humanoid_1seg`` or ``humanoid_2seg``.
        fps: output rate (default 60 Hz, the environments' rate); ``None`` keeps the source rate.
        min_frames: loop cyclic clips until they have at least this many frames at ``fps``.
        bvh_name_map: canonical → BVH joint names for ``.bvh`` sources.
        pin_feet: remove the foot sliding of mocap sources (not applied to ``.npz`` Motions).
    """
    text = str(source)
    path = Path(text)
    if text.startswith("deepmimic:"):
        motion = retarget(deepmimic.load(text.removeprefix("deepmimic:")), model)
    elif path.suffix == ".npz":
        motion = Motion.load(path, model=model)
    elif path.suffix == ".bvh":
        motion = retarget(bvh.load(path, bvh_name_map), model)
    elif path.suffix == ".txt":
        if not path.exists():
            raise FileNotFoundError(f"{path}: no such DeepMimic file")
        motion = retarget(deepmimic.load(path), model)
    else:
        raise ValueError(f"cannot read motion source {text!r}: expected deepmimic:NAME, or a .npz, .bvh or "
                         ".txt (DeepMimic JSON) file")
    if min_frames and motion.loop:
        target_fps = fps or motion.fps
        needed = int(round(min_frames * motion.fps / target_fps)) + 2
        if needed > motion.n_frames:
            motion = loop(motion, needed)
    if fps is not None:
        motion = resample(motion, fps)
    if pin_feet and path.suffix != ".npz":
        motion = pin_contacts(motion)
    return motion


def warped(motion: Motion, speed: float) -> Motion:
    """``motion`` played ``speed`` times as fast (:func:`~reference_motion.transforms.time_warp`)
    and footskate-cleaned again, since resampling the warped poses lets pinned feet slide by up to
    one frame's interpolation error; ``motion`` itself at speed 1."""
    return motion if speed == 1.0 else pin_contacts(time_warp(motion, speed))


def augmented(motions: Sequence[Motion], mirrored: bool = False, speeds: Sequence[float] = (1.0,)) -> list[Motion]:
    """Every clip of ``motions`` at each speed of ``speeds`` (:func:`warped`) and, if ``mirrored``,
    also performed by the other side of the body: ``len(motions) · len(speeds) · (2 if mirrored
    else 1)`` clips; per clip, the speeds in the order given, then their mirrored copies."""
    if not speeds:
        raise ValueError("speeds is empty: give at least one time-warp speed (1.0 = unchanged)")
    out = []
    for motion in motions:
        variants = [warped(motion, s) for s in speeds]
        out += variants + ([mirror(v) for v in variants] if mirrored else [])
    return out
