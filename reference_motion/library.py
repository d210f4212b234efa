"""Turning a SOURCE string into a :class:`Motion`: the one entry point every tool uses.

SOURCE forms:

* ``deepmimic:NAME`` — a DeepMimic clip in the installed ``pybullet_data`` (``deepmimic:walk``,
  ``deepmimic:walker/turn_left0``); ``deepmimic:all`` is not a clip (see :func:`named_set`).
* ``PATH.npz`` — a saved Motion (must have been saved for the requested model).
* ``library:DIR#NAME`` — a take of a motion library (:mod:`reference_motion.motion_library`).
* ``PATH.bvh`` — a BVH file of any common rig (:mod:`reference_motion.rigs`; a joint map for others).
* ``PATH.amc`` — a CMU ASF/AMC take, with the ``.asf`` found beside it.
* ``PATH.txt`` — a DeepMimic-format JSON file.

Mocap sources are retargeted, looped if asked, resampled and then footskate-cleaned
(:func:`reference_motion.footskate.pin_contacts`) at the output rate; a saved ``.npz`` Motion is
returned as saved (resampled only if asked), and so is a library take.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from reference_motion import asf_amc, bvh, deepmimic
from reference_motion.footskate import pin_contacts
from reference_motion.motion import Motion
from reference_motion.motion_library import PREFIX as LIBRARY_PREFIX, is_library_set, library_set, resolve_take
from reference_motion.retarget import retarget
from reference_motion.rigs import MocapOptions
from reference_motion.source import SourceClip
from reference_motion.stance import wider_stance
from reference_motion.transforms import (ENV_FPS, PostureRanges, loop, mirror, random_posture, resample, time_warp,
                                         with_posture)

NAMED_SETS: dict[str, Callable[[], list[str]]] = {
    "deepmimic": lambda: [f"deepmimic:{n}" for n in deepmimic.clip_names()],
    "locomotion": lambda: ["deepmimic:walk", "deepmimic:run"]
    + [f"deepmimic:{n}" for n in deepmimic.clip_names() if n.startswith("walker/")],
}
"""Named clip sets: ``deepmimic`` (all 20), ``locomotion`` (walk, run and the five walker clips)."""


def is_clip_set(name: str) -> bool:
    """Whether ``name`` names a clip set: one of :data:`NAMED_SETS`, or a motion library's
    ``library:DIR`` / ``library:DIR/SPLIT`` (:mod:`reference_motion.motion_library`)."""
    return name in NAMED_SETS or is_library_set(name)


def named_set(name: str) -> list[str]:
    """The SOURCE strings of a clip set (:func:`is_clip_set`); ``KeyError`` lists the sets."""
    if is_library_set(name):
        return library_set(name)
    if name not in NAMED_SETS:
        raise KeyError(f"unknown clip set {name!r}; available: {', '.join(NAMED_SETS)}, library:DIR[/train|val|test]")
    return NAMED_SETS[name]()


def expand_clips(sources: Sequence[str]) -> list[str]:
    """SOURCE strings with every clip set among them (:func:`is_clip_set`) replaced by its clips."""
    out: list[str] = []
    for source in sources:
        out += named_set(source) if is_clip_set(str(source)) else [str(source)]
    return out


MOCAP_SUFFIXES = (".bvh", ".amc", ".txt")
"""Mocap files :func:`load_source_clip` reads: BVH, ASF/AMC, DeepMimic JSON."""


def load_source_clip(source: str | Path, mocap: MocapOptions = MocapOptions()) -> SourceClip:
    """The skeleton animation of a mocap SOURCE (``deepmimic:NAME`` or a :data:`MOCAP_SUFFIXES`
    file), before retargeting."""
    text = str(source)
    path = Path(text)
    if text.startswith("deepmimic:"):
        return deepmimic.load(text.removeprefix("deepmimic:"))
    if path.suffix == ".bvh":
        return bvh.load(path, mocap)
    if path.suffix == ".amc":
        return asf_amc.load(path, mocap)
    if path.suffix == ".txt":
        if not path.exists():
            raise FileNotFoundError(f"{path}: no such DeepMimic file")
        return deepmimic.load(path)
    raise ValueError(f"cannot read motion source {text!r}: expected deepmimic:NAME, library:DIR#TAKE, or a .npz, "
                     ".bvh, .amc (ASF/AMC) or .txt (DeepMimic JSON) file")


def load_motion(source: str | Path, model: str = "humanoid_1seg", fps: float | None = ENV_FPS,
                min_frames: int | None = None, mocap: MocapOptions = MocapOptions(),
                pin_feet: bool = True) -> Motion:
    """Load, retarget and resample SOURCE for ``model``.

    Args:
        source: see the module docstring.
        model: ``humanoid_1seg`` or ``humanoid_2seg``.
        fps: output rate (default 60 Hz, the environments' rate); ``None`` keeps the source rate.
        min_frames: loop cyclic clips until they have at least this many frames at ``fps``.
        mocap: joint map, units, up axis or ASF skeleton of a mocap file, where detection is not
            wanted (:class:`~reference_motion.rigs.MocapOptions`).
        pin_feet: remove the foot sliding of mocap sources (not applied to ``.npz`` Motions).
    """
    text = str(source)
    stored = text.startswith(LIBRARY_PREFIX) or Path(text).suffix == ".npz"
    if text.startswith(LIBRARY_PREFIX):
        motion = Motion.load(resolve_take(text, model), model=model)
    elif Path(text).suffix == ".npz":
        motion = Motion.load(Path(text), model=model)
    else:
        motion = retarget(load_source_clip(text, mocap), model)
    if min_frames and motion.loop:
        target_fps = fps or motion.fps
        needed = int(round(min_frames * motion.fps / target_fps)) + 2
        if needed > motion.n_frames:
            motion = loop(motion, needed)
    if fps is not None:
        motion = resample(motion, fps)
    if pin_feet and not stored:
        motion = pin_contacts(motion)
    return motion


def warped(motion: Motion, speed: float) -> Motion:
    """``motion`` played ``speed`` times as fast (:func:`~reference_motion.transforms.time_warp`)
    and footskate-cleaned again, since resampling the warped poses lets pinned feet slide by up to
    one frame's interpolation error; ``motion`` itself at speed 1."""
    return motion if speed == 1.0 else pin_contacts(time_warp(motion, speed))


def postured(motion: Motion, offsets: np.ndarray, label: str) -> Motion:
    """``motion`` carried with the posture ``offsets`` (:func:`~reference_motion.transforms.with_posture`,
    named ``label``) and footskate-cleaned again, since the changed leg angles let the stance feet
    slide as the pelvis turns over them."""
    return pin_contacts(with_posture(motion, offsets, label))


def posture_copies(motions: Sequence[Motion], copies: int, seed: int | Sequence[int],
                   ranges: PostureRanges = PostureRanges()) -> list[Motion]:
    """``copies`` copies of each of ``motions`` (clip by clip), each carried with its own random
    posture drawn from ``ranges`` (:func:`~reference_motion.transforms.random_posture`,
    :func:`postured`) with ``numpy.random.default_rng(seed)``: the same copies for the same seed."""
    rng = np.random.default_rng(seed)
    return [postured(m, random_posture(m.model, rng, ranges), f"posture {k}") for m in motions for k in range(copies)]


STANCE_EXTRA_M = (0.0, 0.35)
"""How much further apart :func:`stance_copies` walks by default (m, low and high): up to about the
widest stance of the training takes (chimpira's sideways walks) against a normal walk's."""
MAX_NARROWING_M = 0.3
"""The most :func:`check_stance_extra` lets a stance narrow (m): a walk's feet are rarely 0.3 m apart."""


def check_stance_extra(extra_m: Sequence[float], what: str) -> tuple[float, float]:
    """``extra_m`` (m, low and high) as a float pair, checked: two finite numbers, ``low <= high``,
    and no closer than feet together (``low > -MAX_NARROWING_M``); a ``ValueError`` naming ``what``
    (the option or field that gave it) otherwise."""
    values = tuple(extra_m)
    if len(values) != 2:
        raise ValueError(f"{what} must be two numbers (low, high) in metres, got {extra_m!r}")
    low, high = (float(v) for v in values)
    if not (np.isfinite(low) and np.isfinite(high) and -MAX_NARROWING_M < low <= high):
        raise ValueError(f"{what} {low:g} {high:g}: expected finite metres, {-MAX_NARROWING_M:g} < LOW <= HIGH")
    return low, high


def stance_copies(motions: Sequence[Motion], copies: int, seed: int | Sequence[int],
                  extra_m: tuple[float, float] = STANCE_EXTRA_M) -> list[Motion]:
    """``copies`` copies of each of ``motions`` (clip by clip), each walked with the feet further
    apart by its own distance drawn uniformly from ``extra_m`` (m, low and high) with
    ``numpy.random.default_rng(seed)``, the body swaying as the wider steps need
    (:func:`~reference_motion.stance.wider_stance`): the same copies for the same seed."""
    low, high = check_stance_extra(extra_m, "extra_m")
    rng = np.random.default_rng(seed)
    return [wider_stance(m, round(float(rng.uniform(low, high)), 3)) for m in motions for _ in range(copies)]


@dataclass(frozen=True)
class StyleShifts:
    """How :func:`style_shifted` re-makes a take the ways the library's styles differ from one another:
    in the width of the stance, the pace and the carriage. Each range stays within what the training
    styles span, so a shifted take is one a person of another style could have walked.

    Attributes:
        stance_extra_m: (low, high) metres further apart the feet walk, drawn uniformly: within
            :data:`STANCE_EXTRA_M`, :func:`stance_copies`' default range (up to about the widest
            training stance, chimpira's sideways walks, against a normal walk's), from 0.1 m so that
            every copy is a wider walk.
        slower: speed of the slower copy (a time warp; the training split's forward walks go at median
            speeds from 0.3 to 1.6 m/s, 1.0 in the middle).
        faster: speed of the faster copy.
        posture: ranges of the carriage (stoop, crouch, stance, neck and elbows) the postured copy is
            drawn from (:class:`~reference_motion.transforms.PostureRanges`).
    """

    stance_extra_m: tuple[float, float] = (0.1, 0.35)
    slower: float = 0.8
    faster: float = 1.25
    posture: PostureRanges = PostureRanges()

    def __post_init__(self) -> None:
        check_stance_extra(self.stance_extra_m, "StyleShifts.stance_extra_m")
        if not (0 < self.slower < 1 < self.faster and np.isfinite(self.faster)):
            raise ValueError(f"StyleShifts: expected 0 < slower < 1 < faster, got slower {self.slower!r}, "
                             f"faster {self.faster!r}")


STYLE_SHIFT_NAMES = ("as given", "wider", "slower", "faster", "postured")
"""The versions of a take :func:`style_shifted` returns, in its order."""


def style_shifted(motions: Sequence[Motion], seed: int, shifts: StyleShifts = StyleShifts()) -> list[Motion]:
    """Each of ``motions`` in the five versions of :data:`STYLE_SHIFT_NAMES`, take by take: as given,
    walked wider (:func:`~reference_motion.stance.wider_stance` by a distance drawn from
    ``shifts.stance_extra_m``), played at ``shifts.slower`` and at ``shifts.faster`` times its pace
    (:func:`warped`), and carried with a posture drawn from ``shifts.posture`` (:func:`postured`);
    ``5 · len(motions)`` clips, the draws made with ``numpy.random.default_rng(seed)``, so the same
    seed gives the same copies. A validation set of one style seen through these is a set of takes
    that differ from it as the styles differ, so a policy's choice can see style shift."""
    rng = np.random.default_rng(seed)
    out = []
    for motion in motions:
        extra = round(float(rng.uniform(*shifts.stance_extra_m)), 3)
        posture = random_posture(motion.model, rng, shifts.posture)
        out += [motion, wider_stance(motion, extra), warped(motion, shifts.slower), warped(motion, shifts.faster),
                postured(motion, posture, "posture")]
    return out


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
