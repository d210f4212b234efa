"""A motion library on disk: retargeted takes, a manifest, and a train/validation/test split.

Layout of a library directory ``DIR`` (written by ``python -m reference_motion import``)::

    DIR/manifest.json                 every take: source file, fps, frames, content, style, split,
                                      quality before/after pinning, retarget bone-direction error;
                                      and every refused file with the reason
    DIR/humanoid_1seg/NAME.npz        the take retargeted, resampled to 60 Hz and pinned, per model
    DIR/humanoid_2seg/NAME.npz

Clip SOURCE strings: ``library:DIR#NAME`` is one take (for whichever humanoid is asked);
``library:DIR`` and ``library:DIR/train`` (``/val``, ``/test``) are clip sets.

The split (:func:`split_of`) is fixed by content, so it is the same wherever the library is built:
every take of the styles in :data:`TEST_STYLES` and the CMU takes in :data:`TEST_TAKES` are test,
the style :data:`VAL_STYLE` is validation, the rest is training.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

PREFIX = "library:"
SPLITS = ("train", "val", "test")
MANIFEST = "manifest.json"

TEST_STYLES = ("old", "tired", "giant")
"""Bandai Namco styles held out for testing: motions unlike any seen in training."""

TEST_TAKES = ("02_03",)
"""Other takes held out for testing (CMU subject 02's run/jog)."""

VAL_STYLE = "happy"
"""The Bandai Namco style used for validation (model selection), never for training."""

CMU_CONTENT = {"02_01": "walk", "02_02": "walk", "02_03": "run", "02_04": "jump", "02_05": "punch",
               "02_06": "punch", "02_07": "swordplay", "02_08": "swordplay", "02_09": "wash", "02_10": "stretch"}
"""Content of CMU subject 02's takes (the database's own descriptions, shared/mocap/README.md)."""

LOCOMOTION = ("walk", "walk-back", "walk-left", "walk-right", "run", "dash")
"""Contents that are locomotion (the generalist's training data)."""

_BANDAI = re.compile(r"^dataset-\d+_(?P<content>[a-z-]+)_(?P<style>[a-z-]+)_(?P<id>\d+)$")


def labels(name: str) -> tuple[str, str]:
    """``(content, style)`` of a take from its file stem: Bandai Namco names
    ``dataset-1_{content}_{style}_{id}``, CMU subject 02 from :data:`CMU_CONTENT`; else
    ``("unknown", "unknown")``."""
    m = _BANDAI.match(name)
    if m:
        return m["content"], m["style"]
    return CMU_CONTENT.get(name, "unknown"), "cmu" if name in CMU_CONTENT else "unknown"


def split_of(name: str, style: str) -> str:
    """The split of a take (see the module docstring)."""
    if style in TEST_STYLES or name in TEST_TAKES:
        return "test"
    return "val" if style == VAL_STYLE else "train"


def take_path(directory: str | Path, name: str, model: str) -> Path:
    """Where take ``name`` retargeted to ``model`` lives."""
    return Path(directory) / model / f"{name}.npz"


LIBRARY_FORMAT = "physmimic.library/3"
"""Format of the libraries this code writes and reads (2: feet levelled in stance by the retargeter;
3: no shuffling foot dragged across its steps by the footskate pinning, ``PinningConfig.max_correction_m``)."""


def read_manifest(directory: str | Path) -> dict:
    """The library's manifest; a clear error when ``directory`` is no library."""
    path = Path(directory) / MANIFEST
    if not path.exists():
        raise FileNotFoundError(f"{directory}: not a motion library (no {MANIFEST}); "
                                "build one with: python -m reference_motion import PATH... --out DIR")
    try:
        manifest = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: damaged manifest ({err})") from None
    if manifest.get("format") != LIBRARY_FORMAT:
        raise ValueError(f"{path}: a library of format {manifest.get('format')!r}, made by an older import "
                         f"(format 2 dragged shuffling feet across their steps, 1 had unlevelled feet); expected "
                         f"{LIBRARY_FORMAT!r}: import again with "
                         f"python -m reference_motion import PATH... --out {directory}")
    return manifest


def is_library_set(name: str) -> bool:
    """Whether ``name`` is a library clip set (``library:DIR`` or ``library:DIR/SPLIT``)."""
    return name.startswith(PREFIX) and "#" not in name


def library_set(name: str, contents: tuple[str, ...] | None = None) -> list[str]:
    """The take SOURCE strings (``library:DIR#NAME``) of clip set ``name``, in manifest order;
    ``contents`` keeps only takes of those contents (e.g. :data:`LOCOMOTION`)."""
    spec = name.removeprefix(PREFIX).rstrip("/")
    directory, split = spec, None
    head, _, tail = spec.rpartition("/")
    if tail in SPLITS and head:
        directory, split = head, tail
    takes = read_manifest(directory)["takes"]
    chosen = [t["name"] for t in takes if (split is None or t["split"] == split)
              and (contents is None or t["content"] in contents)]
    if not chosen:
        raise ValueError(f"{name}: no takes{f' in split {split!r}' if split else ''}"
                         f"{f' with content {contents}' if contents else ''}")
    return [f"{PREFIX}{directory}#{n}" for n in chosen]


def resolve_take(source: str, model: str) -> Path:
    """The ``.npz`` file of ``library:DIR#NAME`` for ``model``; errors name the take."""
    directory, _, name = source.removeprefix(PREFIX).partition("#")
    path = take_path(directory, name, model)
    if not path.exists():
        known = {t["name"] for t in read_manifest(directory)["takes"]}
        if name not in known:
            raise KeyError(f"{source}: no take {name!r} in the library {directory}")
        raise FileNotFoundError(f"{source}: {path} is missing (re-run the import to rebuild it)")
    return path
