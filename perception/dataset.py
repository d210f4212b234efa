"""Physics-labelled motion datasets: the shard format, and reading it.

A dataset (made by :mod:`agents.physics_dataset`, ``python agents/make_dataset.py``: trained mimic
policies re-perform the clip library, the simulator acting as a pressure insole) holds, per 60 Hz
frame of the simulated body:

=================  ==================  =====================================================
key                shape, dtype        meaning
=================  ==================  =====================================================
``positions``      (N, 23, 3) float32  UnderPressure's joints on the simulated body (m, z up)
``forces``         (N, 2, 16) float32  vGRF per insole cell, left then right (body weights),
                                       as an insole reads it
                                       (:func:`agents.physics_dataset.insole`)
``forces_raw``     (N, 2, 16) float32  the simulator's cell vGRF averaged over each frame's
                                       physics substeps
``contacts``       (N, 4) bool         physics heel/toe contact (≥ 5% BW on the region in
                                       ``forces_raw``), (left_toe, right_toe, left_heel,
                                       right_heel)
``qpos``           (N, nq) float32     the simulated pose
``episode``        (N,) int32          episode index within the shard
``meta``           JSON string         clip, split, variant recipe, policy, episodes
=================  ==================  =====================================================

One shard per (clip, variant) in ``DIR/{train,val,test}/``, split by source clip.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from perception.skeleton import check_positions
from reference_motion.motion import MODEL_NQ

SPLITS = ("train", "val", "test")


@dataclass
class Sequence:
    """One recorded episode: ``positions (T, 23, 3)`` m, ``forces (T, 2, 16)`` BW, physics
    ``contacts (T, 4)`` (CONTACT_CHANNELS order), ``fps``, the source ``clip``, and the simulated
    character's ``qpos (T, nq)`` on humanoid ``model`` (``None`` for data not from our simulator)."""

    positions: np.ndarray
    forces: np.ndarray
    contacts: np.ndarray
    fps: float
    clip: str
    qpos: np.ndarray | None = None
    model: str | None = None


def load_split(root: Path, split: str) -> list[Sequence]:
    """Every episode of ``split`` in the dataset at ``root``, as :class:`Sequence` objects."""
    if split not in SPLITS:
        raise ValueError(f"unknown split {split!r}; expected one of {', '.join(SPLITS)}")
    folder = Path(root) / split
    shards = sorted(folder.glob("*.npz"))
    if not shards:
        raise FileNotFoundError(f"{folder}: no shards (make one with `python agents/make_dataset.py --out {root}`)")
    out = []
    for shard in shards:
        with np.load(shard) as z:
            for key in ("positions", "forces", "contacts", "qpos", "episode", "meta"):
                if key not in z.files:
                    raise ValueError(f"{shard}: not a physmimic dataset shard (missing field {key!r})")
            meta = json.loads(str(z["meta"]))
            if not len(z["episode"]):
                continue
            positions = check_positions(z["positions"], str(shard))
            qpos = z["qpos"]
            model = next((m for m, nq in MODEL_NQ.items() if qpos.shape[1] == nq), None)
            if model is None:
                raise ValueError(f"{shard}: field 'qpos' has {qpos.shape[1]} columns; expected one of "
                                 + ", ".join(f"{nq} ({m})" for m, nq in MODEL_NQ.items()))
            for e in np.unique(z["episode"]):
                rows = z["episode"] == e
                out.append(Sequence(positions[rows], z["forces"][rows], z["contacts"][rows], meta["fps"], meta["clip"],
                                    qpos[rows], model))
    return out


def summarize(root: Path) -> dict:
    """Frames, episodes and clips per split, and how episodes ended."""
    out = {}
    for split in SPLITS:
        frames = episodes = 0
        clips, endings = set(), {}
        for shard in sorted((Path(root) / split).glob("*.npz")):
            with np.load(shard) as z:
                meta = json.loads(str(z["meta"]))
                frames += len(z["episode"])
                episodes += len(np.unique(z["episode"]))
            clips.add(meta["clip"])
            for rec in meta["episodes"]:
                endings[rec["ended_by"]] = endings.get(rec["ended_by"], 0) + 1
        out[split] = {"frames": frames, "episodes": episodes, "clips": sorted(clips), "endings": endings}
    return out
