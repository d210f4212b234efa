"""Seeded synthesis of IMU motion-capture artefacts (adapt §3.1, §4.3; SPEC "IMU artefacts").

IMU suits measure bone orientations only: the pose drifts and jitters, and global placement is
estimated afterwards, which makes feet skate and the body float or sink. :func:`corrupt` applies
each artefact kind with its own strength (0 = off, 1 = typical of a post-processed IMU take):

================  ===========================================  ===========================
kind              what it does                                 metric it raises
================  ===========================================  ===========================
``bias``          constant per-hinge orientation offset        (pose error)
``drift``         slow random walk per hinge                   (pose error)
``noise``         white noise per hinge and frame              jitter
``jitter``        bursts of 8–12 Hz limb oscillation           jitter
``skate``         random slow drift of the root trajectory     foot skate
``height``        constant + slowly varying vertical offset    floating / penetration
``adduction``     hips pulled towards the midline              self-penetration
================  ===========================================  ===========================
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np
from scipy.ndimage import gaussian_filter1d

from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion

ARTEFACT_KINDS = ("bias", "drift", "noise", "jitter", "skate", "height", "adduction")


@dataclass(frozen=True)
class ArtefactScales:
    """Magnitude of each artefact kind at strength 1 (SI units).

    Attributes:
        bias_rad: standard deviation of the constant per-hinge offset.
        drift_rad: standard deviation of the slow per-hinge drift.
        drift_timescale_s: smoothing timescale of the drift.
        noise_rad: standard deviation of per-frame white noise.
        jitter_rad: amplitude of limb oscillation bursts.
        jitter_burst_fraction: share of frames inside a jitter burst.
        skate_mps: standard deviation of the root's drift velocity (horizontal).
        skate_timescale_s: smoothing timescale of that velocity.
        height_m: magnitude of the constant vertical offset (sign random).
        height_wobble_m: amplitude of the slow vertical wobble added to it.
        adduction_rad: hip adduction added to each leg.
    """

    bias_rad: float = 0.05
    drift_rad: float = 0.08
    drift_timescale_s: float = 1.0
    noise_rad: float = 0.02
    jitter_rad: float = 0.06
    jitter_burst_fraction: float = 0.3
    skate_mps: float = 0.35
    skate_timescale_s: float = 0.5
    height_m: float = 0.06
    height_wobble_m: float = 0.02
    adduction_rad: float = 0.22


@dataclass(frozen=True)
class ArtefactRecipe:
    """Strength of each artefact kind (0 = off); see the module table."""

    bias: float = 0.0
    drift: float = 0.0
    noise: float = 0.0
    jitter: float = 0.0
    skate: float = 0.0
    height: float = 0.0
    adduction: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not (np.isfinite(value) and value >= 0):
                raise ValueError(f"artefact strength {f.name!r} must be a finite number >= 0, got {value}")

    @classmethod
    def imu(cls, strength: float = 1.0) -> "ArtefactRecipe":
        """Every artefact kind at the same strength: a typical faulty IMU take."""
        return cls(**{k: strength for k in ARTEFACT_KINDS})

    @classmethod
    def only(cls, kind: str, strength: float = 1.0) -> "ArtefactRecipe":
        """A single artefact kind; ``kind`` is one of :data:`ARTEFACT_KINDS`."""
        if kind not in ARTEFACT_KINDS:
            raise ValueError(f"unknown artefact kind {kind!r}; expected 'imu' or one of {', '.join(ARTEFACT_KINDS)}")
        return cls(**{kind: strength})

    @classmethod
    def named(cls, kind: str, strength: float = 1.0) -> "ArtefactRecipe":
        """``"imu"`` (every kind, :meth:`imu`) or a single kind (:meth:`only`) at ``strength``."""
        return cls.imu(strength) if kind == "imu" else cls.only(kind, strength)

    def scaled(self, factor: float) -> "ArtefactRecipe":
        """Every strength multiplied by ``factor``."""
        return ArtefactRecipe(**{k: v * factor for k, v in self.as_dict().items()})

    def as_dict(self) -> dict:
        return asdict(self)


def _smooth_noise(rng: np.random.Generator, shape: tuple[int, ...], sigma_frames: float) -> np.ndarray:
    """Gaussian-smoothed white noise along axis 0 with unit standard deviation *in expectation*.

    Scaled by the filter's known gain (std of unit white noise through a Gaussian of ``σ`` frames
    is ``1/sqrt(2·sqrt(π)·σ)``), not by the sample std, which on a clip shorter than the smoothing
    timescale would be tiny and blow the signal up.
    """
    sigma = max(sigma_frames, 1e-3)
    smooth = gaussian_filter1d(rng.standard_normal(shape), sigma=sigma, axis=0, mode="reflect")
    return smooth * np.sqrt(2.0 * np.sqrt(np.pi) * sigma) if sigma >= 0.5 else smooth


def _limb_hinges(motion: Motion) -> np.ndarray:
    """Column indices (into ``qpos``) of the arm and leg hinges."""
    hm = load_model(motion.model)
    limbs = ("upper_arm", "forearm", "thigh", "shin", "foot")
    return np.array([hm.qpos_index(n) for n in hm.hinge_names if any(f"_{l}_" in n for l in limbs)])


def corrupt(motion: Motion, recipe: ArtefactRecipe, seed: int, scales: ArtefactScales = ArtefactScales()) -> Motion:
    """``motion`` with IMU artefacts; the same ``seed`` and recipe always give the same output.

    Every kind draws from its own random stream, so switching one kind on or off leaves the
    others' numbers unchanged.
    """
    T, fps = motion.n_frames, motion.fps
    qpos = motion.qpos.copy()
    n_hinge = qpos.shape[1] - 7
    streams = dict(zip(ARTEFACT_KINDS, np.random.SeedSequence(seed).spawn(len(ARTEFACT_KINDS))))
    rng = {k: np.random.default_rng(s) for k, s in streams.items()}

    if recipe.bias:
        qpos[:, 7:] += recipe.bias * scales.bias_rad * rng["bias"].standard_normal(n_hinge)
    if recipe.drift:
        walk = _smooth_noise(rng["drift"], (T, n_hinge), scales.drift_timescale_s * fps)
        qpos[:, 7:] += recipe.drift * scales.drift_rad * walk
    if recipe.noise:
        qpos[:, 7:] += recipe.noise * scales.noise_rad * rng["noise"].standard_normal((T, n_hinge))
    if recipe.jitter:
        cols = _limb_hinges(motion)
        r = rng["jitter"]
        freq = r.uniform(8.0, 12.0, len(cols))
        phase = r.uniform(0, 2 * np.pi, len(cols))
        t = np.arange(T)[:, None] / fps
        gate = (_smooth_noise(r, (T, 1), 0.1 * fps) > np.quantile(r.standard_normal(10000),
                                                                    1 - scales.jitter_burst_fraction))
        qpos[:, cols] += recipe.jitter * scales.jitter_rad * gate * np.sin(2 * np.pi * freq * t + phase)
    if recipe.skate:
        vel = _smooth_noise(rng["skate"], (T, 2), scales.skate_timescale_s * fps) * scales.skate_mps
        qpos[:, :2] += recipe.skate * np.cumsum(vel, axis=0) / fps
    if recipe.height:
        r = rng["height"]
        offset = scales.height_m * r.choice([-1.0, 1.0])
        wobble = scales.height_wobble_m * _smooth_noise(r, (T,), 1.0 * fps)
        qpos[:, 2] += recipe.height * (offset + wobble)
    if recipe.adduction:
        hm = load_model(motion.model)
        # Hip x axis: positive moves the left leg outwards (+y) and the right leg inwards.
        qpos[:, hm.qpos_index("l_thigh_x")] -= recipe.adduction * scales.adduction_rad
        qpos[:, hm.qpos_index("r_thigh_x")] += recipe.adduction * scales.adduction_rad

    source = dict(motion.source, artefacts=recipe.as_dict(), artefact_seed=int(seed))
    return motion.with_qpos(qpos, source=source)
