"""The :class:`Motion` type: one clip for one MJCF humanoid, saved and loaded as ``.npz``."""

from __future__ import annotations

import json
import zipfile
import zlib
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from reference_motion import rotations as rot
from reference_motion.atomic import atomic_write

MODEL_NQ = {"humanoid_1seg": 50, "humanoid_2seg": 52}
"""qpos width of each supported model (7 free-joint values + one per hinge)."""

NPZ_FORMAT = "physmimic.motion/1"


class MotionError(ValueError):
    """A motion file or array is malformed; the message names the file or field."""


def read_npz(path: str | Path, what: str) -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` file ``path`` (a ``what`` file, e.g. ``"motion"``), without
    unpickling; :class:`MotionError` naming the file when it is missing, not a zip archive (a
    truncated download, a text file named ``.npz``) or damaged inside."""
    path = Path(path)
    if not path.is_file():
        raise MotionError(f"{path}: no such {what} file")
    if not zipfile.is_zipfile(path):
        raise MotionError(f"{path}: not a readable .npz {what} file: not a valid .npz (zip) archive; "
                          "truncated, or another kind of file named .npz")
    try:
        with np.load(path, allow_pickle=False) as npz:
            return {k: npz[k] for k in npz.files}
    except (zipfile.BadZipFile, zlib.error, ValueError, OSError, EOFError) as err:
        raise MotionError(f"{path}: not a readable .npz {what} file: damaged ({err})") from err


def read_text(path: Path, kind: str) -> str:
    """The text of the motion file ``path``, a ``kind`` (e.g. ``"BVH file"``): ``FileNotFoundError``
    "no such BVH file" when it is missing, :class:`MotionError` "not a BVH file (binary data)" when it
    is not text."""
    try:
        return path.read_text()
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such {kind}") from None
    except UnicodeDecodeError:
        article = "an" if kind[0] in "AEIOU" else "a"
        raise MotionError(f"{path}: not {article} {kind} (binary data)") from None


@dataclass(frozen=True)
class Motion:
    """One clip for one humanoid model, at a uniform frame rate.

    Attributes:
        name: clip name, e.g. ``"deepmimic:walk"``.
        fps: frames per second (Hz).
        qpos: ``(T, nq)`` generalised positions; layout in :mod:`reference_motion.humanoid.model`
            (pelvis position m, pelvis quaternion w,x,y,z, hinge angles rad), world z up.
        model: ``"humanoid_1seg"`` or ``"humanoid_2seg"``.
        loop: whether the clip is cyclic (its last frame repeats the first, moved by the cycle's
            root displacement), as DeepMimic's ``"wrap"`` clips.
        source: free-form metadata (loader, file, original fps, ...), JSON-serialisable.
    """

    name: str
    fps: float
    qpos: np.ndarray
    model: str
    loop: bool = False
    source: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        where = f"motion {self.name!r}"
        if self.model not in MODEL_NQ:
            raise MotionError(f"{where}: unknown model {self.model!r}; expected one of {sorted(MODEL_NQ)}")
        qpos = np.asarray(self.qpos, dtype=float)
        if qpos.ndim != 2 or qpos.shape[1] != MODEL_NQ[self.model]:
            raise MotionError(f"{where}: qpos must have shape (T, {MODEL_NQ[self.model]}) for {self.model}, "
                              f"got {qpos.shape}")
        if qpos.shape[0] < 2:
            raise MotionError(f"{where}: needs at least 2 frames, got {qpos.shape[0]}")
        if not np.all(np.isfinite(qpos)):
            bad = np.argwhere(~np.isfinite(qpos))[0]
            raise MotionError(f"{where}: qpos has NaN/inf (first at frame {bad[0]}, column {bad[1]})")
        norms = np.linalg.norm(qpos[:, 3:7], axis=1)
        if np.any(np.abs(norms - 1.0) > 1e-3):
            raise MotionError(f"{where}: root quaternions (qpos[:, 3:7]) must have unit norm; "
                              f"frame {int(np.argmax(np.abs(norms - 1)))} has norm {norms.max():.4f}")
        if not (np.isfinite(self.fps) and self.fps > 0):
            raise MotionError(f"{where}: fps must be positive, got {self.fps}")
        object.__setattr__(self, "qpos", qpos)

    # ----------------------------------------------------------- properties
    @property
    def n_frames(self) -> int:
        return int(self.qpos.shape[0])

    @property
    def duration(self) -> float:
        """Seconds from the first to the last frame."""
        return (self.n_frames - 1) / self.fps

    @property
    def root_pos(self) -> np.ndarray:
        """``(T, 3)`` pelvis position (m, world)."""
        return self.qpos[:, :3]

    @property
    def root_quat(self) -> np.ndarray:
        """``(T, 4)`` pelvis orientation (w, x, y, z, world)."""
        return self.qpos[:, 3:7]

    @property
    def hinges(self) -> np.ndarray:
        """``(T, nq - 7)`` hinge angles (rad)."""
        return self.qpos[:, 7:]

    @property
    def qvel(self) -> np.ndarray:
        """``(T, nq - 1)`` generalised velocities by central differences (one-sided at the ends):
        pelvis linear velocity (world, m/s), pelvis angular velocity (pelvis frame, rad/s), hinge
        rates (rad/s) — MuJoCo's qvel layout."""
        dt = 1.0 / self.fps
        lin = np.gradient(self.root_pos, dt, axis=0)
        hinge = np.gradient(self.hinges, dt, axis=0)
        q = self.root_quat
        prev = np.concatenate([q[:1], q[:-1]])
        nxt = np.concatenate([q[1:], q[-1:]])
        span = np.full((self.n_frames, 1), 2.0 * dt)
        span[0] = span[-1] = dt
        ang = rot.log_map(rot.multiply(rot.conjugate(prev), nxt)) / span
        return np.concatenate([lin, ang, hinge], axis=1)

    def with_qpos(self, qpos: np.ndarray, **changes) -> "Motion":
        """Copy with new ``qpos`` (and any other field changes)."""
        return replace(self, qpos=qpos, **changes)

    def held(self, frames: int) -> "Motion":
        """Copy, not cyclic, whose last frame is held ``frames`` frames longer: an environment
        whose episodes are at most ``frames`` frames long can then start one at any frame of this
        clip (``agents.clean`` holds two more, a margin for its control steps)."""
        if frames < 0:
            raise ValueError(f"{self.name}: frames to hold must be >= 0, got {frames}")
        return self.with_qpos(np.concatenate([self.qpos, np.repeat(self.qpos[-1:], frames, axis=0)]), loop=False)

    # ------------------------------------------------------------------ I/O
    def save(self, path: str | Path) -> Path:
        """Write ``.npz`` (qpos, fps, model, name, loop, JSON metadata), atomically; ``.npz`` is
        appended to ``path`` when missing, as numpy does. Returns the path written."""
        path = Path(path) if str(path).endswith(".npz") else Path(f"{path}.npz")
        with atomic_write(path) as tmp:
            np.savez_compressed(tmp, format=NPZ_FORMAT, qpos=self.qpos, fps=self.fps, model=self.model,
                                name=self.name, loop=self.loop, source=json.dumps(self.source))
        return path

    @classmethod
    def load(cls, path: str | Path, model: str | None = None) -> "Motion":
        """Read a Motion ``.npz``. If ``model`` is given, the file must have been saved for it."""
        path = Path(path)
        data = read_npz(path, "motion")
        missing = [k for k in ("qpos", "fps", "model", "name") if k not in data]
        if missing:
            raise MotionError(f"{path}: missing field(s) {missing}; expected a file written by Motion.save")
        saved_model = str(data["model"])
        if model is not None and saved_model != model:
            raise MotionError(f"{path}: motion was saved for model {saved_model} "
                              f"(nq={data['qpos'].shape[-1]}) but {model} was requested; retarget the "
                              f"source clip for {model} instead")
        try:
            return cls(name=str(data["name"]), fps=float(data["fps"]), qpos=data["qpos"], model=saved_model,
                       loop=bool(data.get("loop", False)), source=json.loads(str(data.get("source", "{}"))))
        except (ValueError, TypeError) as err:  # MotionError, or a field of the wrong kind
            raise MotionError(f"{path}: {err}") from err
