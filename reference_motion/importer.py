"""Building a motion library from mocap files: ``python -m reference_motion import PATH... --out DIR``.

Every take (a ``.bvh`` or ``.amc`` file, or every such file under a directory) is loaded, its rig
detected, retargeted onto both humanoids, resampled to 60 Hz and pinned
(:func:`~reference_motion.footskate.pin_contacts`); the result is written per model
(:mod:`reference_motion.motion_library`) with a manifest entry: source file, fps, frames,
content, style, split, artefact metrics before and after pinning, the retarget's bone-direction
error and the rig as detected. A take that cannot be used is refused with the reason. The import
is resumable: a take already in the manifest with its files present is not redone.
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from reference_motion.atomic import atomic_write
from reference_motion.footskate import pin_contacts
from reference_motion.library import load_source_clip
from reference_motion.motion_library import LIBRARY_FORMAT, MANIFEST, TEST_STYLES, TEST_TAKES, VAL_STYLE, labels, split_of, take_path
from reference_motion.quality import motion_quality
from reference_motion.retarget import bone_direction_error, retarget
from reference_motion.rigs import MocapOptions
from reference_motion.transforms import ENV_FPS, resample

MODELS = ("humanoid_1seg", "humanoid_2seg")
TAKE_SUFFIXES = (".bvh", ".amc")


@dataclass(frozen=True)
class ImportConfig:
    """What makes a take usable.

    Attributes:
        min_duration_s: shortest take kept (s): a policy needs about a second to settle into a motion.
        max_bone_error_deg: largest mean bone-direction error (degrees) of the retarget kept; beyond
            it the rig was misread (a wrong joint map).
        max_bone_error_p95_deg: the same for the 95th percentile over frames and bones.
    """

    min_duration_s: float = 1.0
    max_bone_error_deg: float = 5.0
    max_bone_error_p95_deg: float = 20.0


def find_takes(paths: Sequence[str | Path]) -> list[Path]:
    """The take files named by ``paths``: files as given, directories searched recursively for
    :data:`TAKE_SUFFIXES`; sorted, duplicates removed."""
    found: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            found += [f for f in sorted(p.rglob("*")) if f.suffix in TAKE_SUFFIXES]
        elif p.exists():
            if p.suffix not in TAKE_SUFFIXES:
                raise ValueError(f"{p}: not a take file (expected {', '.join(TAKE_SUFFIXES)}, or a directory)")
            found.append(p)
        else:
            raise FileNotFoundError(f"{p}: no such file or directory")
    return sorted(dict.fromkeys(found))


def _rounded(values: dict) -> dict:
    return {k: (round(v, 5) if isinstance(v, float) else v) for k, v in values.items()}


def import_take(path: Path, out: Path, config: ImportConfig, mocap: MocapOptions = MocapOptions()) -> dict:
    """Import one take into library ``out``; returns its manifest entry.

    Raises:
        ValueError: the take is unusable (the message is the reason recorded in the manifest).
    """
    clip = load_source_clip(path, mocap)
    duration = clip.n_frames / clip.fps
    if duration < config.min_duration_s:
        raise ValueError(f"{duration:.2f} s long, shorter than {config.min_duration_s} s")
    content, style = labels(path.stem)
    entry = {"name": path.stem, "file": str(path), "format": clip.source["format"], "rig": clip.source["rig"],
             "units_m": clip.source["units_m"], "up": clip.source["up"], "mirrored": clip.source["mirrored"],
             "fps": round(clip.fps, 4), "frames": clip.n_frames, "duration_s": round(duration, 3),
             "content": content, "style": style, "split": split_of(path.stem, style), "models": {}}
    for model in MODELS:
        raw = retarget(clip, model)
        err = bone_direction_error(clip, raw)
        if err.mean() > config.max_bone_error_deg or np.percentile(err, 95) > config.max_bone_error_p95_deg:
            raise ValueError(f"retarget bone-direction error {err.mean():.1f}° mean, {np.percentile(err, 95):.1f}° "
                             f"95th percentile on {model} (limits {config.max_bone_error_deg}°, "
                             f"{config.max_bone_error_p95_deg}°): is the rig read right?")
        resampled = resample(raw, ENV_FPS)
        pinned = pin_contacts(resampled)
        pinned.save(take_path(out, path.stem, model))
        entry["models"][model] = {
            "frames": pinned.n_frames, "bone_error_deg_mean": round(float(err.mean()), 3),
            "bone_error_deg_p95": round(float(np.percentile(err, 95)), 3),
            "root_scale": round(float(raw.source["root_scale"]), 4),
            "quality_before": _rounded(motion_quality(resampled).as_dict()),
            "quality_after": _rounded(motion_quality(pinned).as_dict())}
    return entry


def _write_manifest(out: Path, manifest: dict) -> None:
    with atomic_write(out / MANIFEST) as tmp:
        tmp.write_text(json.dumps(manifest, indent=1))


def import_library(paths: Sequence[str | Path], out: str | Path, config: ImportConfig = ImportConfig(),
                   mocap: MocapOptions = MocapOptions(), progress: bool = True) -> dict:
    """Import every take of ``paths`` into library ``out`` (resumable); returns the manifest.

    The manifest is rewritten after every take, so an interrupted import loses at most the take
    in progress.
    """
    out = Path(out)
    takes = find_takes(paths)
    if not takes:
        raise ValueError(f"no {'/'.join(TAKE_SUFFIXES)} takes under {', '.join(map(str, paths))}")
    out.mkdir(parents=True, exist_ok=True)
    manifest_path = out / MANIFEST
    manifest = json.loads(manifest_path.read_text()) if manifest_path.exists() else {}
    if manifest.get("format") != LIBRARY_FORMAT:  # resume only an import of this format; redo an older one
        manifest = {}
    done = {t["name"]: t for t in manifest.get("takes", [])
            if all(take_path(out, t["name"], m).exists() for m in MODELS)}
    refused = {r["file"]: r for r in manifest.get("refused", [])}
    wall = manifest.get("wall_s", 0.0)
    names = [p.stem for p in takes]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise ValueError(f"takes share a file name: {', '.join(duplicates)} (a take is named by its file stem)")
    bar = tqdm(takes, desc="importing", unit="take", disable=not progress)
    for path in bar:
        if path.stem in done or str(path) in refused:
            continue
        bar.set_postfix_str(path.stem)
        start = time.perf_counter()
        try:
            done[path.stem] = import_take(path, out, config, mocap)
        except (ValueError, KeyError, FileNotFoundError) as err:
            refused[str(path)] = {"file": str(path), "reason": str(err).removeprefix(f"{path}: ")}
        wall += time.perf_counter() - start
        _write_manifest(out, _manifest(done, refused, config, wall))
    manifest = _manifest(done, refused, config, wall)
    _write_manifest(out, manifest)
    return manifest


def _manifest(done: dict, refused: dict, config: ImportConfig, wall: float) -> dict:
    return {"format": LIBRARY_FORMAT, "models": list(MODELS), "fps": ENV_FPS,
            "split_rule": {"test_styles": list(TEST_STYLES), "test_takes": list(TEST_TAKES), "val_style": VAL_STYLE},
            "config": asdict(config), "wall_s": round(wall, 2),
            "takes": sorted(done.values(), key=lambda t: t["name"]),
            "refused": sorted(refused.values(), key=lambda r: r["file"])}
