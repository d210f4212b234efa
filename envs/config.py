"""Configuration of the mimic environments: every constant of ADAPT §3.2 in one place.

:class:`MimicConfig` holds the task's timing, action, reward and termination constants (adapt
Tables 2 and 3); :class:`ArtefactMix` says which episodes get an IMU-corrupted reference (ADAPT's
clean/faulty training mix). The three registered ids differ only in ``obs_mode`` and
``action_mode``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from reference_motion.artefacts import ArtefactRecipe

FOOT_MODELS = {"one": "humanoid_1seg", "two": "humanoid_2seg"}
"""``foot`` argument → humanoid model."""

OBS_MODES = ("adapt", "drecon")
"""``adapt``: adapt Table 1 over all bodies (273-D on ``humanoid_1seg``); ``drecon``: the same
terms over DReCon's key bodies only (:data:`DRECON_BODIES`), the reduced-state ablation."""

ACTION_MODES = ("key", "full")
"""``key``: offsets on the 8 key joints (20 hinges, adapt eq. 4); ``full``: every actuated hinge."""

KEY_JOINT_BODIES = ("r_upper_arm", "r_thigh", "r_shin", "r_foot", "l_upper_arm", "l_thigh", "l_shin", "l_foot")
"""Bodies whose hinges the policy drives in ``key`` action mode: shoulders, hips, knees, ankles (adapt eq. 4)."""

DRECON_BODIES = ("pelvis", "head", "l_hand", "r_hand", "l_foot", "r_foot")
"""Bodies observed in ``drecon`` mode: the root and the end effectors, as DReCon's reduced state."""

SPINAL_BODIES = ("pelvis", "spine_lower", "spine_mid", "chest", "neck", "head")
"""Bodies whose ground contacts count towards the fall termination (adapt §3.2.3)."""


@dataclass(frozen=True)
class MimicConfig:
    """Constants of a mimic task (defaults: ADAPT).

    Attributes:
        frame_rate_hz: rate of simulation frames = reference frames (60 Hz; the physics substeps
            inside a frame follow from the model's 1/120 s timestep).
        control_rate_hz: policy rate (30 Hz: one action per two frames).
        episode_frames: longest episode, in reference frames (300 = 5 s).
        action_smoothing: β of ``a_t = β·a_raw + (1 − β)·a_{t−1}`` (adapt eq. 5).
        action_limit_rad: the action space is ``[−limit, limit]`` rad per driven hinge.
        alpha_local, alpha_p, alpha_v: reward scales of adapt Table 2.
        discount_threshold: the episode ends when e_discount falls below this (ε_discount).
        fall_contacts: the episode ends when this many spinal bodies touch the ground at once.
        cube_size_m: edge of the cube whose face centres r_p and r_v compare (1 m, adapt eq. 7).
        init_clearance_m: at reference state initialisation, a reference pose that reaches below
            the floor is lifted until its lowest point is this high.
        max_joint_speed: a hinge or root speed above this (rad/s or m/s) counts as the simulation
            going unstable, as does any NaN/inf.
        min_clip_frames: shortest clip accepted (frames after the first; 30 = 0.5 s): clips shorter
            than an episode are played to their end.
        track_cache_size: reference tracks (clip or corrupted variant) kept in memory per env,
            least recently used dropped first (each is ~10 kB per frame; rebuilt in ~20 ms).
    """

    frame_rate_hz: float = 60.0
    control_rate_hz: float = 30.0
    episode_frames: int = 300
    action_smoothing: float = 0.2
    action_limit_rad: float = 1.0
    alpha_local: float = 2.5
    alpha_p: float = 1.0
    alpha_v: float = 0.1
    discount_threshold: float = 0.025
    fall_contacts: int = 3
    cube_size_m: float = 1.0
    init_clearance_m: float = 0.002
    max_joint_speed: float = 200.0
    min_clip_frames: int = 30
    track_cache_size: int = 128

    def __post_init__(self) -> None:
        ratio = self.frame_rate_hz / self.control_rate_hz
        if ratio < 1 or abs(ratio - round(ratio)) > 1e-9:
            raise ValueError(f"frame_rate_hz ({self.frame_rate_hz}) must be a whole multiple of "
                             f"control_rate_hz ({self.control_rate_hz})")
        if self.episode_frames < round(ratio):
            raise ValueError(f"episode_frames must be at least one control step ({round(ratio)} frames), "
                             f"got {self.episode_frames}")
        if not 0.0 < self.action_smoothing <= 1.0:
            raise ValueError(f"action_smoothing must be in (0, 1], got {self.action_smoothing}")

    @property
    def frames_per_control(self) -> int:
        """Reference frames advanced per policy step (2)."""
        return round(self.frame_rate_hz / self.control_rate_hz)


@dataclass(frozen=True)
class ArtefactMix:
    """Which episodes mimic an IMU-corrupted reference (ADAPT trains on clean + faulty takes).

    Attributes:
        recipe: relative strength of each artefact kind (see :mod:`reference_motion.artefacts`).
        strength: ``(low, high)``; each corrupted variant scales ``recipe`` by a strength drawn
            uniformly from this range.
        fraction: probability that an episode gets a corrupted reference (0 = clean only,
            1 = corrupted only).
        variants_per_clip: corrupted variants made per clip (lazily, seeded from the env's
            seed) and reused; each needs one corruption and one reference precomputation.
    """

    recipe: ArtefactRecipe = field(default_factory=ArtefactRecipe.imu)
    strength: tuple[float, float] = (0.5, 1.0)
    fraction: float = 0.5
    variants_per_clip: int = 4

    def __post_init__(self) -> None:
        lo, hi = self.strength
        if not 0 <= lo <= hi:
            raise ValueError(f"ArtefactMix.strength must be (low, high) with 0 <= low <= high, got {self.strength}")
        if not 0.0 <= self.fraction <= 1.0:
            raise ValueError(f"ArtefactMix.fraction must be in [0, 1], got {self.fraction}")
        if self.variants_per_clip < 1:
            raise ValueError(f"ArtefactMix.variants_per_clip must be >= 1, got {self.variants_per_clip}")
