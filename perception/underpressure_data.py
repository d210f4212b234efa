"""Reading UnderPressure's preprocessed sequences (``S*/preprocessed/*.pth``; SPEC "Data").

Each file is a ``torch.save`` dict with ``angles (F, 23, 4)`` global joint orientations (w, x, y,
z), ``skeleton (1, 23, 3)`` the rest-pose joint positions, ``trajectory (F, 1, 3)`` the root
translation, ``forces (F, 2, 16)`` insole-cell vGRF in body weights and ``contacts (F, 2, 2)``
(toe/heel × left/right), at 100 Hz, z up, joints in :data:`perception.skeleton.JOINTS` order.
Joint positions follow UnderPressure's forward kinematics: a joint sits at its parent plus the
parent's global rotation applied to the rest-pose bone (``skeleton[j] - skeleton[parent]``); every
joint is then moved by the trajectory. The result is resampled to 60 Hz, the rate our networks
run at.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from perception.dataset import Sequence
from perception.skeleton import N_JOINTS, PARENTS, check_positions
from perception.weights import read_torch_file
from reference_motion import rotations as rot

SOURCE_FPS = 100.0
"""UnderPressure's frame rate."""

_FIELDS = {"angles": (N_JOINTS, 4), "skeleton": (N_JOINTS, 3), "trajectory": (1, 3), "forces": (2, 16),
           "contacts": (2, 2)}


def _field(item: dict, key: str, path: Path) -> np.ndarray:
    if key not in item:
        raise ValueError(f"{path}: field {key!r} missing (an UnderPressure sequence has {', '.join(_FIELDS)})")
    value = item[key]
    arr = value.detach().cpu().numpy() if isinstance(value, torch.Tensor) else np.asarray(value)
    if arr.ndim != 3 or arr.shape[1:] != _FIELDS[key]:
        raise ValueError(f"{path}: field {key!r} has shape {arr.shape}, expected (frames, "
                         f"{', '.join(map(str, _FIELDS[key]))})")
    if not np.isfinite(arr).all():
        raise ValueError(f"{path}: field {key!r} contains NaN or inf")
    return arr.astype(float)


def underpressure_positions(angles: np.ndarray, skeleton: np.ndarray, trajectory: np.ndarray) -> np.ndarray:
    """Joint positions ``(F, 23, 3)`` from global orientations ``(F, 23, 4)``, the rest skeleton
    ``(23, 3)`` and the root trajectory ``(F, 3)`` (UnderPressure's ``anim.FK``)."""
    angles = rot.normalize(angles)
    out = np.empty(angles.shape[:1] + (N_JOINTS, 3))
    out[:, 0] = skeleton[0]
    for j in range(1, N_JOINTS):
        p = PARENTS[j]
        out[:, j] = out[:, p] + rot.rotate(angles[:, p], np.broadcast_to(skeleton[j] - skeleton[p], (len(angles), 3)))
    return out + trajectory[:, None, :]


def _resample(values: np.ndarray, fps_in: float, fps_out: float) -> np.ndarray:
    """Linear resampling along axis 0 over the same duration."""
    t_in = np.arange(len(values)) / fps_in
    t_out = np.arange(int(np.floor(t_in[-1] * fps_out + 1e-6)) + 1) / fps_out
    flat = values.reshape(len(values), -1)
    out = np.stack([np.interp(t_out, t_in, flat[:, k]) for k in range(flat.shape[1])], axis=1)
    return out.reshape((len(t_out),) + values.shape[1:])


def load_underpressure(path: str | Path, fps: float = 60.0) -> Sequence:
    """One UnderPressure ``.pth`` sequence as a :class:`~perception.dataset.Sequence` at ``fps``:
    joint positions, cell forces, and contacts in CONTACT_CHANNELS order."""
    path = Path(path)
    item = read_torch_file(path, ".pth sequence", "UnderPressure's preprocessed S*/preprocessed/*.pth files")
    if not isinstance(item, dict):
        raise ValueError(f"{path}: expected a dict of tensors, got {type(item).__name__}")
    angles, forces, contacts = (_field(item, k, path) for k in ("angles", "forces", "contacts"))
    skeleton = _field(item, "skeleton", path)[0]
    trajectory = _field(item, "trajectory", path)[:, 0]
    n = len(angles)
    if n < 2:
        raise ValueError(f"{path}: the sequence has {n} frame(s); at least 2 are needed")
    for key, arr in (("trajectory", trajectory), ("forces", forces), ("contacts", contacts)):
        if len(arr) != n:
            raise ValueError(f"{path}: field {key!r} has {len(arr)} frames but 'angles' has {n}")
    positions = underpressure_positions(angles, skeleton, trajectory)
    # contacts (F, toe/heel, left/right) → (left_toe, right_toe, left_heel, right_heel)
    labels = contacts.reshape(n, 4) > 0.5
    if fps != SOURCE_FPS:
        positions, forces = _resample(positions, SOURCE_FPS, fps), _resample(forces, SOURCE_FPS, fps)
        idx = np.minimum(np.round(np.arange(len(positions)) * SOURCE_FPS / fps).astype(int), n - 1)
        labels = labels[idx]
    return Sequence(check_positions(positions, str(path)), forces.astype(np.float32), labels, float(fps),
                    f"underpressure:{path.stem}")
