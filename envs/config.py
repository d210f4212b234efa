"""Configuration of the mimic environments: every constant of ADAPT §3.2 in one place.

:class:`MimicConfig` holds the task's timing, action, reward and termination constants (adapt
Tables 2 and 3); :class:`ArtefactMix` says which episodes get an IMU-corrupted reference (ADAPT's
clean/faulty training mix). The three ADAPT ids differ only in ``obs_mode`` and
``action_mode``. :class:`GaitConfig` holds the constants of ``MimicGait-v0`` (ContactVision's
reconstruction reward, contactvision App. C).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from envs.observations import OBS_FRAMES
from envs.preparation import PreparationSteps, prepares_any
from reference_motion.artefacts import HINGE_KINDS, ArtefactRecipe
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.quality import QualityConfig
from reference_motion.swing_lift import SwingLift

FOOT_MODELS = {"one": "humanoid_1seg", "two": "humanoid_2seg"}
"""``foot`` argument → humanoid model."""

OBS_MODES = ("adapt", "drecon")
"""``adapt``: adapt Table 1 over all bodies (273-D on ``humanoid_1seg``); ``drecon``: the same
terms over DReCon's key bodies only (:data:`DRECON_BODIES`), the reduced-state ablation."""

KEY_JOINT_BODIES = ("r_upper_arm", "r_thigh", "r_shin", "r_foot", "l_upper_arm", "l_thigh", "l_shin", "l_foot")
"""Bodies whose hinges the policy drives in ``key`` action mode: shoulders, hips, knees, ankles (adapt eq. 4)."""

TOE_BODIES = ("l_toe", "r_toe")
"""The toe segments of ``humanoid_2seg``, each on one hinge (pitch; + bends the toes up)."""

ACTION_BODIES = {"key": KEY_JOINT_BODIES, "key_toes": KEY_JOINT_BODIES + TOE_BODIES}
"""Driven bodies of the action modes that drive a subset of the hinges."""

ACTION_MODES = ("key", "key_toes", "full")
"""``key``: offsets on the 8 key joints (20 hinges, adapt eq. 4); ``key_toes``: those and the two
toe hinges (22; ``humanoid_2seg`` only, the ``MimicGait-v0`` default); ``full``: every actuated hinge."""

DRECON_BODIES = ("pelvis", "head", "l_hand", "r_hand", "l_foot", "r_foot")
"""Bodies observed in ``drecon`` mode: the root and the end effectors, as DReCon's reduced state."""

SPINAL_BODIES = ("pelvis", "spine_lower", "spine_mid", "chest", "neck", "head")
"""Bodies whose ground contacts count towards the fall termination (adapt §3.2.3)."""


@dataclass(frozen=True)
class MimicConfig:
    """Constants of a mimic task (defaults: ADAPT).

    Attributes:
        frame_rate_hz: rate of simulation frames = reference frames (60 Hz).
        physics_rate_hz: rate of the physics steps (Hz), a whole multiple of ``frame_rate_hz``.
            120 (default): the model's own 1/120 s timestep, on which every shipped policy
            trained. MuJoCo's soft contacts cannot be stiffer than a time constant of two steps,
            so at 120 Hz a loaded sole sinks up to ~3 cm into the floor and slides while it
            rocks; above 120 Hz the contact time constant is set to two steps of the finer rate
            (:func:`envs.physics.at_physics_rate`), which cuts both (``bench/physics_rate.py``)
            for 2× (240 Hz) to 4× (480 Hz) the physics time.
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
        track_cache_size: reference tracks (clip or corrupted variant) kept in memory by each
            process, shared by all its envs, least recently used dropped first (each ~5 kB a frame,
            ~3 MB for a 602-frame training clip; at the default ~0.8 GB). The largest value asked by
            any env of a process holds (:mod:`envs.track_cache`). Give it at least three per env of
            the process (the tracked, judged and clean track of each running episode), or tracks
            are rebuilt during episodes. Not part of the task: envs made from a policy's sidecar
            keep the defaults (:meth:`agents.sidecar.EnvSpec.make`).
        reference_cache_size: prepared references (a clip or corrupted variant as tracked, after
            corruption, denoising and preparation; ``qpos`` only, ~0.4 kB a frame, each ~12x smaller
            than its track; at the default ~1 GB) kept by each process, so that a dropped track is
            rebuilt without corrupting and denoising again (a reset on a training run's references
            3.4x faster with 8 tracks kept, ``bench/track_rebuild.py``). Shared and bounded as
            ``track_cache_size``.
        obs_frame: axes of the observation's vectors (:data:`envs.observations.OBS_FRAMES`):
            ``"world"`` (ADAPT's, adapt §3.2.1), ``"heading"`` (the character's heading frame,
            plus its CoM offset from the reference's; 3 values longer) or ``"reference"``
            (ADAPT's layout in axes turned with the reference's heading: every clip then walks
            towards +x, as the clips a world-frame policy trained on start; such a policy runs
            in it as it is).
        com_offset: the observation also carries ``dp_com``, the character's CoM minus the
            reference's (m), in the observation's axes (3 values longer). ADAPT's world-frame state has
            no position error at all, so drift from the reference, which the lag termination ends
            episodes on, is invisible to the policy. Always on in the heading frame.
        velocity_feedforward: the PD controllers damp towards the reference's joint velocity
            instead of towards rest (False: ADAPT's PD, whose damping makes the body trail a
            moving reference; see :func:`envs.reference.pd_targets`).
        lookahead: future control steps (each ``frames_per_control`` frames ahead, clamped to the
            clip's last frame) whose reference the observation also shows: per step, the
            reference CoM's displacement from its current position, its CoM velocity and its body
            origins relative to its CoM (``6 + 3·B`` values, in the observation's axes; layout in
            :mod:`envs.observations`). ADAPT's state shows the reference at the current frame
            only, so a change of step or direction is seen once it has begun. Empty (default):
            ADAPT's observation. Strictly increasing positive integers.
        lookbehind: past control steps (each ``frames_per_control`` frames back, clamped to the
            clip's first frame) whose reference the observation also shows, after the lookahead and
            laid out as it is (its CoM's displacement from its current position, its CoM velocity,
            its body origins relative to its CoM). With the lookahead it is a window of the take
            around now, from which a policy can tell an IMU take's jitter and noise from its
            motion as a denoiser does (README "Round 20"). Empty (default): ADAPT's observation.
            Strictly increasing positive integers.
        steer_gain_hz: the observed reference velocities (its CoM's and every body's) get a
            horizontal pull back towards the reference's CoM position, this gain (1/s) times the
            character's offset from it (:func:`envs.observations.steered_velocities`), so a
            policy that tracks velocities also closes a drift it cannot otherwise see (ADAPT's
            observation holds no position error). 0 (default): ADAPT's observation. The reward and
            terminations are unchanged. The observation's layout is the same, so a policy trained
            without it runs with it (``bench/steering.py``).
        steer_max_speed_mps: the cap on that pull's speed (m/s).
        still_feet_weight: w_still, the weight of the still-feet term r_still in the reward
            (:func:`envs.rewards.still_feet_reward`; the reward is then e_discount·(r_local + r_p +
            r_v + w_still·r_still) and a step's largest reward 3 + w_still). 0 (default): ADAPT's
            reward. ADAPT's terms ask a stance foot to stay still only through r_v, one of 20
            bodies' face velocities at α_v = 0.1, so a policy's feet rock, turn and scuff on the
            floor (foot skate several times the take's).
        still_feet_alpha: α of r_still, per m/s of summed horizontal foot-point speed.
        still_feet_height_m: a foot point at most this high above the floor (m) counts in r_still
            (default: the contact height of ``reference_motion.quality.QualityConfig``, whose foot
            skate r_still is). With a weight above 0 the reward's units change (MRR, the search's
            ranking and ``clean.py``'s reward ratio divide by 3 + w_still), so those figures do not
            compare with an ADAPT-reward policy's.
        com_velocity_weight: w_com, the weight of the CoM-velocity term r_com in the reward
            (:func:`envs.rewards.com_velocity_reward`; the reward is then e_discount·(r_local + r_p
            + r_v + w_still·r_still + w_com·r_com) and a step's largest reward 3 + w_still + w_com).
            r_com asks the character's horizontal CoM velocity to match the judged reference's plus
            the steering pull back onto its CoM position (the pull of ``steer_gain_hz`` and
            ``steer_max_speed_mps``, none at gain 0), so a character that walks slower than the
            take, or has drifted from it, loses reward at once. ADAPT's reward sees speed only
            through r_v (α_v = 0.1, nearly flat) and drift only beyond 0.21 m of head distance
            (e_discount). 0 (default): ADAPT's reward.
        com_velocity_alpha: α of r_com, per m/s of horizontal CoM velocity error.
    """

    frame_rate_hz: float = 60.0
    physics_rate_hz: float = 120.0
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
    track_cache_size: int = 256
    reference_cache_size: int = 4096
    obs_frame: str = "world"
    com_offset: bool = False
    velocity_feedforward: bool = False
    lookahead: tuple[int, ...] = ()
    lookbehind: tuple[int, ...] = ()
    steer_gain_hz: float = 0.0
    steer_max_speed_mps: float = 0.5
    still_feet_weight: float = 0.0
    still_feet_alpha: float = 5.0
    still_feet_height_m: float = QualityConfig.contact_height
    com_velocity_weight: float = 0.0
    com_velocity_alpha: float = 2.0

    def __post_init__(self) -> None:
        weight, alpha, height = self.still_feet_weight, self.still_feet_alpha, self.still_feet_height_m
        if not (all(map(math.isfinite, (weight, alpha, height))) and weight >= 0 and alpha > 0 and height > 0):
            raise ValueError("still_feet_weight must be finite and >= 0, still_feet_alpha and still_feet_height_m "
                             f"finite and > 0, got {weight!r}, {alpha!r}, {height!r}")
        if not (math.isfinite(self.com_velocity_weight) and self.com_velocity_weight >= 0
                and math.isfinite(self.com_velocity_alpha) and self.com_velocity_alpha > 0):
            raise ValueError("com_velocity_weight must be finite and >= 0 and com_velocity_alpha finite and > 0, got "
                             f"{self.com_velocity_weight!r}, {self.com_velocity_alpha!r}")
        if not (math.isfinite(self.steer_gain_hz) and self.steer_gain_hz >= 0
                and math.isfinite(self.steer_max_speed_mps) and self.steer_max_speed_mps > 0):
            raise ValueError("steer_gain_hz must be finite and >= 0 and steer_max_speed_mps finite and > 0, got "
                             f"{self.steer_gain_hz!r}, {self.steer_max_speed_mps!r}")
        for name in ("lookahead", "lookbehind"):
            steps = tuple(getattr(self, name))  # a sidecar's JSON list arrives as a list
            if not all(map(_whole, steps)) or any(
                    k < 1 for k in steps) or list(steps) != sorted(set(steps)):
                raise ValueError(f"{name} must be strictly increasing positive whole control steps, "
                                 f"got {getattr(self, name)!r}")
            object.__setattr__(self, name, tuple(int(k) for k in steps))
        steps = self.physics_rate_hz / self.frame_rate_hz
        if not steps >= 1 or abs(steps - round(steps)) > 1e-6:
            raise ValueError(f"physics_rate_hz must be a whole multiple of frame_rate_hz ({self.frame_rate_hz:g} Hz), "
                             f"got {self.physics_rate_hz!r}")
        if self.obs_frame not in OBS_FRAMES:
            raise ValueError(f"obs_frame must be one of {', '.join(map(repr, OBS_FRAMES))}, got {self.obs_frame!r}")
        ratio = self.frame_rate_hz / self.control_rate_hz
        if ratio < 1 or abs(ratio - round(ratio)) > 1e-9:
            raise ValueError(f"frame_rate_hz ({self.frame_rate_hz}) must be a whole multiple of "
                             f"control_rate_hz ({self.control_rate_hz})")
        if self.episode_frames < round(ratio):
            raise ValueError(f"episode_frames must be at least one control step ({round(ratio)} frames), "
                             f"got {self.episode_frames}")
        for name, least in (("track_cache_size", 1), ("reference_cache_size", 0)):
            if not (_whole(getattr(self, name)) and getattr(self, name) >= least):
                raise ValueError(f"{name} must be a whole number >= {least}, got {getattr(self, name)!r}")
        if not 0.0 < self.action_smoothing <= 1.0:
            raise ValueError(f"action_smoothing must be in (0, 1], got {self.action_smoothing}")

    @property
    def window_steps(self) -> tuple[int, ...]:
        """The control steps, relative to now, of the reference frames the observation shows beyond
        the current one: ``lookahead`` (positive), then ``lookbehind`` negated, in that order."""
        return self.lookahead + tuple(-k for k in self.lookbehind)

    @property
    def observes_com_offset(self) -> bool:
        """Whether the observation carries ``dp_com`` (``com_offset``, or the heading frame)."""
        return self.com_offset or self.obs_frame == "heading"

    @property
    def frames_per_control(self) -> int:
        """Reference frames advanced per policy step (2)."""
        return round(self.frame_rate_hz / self.control_rate_hz)


JUDGES = ("corrupted", "clean", "given", "clean_pose", "unslid_pose")
"""What an episode is rewarded and terminated against (:attr:`ArtefactMix.judge`)."""

JUDGED_WITHOUT = {"clean_pose": HINGE_KINDS, "unslid_pose": (*HINGE_KINDS, "skate")}
"""The judges that compare a corrupted episode with its variant as made without some artefact kinds
(:data:`reference_motion.artefacts.ARTEFACT_KINDS`), and those kinds."""


@dataclass(frozen=True)
class ArtefactMix:
    """Which episodes mimic an IMU-corrupted reference (ADAPT trains on clean + faulty takes), and
    how every reference is prepared before the policy tracks it.

    Attributes:
        recipe: relative strength of each artefact kind (see :mod:`reference_motion.artefacts`).
        strength: ``(low, high)``; each corrupted variant scales ``recipe`` by a strength drawn
            uniformly from this range.
        fraction: probability that an episode gets a corrupted reference (0 = clean only,
            1 = corrupted only).
        variants_per_clip: corrupted variants made per clip (lazily) and reused; each needs one
            corruption and one reference precomputation.
        seed: base seed of the variants. ``None``: the seed given to ``reset`` (each environment
            of a vector env its own variants); an int: every environment with this mix makes the
            same variants, so the environments of one process build each once and share it
            (``agents/train_ppo.py`` sets it: 8 environments, 1/8 of the building and memory).
        judge: what a corrupted episode's reward and terminations compare the simulation with:
            ``"corrupted"``, the reference the policy observes and its PD targets follow (ADAPT);
            or ``"clean"``, the clip it was corrupted from, which only training can know (the
            policy is then rewarded for performing the clean motion from the corrupted reference:
            :mod:`agents.expert_iteration`'s ``--judge clean``); or ``"given"``, the reference as made,
            before ``denoiser``, ``symmetry``, ``legs``, ``grounding`` and ``lift`` prepared it (the corrupted variant, or
            in a clean episode the clip), as ``evaluate.py --denoise --part-legs --ground --swing-lift``
            judges a take.
            Or ``"clean_pose"``: the variant as made with none of its hinge errors
            (:data:`reference_motion.artefacts.HINGE_KINDS`): the clean clip's pose on the corrupted
            variant's root path (its heading, root drift, skate and height, drawn from the same
            streams), so the policy is paid for a pose it can perform (the IMU suit's hip adduction
            crosses the legs) along the path that evaluation judges it against.
            Or ``"unslid_pose"``: that without its stance skate too (heading, root drift and height
            kept), so the policy is not paid to follow a slide of the root its planted feet cannot make
            (:data:`JUDGED_WITHOUT`).
            With ``"clean"``, ``"given"``, ``"clean_pose"`` and ``"unslid_pose"`` a clean episode the mix prepares is
            judged against the clip as given; with ``"corrupted"`` every episode against what the
            policy tracks.
        denoiser: directory of an IMU denoiser (:mod:`perception.imu_denoiser`) that every
            corrupted variant passes through before the policy observes it, as ``clean.py
            --denoise`` passes a take; ``None`` (default): the corrupted reference as made.
        denoise_slow_s: with ``denoiser``, only the slow part of its hinge corrections (a Gaussian of
            this many seconds) and none of its height correction
            (:class:`perception.imu_denoiser.SlowCorrections`, ``evaluate.py --denoise-slow``);
            ``None`` (default): its whole correction.
        symmetry: every reference the policy tracks, clean or corrupted, with its legs evened after
            the denoiser (:func:`reference_motion.leg_symmetry.even_legs`, ``evaluate.py --even-legs``),
            as evaluation evens every take: set for a raw take at strength 1, it evens clean episodes
            and weaker variants more than their offsets call for; ``None`` (default): as made.
        legs: every reference the policy tracks, clean or corrupted, with its legs parted after the
            denoiser and the evening where its feet pass closer than ``legs.min_gap_m``
            (:func:`reference_motion.leg_gap.part_legs`, ``evaluate.py --part-legs``); ``None``
            (default): as made.
        grounding: every reference the policy tracks, clean or corrupted, set on the floor after
            the denoiser and the legs (:func:`reference_motion.grounding.ground`, ``evaluate.py --ground``);
            ``None`` (default): as made.
        lift: every reference the policy tracks with its backward steps' knees lifted in swing, last
            (:func:`reference_motion.swing_lift.lift_swing`, ``evaluate.py --swing-lift``); ``None``
            (default): as made. The five steps are :func:`envs.preparation.prepared`'s.
    """

    recipe: ArtefactRecipe = field(default_factory=ArtefactRecipe.imu)
    strength: tuple[float, float] = (0.5, 1.0)
    fraction: float = 0.5
    variants_per_clip: int = 4
    seed: int | None = None
    judge: str = "corrupted"
    denoiser: str | None = None
    denoise_slow_s: float | None = None
    symmetry: LegSymmetry | None = None
    legs: LegGap | None = None
    grounding: Grounding | None = None
    lift: SwingLift | None = None

    @property
    def steps(self) -> PreparationSteps:
        """``symmetry``, ``legs``, ``grounding`` and ``lift``: the preparation after the denoiser, as
        keyword arguments of :func:`envs.preparation.prepared`."""
        return PreparationSteps(symmetry=self.symmetry, legs=self.legs, grounding=self.grounding, lift=self.lift)

    def prepares(self, corrupted: bool) -> bool:
        """Whether the reference of a corrupted (or clean) episode is prepared before the policy
        tracks it (denoised, its legs evened or parted, grounded or lifted), so that ``judge`` may
        compare with another one."""
        return (corrupted and self.denoiser is not None) or prepares_any(self.steps)

    def __post_init__(self) -> None:
        lo, hi = self.strength
        if not 0 <= lo <= hi:
            raise ValueError(f"ArtefactMix.strength must be (low, high) with 0 <= low <= high, got {self.strength}")
        if not 0.0 <= self.fraction <= 1.0:
            raise ValueError(f"ArtefactMix.fraction must be in [0, 1], got {self.fraction}")
        if self.variants_per_clip < 1:
            raise ValueError(f"ArtefactMix.variants_per_clip must be >= 1, got {self.variants_per_clip}")
        if self.judge not in JUDGES:
            raise ValueError(f"ArtefactMix.judge must be one of {JUDGES}, got {self.judge!r}")
        if self.denoise_slow_s is not None and (self.denoiser is None or not self.denoise_slow_s > 0):
            raise ValueError(f"ArtefactMix.denoise_slow_s must be a number of seconds > 0 and go with a denoiser, got "
                             f"{self.denoise_slow_s} with denoiser {self.denoiser!r}")


@dataclass(frozen=True)
class Pushes:
    """Random shoves of the pelvis during training episodes, so that the policy meets, and learns to
    recover from, states off the reference that no clip shows (DeepMimic's perturbations: Peng et
    al. 2018, §9; the generalist's zero-shot failures are falls in progress).

    While no push is on, each control step starts one with probability ``rate_hz /
    control_rate_hz``: a horizontal force at the pelvis's origin (world, direction uniform) held for
    ``duration_s``. Training only: evaluation, cleaning and adaptation never push.

    Attributes:
        force_n: ``(low, high)`` N; each push's magnitude is drawn uniformly from it (the humanoid
            weighs 70 kg: 120 N for 0.2 s changes its speed by 0.34 m/s).
        duration_s: how long each push lasts (s; whole control steps, at least one).
        rate_hz: pushes started per second, on average, while none is on.
    """

    force_n: tuple[float, float] = (40.0, 120.0)
    duration_s: float = 0.2
    rate_hz: float = 0.4

    def __post_init__(self) -> None:
        lo, hi = self.force_n
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo <= hi):
            raise ValueError(f"Pushes.force_n must be (low, high) with 0 <= low <= high (N), got {self.force_n}")
        if not (math.isfinite(self.duration_s) and self.duration_s > 0):
            raise ValueError(f"Pushes.duration_s must be > 0 (s), got {self.duration_s}")
        if not (math.isfinite(self.rate_hz) and self.rate_hz >= 0):
            raise ValueError(f"Pushes.rate_hz must be >= 0 (pushes per second), got {self.rate_hz}")


@dataclass(frozen=True)
class Dynamics:
    """Random changes to the simulated humanoid's physics, drawn anew at every training episode's
    reset (domain randomisation: Peng et al. 2018, "Sim-to-real transfer of robotic control with
    dynamics randomization"), so that the policy does not lean on one exact body: a reference it
    has never seen (an unseen style, an IMU take) asks for torques and balance the nominal body was
    never shown, which a policy hardened against a range of bodies may still meet.

    ``mass``, ``friction`` and ``strength`` are relative half-ranges ``r``: a factor is drawn
    uniformly from ``[1 - r, 1 + r]``. Training only: evaluation, cleaning and adaptation simulate
    the nominal humanoid.

    Attributes:
        mass: each body's mass and rotational inertia scaled by its own factor (the humanoid's total
            mass, 70 kg, then varies with a std of about ``r / 5.6`` of itself: 1.9 kg at 0.15).
        friction: every geom's sliding friction scaled by one factor per episode (MuJoCo takes the
            larger of two touching geoms', so sole-on-floor friction scales by it).
        strength: each actuator's PD gains ``kp`` and ``kv`` scaled together by its own factor
            (its stiffness and damping; their ratio, and so any velocity feed-forward, unchanged).
        offset_deg: half-range (degrees) of a constant offset, drawn per actuator, that its PD
            target gets unseen by the policy (a miscalibrated joint: every hinge of an IMU take is
            a few degrees off, 2° std, which no denoiser can see; ``bench/imu_ceiling.py``). The
            reward still compares with the reference, so the policy learns to keep its balance and
            its driven hinges on the reference despite errors it is not shown; the hinges it does
            not drive keep theirs, as they keep an IMU take's. 0 (default): none.
    """

    mass: float = 0.15
    friction: float = 0.3
    strength: float = 0.15
    offset_deg: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.offset_deg) and 0.0 <= self.offset_deg <= 30.0):
            raise ValueError(f"Dynamics.offset_deg must be a half-range in [0, 30] degrees, got {self.offset_deg}")
        for name in ("mass", "friction", "strength"):
            value = getattr(self, name)
            if not (math.isfinite(value) and 0.0 <= value < 1.0):
                raise ValueError(f"Dynamics.{name} must be a half-range in [0, 1) (factors 1 - r .. 1 + r), "
                                 f"got {value}")


CONTACT_MODES = ("vgrf", "keypoints")
"""Named sources of ``MimicGait-v0``'s contact targets: VGRFNet + Γ on the reference's joints, or
the ContactTransformer on 2D keypoints of the reference filmed from the side."""

MODELS_DIR = Path(__file__).resolve().parents[1] / "models"
DEFAULT_VGRF_NET = MODELS_DIR / "vgrf"
"""The shipped VGRFNet (``python -m perception train-vgrf``)."""
DEFAULT_CONTACT_NET = MODELS_DIR / "contact_transformer"
"""The shipped ContactTransformer (``python -m perception train-keypoints``)."""


@dataclass(frozen=True)
class GaitConfig:
    """Constants of ``MimicGait-v0``: ContactVision's reconstruction reward (contactvision eq. 6,
    App. C) and what the policy observes of the gait targets.

    R = w_q r_q + w_v r_v + w_e r_e + w_fc r_fc + w_up r_up + w_root_ori r_root_ori + w_torque r_torque,
    each term exp(−α · squared error) (:mod:`envs.rewards`). The weights are ContactVision's
    (App. C; they sum to 1, so R ≤ 1). ContactVision gives no α. r_q and r_e take DeepMimic's
    (Peng et al. 2018: pose 2, end effector 40), on whose reward terms Yu et al. [YPL21], and so
    ContactVision, build; the other five are ours, each set so that the term halves at an error
    one would call clearly wrong, or, for r_v and r_torque, is about 0.5 and 0.9 where PD
    controllers following the reference leave it (measured on ``deepmimic:walk``).

    Attributes:
        w_q, w_v, w_e, w_fc, w_up, w_root_ori, w_torque: term weights (contactvision App. C).
        alpha_q: r_q, per rad² summed over all 45 hinges (DeepMimic's 2; the toe hinges' reference
            is the ToeRefEstimator's angle).
        alpha_v: r_v, per (rad/s)² summed over all hinges: halves at 28 (rad/s)² (ours). The PD
            controllers following the 60 Hz reference from its own state leave 20–30 (rad/s)²,
            where DeepMimic's 0.1 would already give 0.05–0.1, and so no signal.
        alpha_e: r_e, per m² summed over the end effectors (DeepMimic's 40).
        alpha_fc: r_fc, per wrong contact channel: one channel wrong gives exp(−1) ≈ 0.37, two
            0.14 (ours; ContactVision's xor count is small, 0–4, so α_fc ~ 1 makes each mistake count).
        alpha_up: r_up, per rad² of upper-body tilt error: halves at 15° (ours).
        alpha_root_ori: r_root_ori, on (1 − cos tilt)²: halves at a 28° pelvis tilt, 0.01 at 45°
            (ours; walking tilts the pelvis < 10°, which costs at most 1.2%).
        alpha_torque: r_torque, on Σ (τ / τ_max)² over the actuators (torque over force limit):
            halves at a sum of 0.69, e.g. three joints at 48% of their limit (ours; following the
            reference on walk the sum is 0.1–0.2, r_torque ≈ 0.85, and a stumble reaches 0.8).
        end_effectors: bodies of r_e (hands and feet, contactvision App. C).
        preview_frames: the observation carries the contact and toe targets of this many next
            reference frames (60 Hz; 4 = the next two policy steps).
        keypoint_azimuth_deg: ``contacts="keypoints"`` films the reference from this direction
            (degrees from +x towards +y; 90 = from the character's left, a side view of a clip
            that starts facing +x) at ContactVision's rig distance and height (4 m, 1 m).
        toe_reference: the toe hinges' targets come from the ToeRefEstimator (True) or are 0, the
            toes held straight (False: ContactVision's "without ToeRefEstimator" ablation, Fig. 12).
    """

    w_q: float = 0.3
    w_v: float = 0.05
    w_e: float = 0.05
    w_fc: float = 0.3
    w_up: float = 0.1
    w_root_ori: float = 0.15
    w_torque: float = 0.05
    alpha_q: float = 2.0
    alpha_v: float = 0.025
    alpha_e: float = 40.0
    alpha_fc: float = 1.0
    alpha_up: float = math.log(2.0) / math.radians(15.0) ** 2
    alpha_root_ori: float = math.log(2.0) / (1.0 - math.cos(math.radians(28.0))) ** 2
    alpha_torque: float = 1.0
    end_effectors: tuple[str, ...] = ("l_hand", "r_hand", "l_foot", "r_foot")
    preview_frames: int = 4
    keypoint_azimuth_deg: float = 90.0
    toe_reference: bool = True

    def __post_init__(self) -> None:
        named = {**{f"w_{k[2:]}": w for k, w in self.weights.items()}, **{f"alpha_{k[2:]}": a for k, a in self.alphas.items()}}
        bad = {k: v for k, v in named.items() if not (math.isfinite(v) and v >= 0)}
        if bad:
            raise ValueError(f"GaitConfig weights and alphas must be finite and >= 0, got {bad}")
        if self.preview_frames < 1:
            raise ValueError(f"GaitConfig.preview_frames must be >= 1, got {self.preview_frames}")
        if not self.end_effectors:
            raise ValueError("GaitConfig.end_effectors is empty")

    def ablated(self, ablation: str | None) -> GaitConfig:
        """These constants under one of ContactVision Fig. 12's ablations (:data:`GAIT_ABLATIONS`):
        ``"no_fc"`` drops the contact reward (w_fc 0), ``"no_toeref"`` holds the toe targets at 0;
        ``None``: unchanged. The third ablation, the one-segment foot, is a body, not a constant."""
        if ablation is None:
            return self
        if ablation == "no_fc":
            return replace(self, w_fc=0.0)
        if ablation == "no_toeref":
            return replace(self, toe_reference=False)
        raise ValueError(f"unknown gait ablation {ablation!r}; expected one of {GAIT_ABLATIONS}")

    @property
    def weights(self) -> dict[str, float]:
        """``{term: w}`` for the terms of :data:`envs.rewards.GAIT_TERMS`."""
        return {"r_q": self.w_q, "r_v": self.w_v, "r_e": self.w_e, "r_fc": self.w_fc, "r_up": self.w_up,
                "r_root_ori": self.w_root_ori, "r_torque": self.w_torque}

    @property
    def alphas(self) -> dict[str, float]:
        """``{term: α}`` for the terms of :data:`envs.rewards.GAIT_TERMS`."""
        return {"r_q": self.alpha_q, "r_v": self.alpha_v, "r_e": self.alpha_e, "r_fc": self.alpha_fc,
                "r_up": self.alpha_up, "r_root_ori": self.alpha_root_ori, "r_torque": self.alpha_torque}


GAIT_ABLATIONS = ("no_fc", "no_toeref")
"""ContactVision Fig. 12's ablations of ``MimicGait-v0``'s constants (:meth:`GaitConfig.ablated`):
no contact reward, toe targets 0."""


def _whole(value: object) -> bool:
    """Whether ``value`` is a whole number (a Python or NumPy integer, not a bool)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)
