"""Seeded synthesis of IMU motion-capture artefacts (adapt §3.1, §4.3; SPEC "IMU artefacts").

IMU suits measure bone orientations only (adapt §3.1: Rokoko's Smartsuit Pro II, 17 sensors):
joint angles carry calibration offsets, drift and noise, the suit's heading drifts, and global
placement is estimated afterwards from the orientations, which makes the root drift away from
where the actor went, the planted feet slide and the body float or sink. :func:`corrupt` applies
each artefact kind with its own strength: 0 = off, **1 = a poor but real take** (every kind at
the bad end of what published IMU-suit figures show, :class:`ArtefactScales`), up to 3 and
beyond = a stress test (everything scales linearly with the strength).

==============  ================================================  ===========================
kind            what it does                                      metric it raises
==============  ================================================  ===========================
``bias``        constant per-hinge orientation offset             (pose error)
``drift``       slow wandering offset per hinge                   (pose error)
``noise``       per-frame hinge error, larger at fast motion      jitter, pose error
``jitter``      bursts of 8–12 Hz limb oscillation                jitter
``adduction``   hips pulled towards the midline                   self-penetration
``heading``     yaw of the whole take growing linearly in time    (global path error)
``root_drift``  root displaced by a fraction of the distance      (global path error)
                travelled, in a direction fixed per take
``skate``       stance skate: the root, and so the planted        foot skate
                foot, slides back and forth, zero-mean over each
                step
``height``      constant + slowly varying vertical offset         floating / penetration
==============  ================================================  ===========================

``root_drift`` and ``skate`` are separate on purpose: root drift is a slow global error that
accumulates with distance (a cleaner cannot and should not follow it exactly), stance skate is a
local slide that a cleaner removes by planting the foot. Orientation errors act on the hinge
angles (``qpos[7:]``), the other kinds on the root (``qpos[:7]``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass, fields, replace

import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.special import ndtri

from reference_motion import rotations as rot
from reference_motion.humanoid.model import load_model
from reference_motion.leg_gap import HIP_ABDUCTION
from reference_motion.motion import Motion
from reference_motion.quality import motion_contacts

ARTEFACT_KINDS = ("bias", "drift", "noise", "jitter", "adduction", "heading", "root_drift", "skate", "height")
HINGE_KINDS = ("bias", "drift", "noise", "jitter", "adduction")
"""The kinds that act on the hinge angles (``qpos[7:]``); the others act on the root (``qpos[:7]``)."""


@dataclass(frozen=True)
class ArtefactScales:
    """Magnitude of each artefact kind at strength 1 (SI units; angles in rad), with its source.

    Strength 1 sits at the poor end of published IMU-suit figures. Where the figure is the
    typical range reported by validation studies of commercial suits (Xsens MVN, Rokoko and the
    like, against optical mocap), it says "typical published figure"; we did not take the
    numbers from one paper we could quote exactly. The ADAPT paper (adapt §3.1) names the
    artefacts of its post-processed Rokoko takes (self-collisions, foot skating, floating, jittering
    limbs) but gives no magnitudes. The errors of the hinges are per hinge: a ball joint's
    three hinges together are off by about √3 times as much in orientation.

    Attributes:
        bias_rad: std of the constant per-hinge offset: 2°. Typical published figure: joint
            angles of IMU suits differ from optical ones by a few degrees RMS, most of it a
            constant offset from sensor-to-segment calibration.
        drift_rad: std of the slow per-hinge drift: 2°. Typical published figure: the remaining
            part of that few-degree RMS error varies slowly through a take (fusion filter and
            soft-tissue drift); bias + drift + noise give ≈ 3° RMS per hinge on a walk at
            strength 1 (measured in ``tests/test_artefacts.py``).
        drift_timescale_s: smoothing timescale of the drift: 2 s. Our choice: longer than a
            stride, so it reads as a wandering offset rather than as noise.
        noise_rad: std of the per-frame error at rest: 0.3°. Typical published figure: static
            orientation noise of IMU fusion filters is a few tenths of a degree.
        noise_rad_per_rad_s: growth of that std with the hinge's angular speed: 0.5° per rad/s
            (a knee swinging at 6 rad/s is off by ≈ 3°). Typical published figure: IMU joint
            angle errors grow with movement speed (larger RMS errors in running and fast tasks
            than in walking); the linear model and its gain are ours.
        noise_timescale_s: smoothing timescale of the per-frame error: 0.1 s. Our choice: the
            error of an orientation fusion filter is low-frequency (integrated gyroscopes, slow
            corrections) and the suit's software low-passes its output; white noise at 60 Hz
            would make planted feet buzz at metres per second (at 25 ms they slide 0.5 m/s, at
            0.1 s 0.2 m/s on a walk at strength 1).
        jitter_rad: amplitude of the limb oscillation bursts: 1°. ADAPT §3.1 reports jittering
            limbs in post-processed Rokoko takes; we found no published amplitude to cite. 1°
            stays inside the few-degree error budget and still raises the jerk several-fold.
        jitter_burst_fraction: share of frames inside a jitter burst: 0.2 (our choice: bursts,
            e.g. near magnetic disturbances, not the whole take).
        adduction_rad: hip adduction added to each leg: 8° (0.14 rad). Typical published
            figure: ab/adduction is the least accurate hip angle of IMU suits, with offsets up
            to about 10°; ADAPT §3.1 and Figure 1 show the resulting leg–leg self-collision.
        heading_deg_per_min: heading (yaw) drift rate of the whole take: 2°/min. Typical
            published figure: 0.2–2°/min for magnetometer-aided IMU suits; strength 1 is the
            poor end.
        root_drift_fraction: root displacement error per metre travelled: 2 %. Typical published
            figure: 0.3–2 % of the distance travelled for IMU-suit position estimates; strength
            1 is the poor end.
        skate_mps: peak slide speed of a planted foot within a step: 0.3 m/s (mean speed over the
            step 2/π of it, 0.19 m/s; RMS 0.21 m/s). Typical published figure: planted-foot
            slide of 0.05–0.3 m/s in post-processed IMU takes (adapt §3.1 names foot skating);
            strength 1 is the poor end.
        skate_step_min_s: touchdowns closer than this (contact chatter) start no new step: 0.2 s
            (our choice).
        skate_step_max_s: a longer interval between touchdowns (standing, a clip without steps)
            is split into slides of at most this length: 0.8 s (our choice: a slow step).
        height_m: magnitude of the constant vertical offset (sign random): 4 cm. Typical
            published figure: a few centimetres of floating or floor penetration.
        height_wobble_m: std of the slow vertical wobble added to it: 1 cm (our choice, within
            the same few centimetres).
        height_timescale_s: smoothing timescale of the wobble: 2 s (our choice).
    """

    bias_rad: float = float(np.radians(2.0))
    drift_rad: float = float(np.radians(2.0))
    drift_timescale_s: float = 2.0
    noise_rad: float = float(np.radians(0.3))
    noise_rad_per_rad_s: float = float(np.radians(0.5))
    noise_timescale_s: float = 0.1
    jitter_rad: float = float(np.radians(1.0))
    jitter_burst_fraction: float = 0.2
    adduction_rad: float = 0.14
    heading_deg_per_min: float = 2.0
    root_drift_fraction: float = 0.02
    skate_mps: float = 0.3
    skate_step_min_s: float = 0.2
    skate_step_max_s: float = 0.8
    height_m: float = 0.04
    height_wobble_m: float = 0.01
    height_timescale_s: float = 2.0


@dataclass(frozen=True)
class ArtefactRecipe:
    """Strength of each artefact kind (0 = off, 1 = a poor but real take); see the module table."""

    bias: float = 0.0
    drift: float = 0.0
    noise: float = 0.0
    jitter: float = 0.0
    adduction: float = 0.0
    heading: float = 0.0
    root_drift: float = 0.0
    skate: float = 0.0
    height: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not (np.isfinite(value) and value >= 0):
                raise ValueError(f"artefact strength {f.name!r} must be a finite number >= 0, got {value}")

    @classmethod
    def imu(cls, strength: float = 1.0) -> "ArtefactRecipe":
        """Every artefact kind at the same strength: 1 = a poor but real IMU take."""
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

    def without(self, kinds: Sequence[str]) -> "ArtefactRecipe":
        """This recipe with the artefact ``kinds`` (of :data:`ARTEFACT_KINDS`) switched off: what the
        others cost together (:func:`corrupt` draws each kind from its own stream, so the others'
        numbers stay the same)."""
        if isinstance(kinds, str):
            raise TypeError(f"without: give a sequence of kinds, e.g. [{kinds!r}], not the string {kinds!r}")
        unknown = sorted(set(kinds) - set(ARTEFACT_KINDS))
        if unknown:
            raise ValueError(f"unknown artefact kind(s) {', '.join(map(repr, unknown))}; expected some of "
                             f"{', '.join(ARTEFACT_KINDS)}")
        return replace(self, **{k: 0.0 for k in kinds})

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


def hinge_speed(motion: Motion) -> np.ndarray:
    """Angular speed ``(T, n_hinge)`` (rad/s) of each hinge, lightly smoothed (σ 2 frames)."""
    if motion.n_frames < 2:
        return np.zeros_like(motion.hinges)
    speed = np.abs(np.gradient(motion.hinges, axis=0)) * motion.fps
    return gaussian_filter1d(speed, sigma=2.0, axis=0, mode="nearest")


def step_boundaries(motion: Motion, min_step_s: float = 0.2, max_step_s: float = 0.8) -> np.ndarray:
    """Frames that start a step: 0, every foot touchdown of ``motion``, and ``T − 1``.

    Touchdowns are the frames where a foot (heel or toe, the contacts of
    :func:`reference_motion.quality.motion_quality`) lands; one closer than ``min_step_s`` to the
    previous boundary is skipped (contact chatter), and an interval longer than ``max_step_s``
    (standing, flight, a clip without steps) is split into equal parts no longer than it.
    """
    T, fps = motion.n_frames, motion.fps
    if T < 2:
        return np.array([0, max(T - 1, 0)])
    contacts = motion_contacts(motion)  # LT, RT, LH, RH
    feet = np.stack([contacts[:, 0] | contacts[:, 2], contacts[:, 1] | contacts[:, 3]], axis=1)
    landings = np.flatnonzero((feet[1:] & ~feet[:-1]).any(axis=1)) + 1
    bounds = [0]
    for frame in landings:
        if frame - bounds[-1] >= min_step_s * fps and (T - 1) - frame >= min_step_s * fps:
            bounds.append(int(frame))
    bounds.append(T - 1)
    out = [0]
    longest = max(max_step_s * fps, 2.0)
    for a, b in zip(bounds[:-1], bounds[1:]):
        parts = int(np.ceil((b - a) / longest))
        out += [int(round(a + (b - a) * k / parts)) for k in range(1, parts + 1)]
    return np.unique(out)


def _stance_skate(rng: np.random.Generator, bounds: np.ndarray, T: int, fps: float, peak_mps: float) -> np.ndarray:
    """Horizontal root offset ``(T, 2)``: over each step ``[a, b]`` a slide out along a random
    direction and back, ``D·(1 − cos 2πτ)/2`` with ``D = peak·duration/π`` (so the slide speed
    peaks at ``peak_mps`` mid-step), zero at every step boundary: zero-mean velocity per step."""
    offset = np.zeros((T, 2))
    for a, b in zip(bounds[:-1], bounds[1:]):
        angle = rng.uniform(0.0, 2.0 * np.pi)
        tau = (np.arange(a, b + 1) - a) / (b - a)
        reach = peak_mps * ((b - a) / fps) / np.pi
        offset[a:b + 1] = (reach * 0.5 * (1.0 - np.cos(2.0 * np.pi * tau)))[:, None] * [np.cos(angle), np.sin(angle)]
    return offset


def _yaw_quat(angle: np.ndarray) -> np.ndarray:
    half = 0.5 * np.asarray(angle)
    return np.stack([np.cos(half), np.zeros_like(half), np.zeros_like(half), np.sin(half)], axis=-1)


def _rotate_xy(v: np.ndarray, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=-1)


def corrupt(motion: Motion, recipe: ArtefactRecipe, seed: int, scales: ArtefactScales = ArtefactScales()) -> Motion:
    """``motion`` with IMU artefacts; the same ``seed`` and recipe always give the same output.

    Every kind draws from its own random stream, so switching one kind on or off leaves the
    others' numbers unchanged. Everything is computed from the clean motion (speeds, steps,
    distance travelled), then applied: hinge errors, then heading, root drift, skate and height.
    """
    T, fps = motion.n_frames, motion.fps
    qpos = motion.qpos.copy()
    n_hinge = qpos.shape[1] - 7
    streams = dict(zip(ARTEFACT_KINDS, np.random.SeedSequence(seed).spawn(len(ARTEFACT_KINDS))))
    rng = {k: np.random.default_rng(s) for k, s in streams.items()}
    t = np.arange(T) / fps

    # ---- orientation errors of the hinges
    if recipe.bias:
        qpos[:, 7:] += recipe.bias * scales.bias_rad * rng["bias"].standard_normal(n_hinge)
    if recipe.drift:
        walk = _smooth_noise(rng["drift"], (T, n_hinge), scales.drift_timescale_s * fps)
        qpos[:, 7:] += recipe.drift * scales.drift_rad * walk
    if recipe.noise:
        std = scales.noise_rad + scales.noise_rad_per_rad_s * hinge_speed(motion)
        qpos[:, 7:] += recipe.noise * std * _smooth_noise(rng["noise"], (T, n_hinge), scales.noise_timescale_s * fps)
    if recipe.jitter:
        cols = _limb_hinges(motion)
        r = rng["jitter"]
        freq = r.uniform(8.0, 12.0, len(cols))
        phase = r.uniform(0, 2 * np.pi, len(cols))
        gate = _smooth_noise(r, (T, 1), 0.1 * fps) > ndtri(1.0 - scales.jitter_burst_fraction)
        qpos[:, cols] += recipe.jitter * scales.jitter_rad * gate * np.sin(2 * np.pi * freq * t[:, None] + phase)
    if recipe.adduction:
        hm = load_model(motion.model)
        for joint, abduction_sign in HIP_ABDUCTION:  # both legs turned toward the midline
            qpos[:, hm.qpos_index(joint)] -= abduction_sign * recipe.adduction * scales.adduction_rad

    # ---- global placement of the root
    if recipe.heading:
        # The take's heading turns at a constant rate: each frame's root orientation and each
        # frame-to-frame root step are yawed by θ(t), so the path bends as the actor's would
        # when integrated with a drifting heading.
        sign = rng["heading"].choice([-1.0, 1.0])
        theta = sign * recipe.heading * np.radians(scales.heading_deg_per_min) / 60.0 * t
        qpos[:, 3:7] = rot.normalize(rot.multiply(_yaw_quat(theta), qpos[:, 3:7]))
        if T > 1:
            steps = _rotate_xy(np.diff(motion.qpos[:, :2], axis=0), 0.5 * (theta[1:] + theta[:-1]))
            qpos[1:, :2] = motion.qpos[0, :2] + np.cumsum(steps, axis=0)
    if recipe.root_drift and T > 1:
        # Distance travelled along the root's path with the within-stride sway smoothed out.
        path = gaussian_filter1d(motion.qpos[:, :2], sigma=0.5 * fps, axis=0, mode="nearest")
        travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
        angle = rng["root_drift"].uniform(0.0, 2.0 * np.pi)
        qpos[:, :2] += recipe.root_drift * scales.root_drift_fraction * travelled[:, None] * [np.cos(angle), np.sin(angle)]
    if recipe.skate and T > 1:
        bounds = step_boundaries(motion, scales.skate_step_min_s, scales.skate_step_max_s)
        qpos[:, :2] += _stance_skate(rng["skate"], bounds, T, fps, recipe.skate * scales.skate_mps)
    if recipe.height:
        r = rng["height"]
        offset = scales.height_m * r.choice([-1.0, 1.0])
        wobble = scales.height_wobble_m * _smooth_noise(r, (T,), scales.height_timescale_s * fps)
        qpos[:, 2] += recipe.height * (offset + wobble)

    source = dict(motion.source, artefacts=recipe.as_dict(), artefact_seed=int(seed))
    return motion.with_qpos(qpos, source=source)
