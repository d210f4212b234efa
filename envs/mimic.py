"""The ADAPT mimic environment (adapt §3.2): a PD-driven humanoid re-performs reference clips.

Per policy step (30 Hz) the environment advances two 60 Hz reference frames. In each frame every
actuated hinge gets the reference angle of that frame as its PD target, and the driven hinges
(the 8 key joints, or all) add the smoothed action. Rewards, terminations and the observation are
the pure functions of :mod:`envs.rewards` and :mod:`envs.observations`; the reference quantities
they need are precomputed per clip (:class:`envs.reference.ReferenceTrack`).
"""

from __future__ import annotations

import copy
import hashlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np

from envs.bodies import bodies_touching, floor_contact_geoms, read_body_state, region_contacts, update_kinematics
from envs.config import (ACTION_BODIES, ACTION_MODES, DRECON_BODIES, FOOT_MODELS, JUDGED_WITHOUT, OBS_MODES,
                         SPINAL_BODIES, ArtefactMix, Dynamics, MimicConfig, Pushes)
from envs.observations import (heading_rotation, lookahead_observation, mimic_observation, observation_slices,
                               steered_velocities, steering_pull)
from envs.physics import PhysicsDraw, apply_physics, at_physics_rate, draw_physics
from envs.preparation import PreparationSteps, no_preparation, prepared
from envs.privileged import privileged_features, privileged_size
from envs.reference import ReferenceFrame, ReferenceTrack, pd_targets
from envs.sampling import FailureSampler, SamplingConfig
from envs.track_cache import REFERENCES, TRACKS
from envs.rendering import GhostRenderer
from envs.rewards import (MAX_STEP_REWARD, RewardTerms, body_points, com_velocity_reward, cube_face_points,
                          cube_face_velocities, fallen, lagging, mimic_reward, still_feet_reward, unstable)
from reference_motion import rotations as rot
from reference_motion.artefacts import corrupt
from reference_motion.humanoid.model import HumanoidModel, load_model
from reference_motion.library import load_motion, named_set
from reference_motion.motion import Motion
from reference_motion.transforms import resample

ClipSpec = str | Path | Motion


def shipped_network(path: str | Path, kind: str):
    """A shipped perception network, loaded once per process (:func:`perception.weights.shared_network`;
    imported here, so that ``import envs`` stays free of torch)."""
    from perception.weights import shared_network
    return shared_network(str(path), kind)


def mix_denoiser(path: str | Path, slow_s: float | None):
    """The IMU denoiser of an :class:`ArtefactMix` (``denoiser``, ``denoise_slow_s``): the shipped
    network, or its :class:`perception.imu_denoiser.SlowCorrections` (imported here, for the same reason)."""
    from perception.imu_denoiser import slowed
    return slowed(shipped_network(path, "denoiser"), slow_s)


JUDGED = -2
"""``MimicEnv.track``'s variant of a clip's judged motion (the env's ``judged_clips``)."""


class MimicEnv(gym.Env):
    """Mimic reference clips with a PD-driven MuJoCo humanoid (``MimicIMU-v0`` and its siblings).

    Args:
        clips: the motion set: a named set (``"locomotion"``, ``"deepmimic"``), or a sequence of
            SOURCE strings / paths (see :func:`reference_motion.library.load_motion`) and
            :class:`Motion` objects. Cyclic clips are looped to two episodes; a clip shorter than an
            episode ends its episodes (truncation) at its last frame; every clip must be longer than
            ``config.min_clip_frames``.
        artefacts: which episodes get an IMU-corrupted reference, and how every reference is
            prepared before the policy tracks it (:class:`ArtefactMix`); ``None`` mimics the clips
            as given.
        foot: ``"one"`` (``humanoid_1seg``) or ``"two"`` (``humanoid_2seg``, toe joint open loop).
        episode_frames: longest episode in reference frames (default 300 = 5 s at 60 Hz).
        obs_mode: ``"adapt"`` (all bodies, adapt Table 1) or ``"drecon"`` (key bodies only).
        action_mode: ``"key"`` (20 hinges of the 8 key joints), ``"key_toes"`` (those and the two toe
            hinges; ``foot="two"`` only) or ``"full"`` (every actuated hinge).
        config: the remaining constants (:class:`MimicConfig`); ``episode_frames`` overrides its field.
        sampling: how episodes pick their clip and start frame (:class:`envs.sampling.SamplingConfig`;
            default: where the policy currently fails more often).
        render_mode: ``None`` or ``"rgb_array"`` (character with the reference translucent beside it).
        width, height: rendered image size (pixels).
        judged_clips: per clip, the motion the reward and terminations compare the simulation with
            instead of the clip itself, which the policy still observes and follows: the take as
            given, when the clip is a denoised copy of it (``agents/evaluate.py --denoise``). As
            many clips as ``clips``, each with as many frames; not with ``artefacts``. ``None``
            (default): the clips themselves.
        pushes: random shoves of the pelvis (:class:`envs.config.Pushes`), for training; ``None``
            (default): none.
        dynamics: the humanoid's masses, friction, PD gains and PD-target offsets drawn anew at every
            reset (:class:`envs.config.Dynamics`), for training; ``None`` (default): the nominal
            humanoid. The episode's draw is in :attr:`physics_draw`.

    Observation: ``Box(13 + 12·B + A,)`` float32 (3 more with ``config.obs_frame="heading"`` or ``config.com_offset``,
    ``K·(6 + 3B)`` more with ``K`` steps of ``config.lookahead`` and ``config.lookbehind`` together) — layout in
    :mod:`envs.observations`,
    named slices in ``env.unwrapped.obs_slices``. Action: ``Box(−1, 1, (A,))`` rad offsets
    added to the reference PD targets of the driven hinges.

    ``reset(options=...)`` accepts ``clip`` (index or name), ``start_frame`` and ``corrupted``
    (bool) to pin down an episode, e.g. for evaluation, and ``state`` = ``(qpos, qvel)`` or
    ``(qpos, qvel, action)`` to start from a given simulated state instead of the reference state
    (to continue a long clip): ``action`` ``(A,)`` (rad) is the smoothed action in effect there
    (:attr:`smoothed`), which the next step's smoothing continues from and the observation shows
    (default zeros, as at a reference start).

    ``info``: ``r_local``, ``r_p``, ``r_v``, ``r_still``, ``r_com``, ``e_discount``, ``total`` and ``reward``
    (the same value); ``contacts`` (4 bools, order LT, RT, LH, RH: a sole region touching the
    floor); ``frame`` (reference frame index)
    and ``episode_frame`` (frames since the start); ``clip``, ``corrupted``, ``artefact_seed``;
    ``unstable`` (the simulation blew up); ``ended_by``: ``""`` while running, else one of
    ``"lagging"``, ``"fallen"``, ``"unstable"``, ``"time_limit"``; at ``"time_limit"`` also
    ``privileged_observation`` (:meth:`privileged_observation` of the last state, which a vector env's
    reset would replace).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 30}

    def __init__(self, clips: str | Sequence[ClipSpec] = "locomotion", artefacts: ArtefactMix | None = None,
                 foot: str = "one", episode_frames: int | None = None, obs_mode: str = "adapt",
                 action_mode: str = "key", config: MimicConfig | None = None,
                 sampling: SamplingConfig = SamplingConfig(), render_mode: str | None = None,
                 width: int = 480, height: int = 360, judged_clips: Sequence[ClipSpec] | None = None,
                 pushes: Pushes | None = None, dynamics: Dynamics | None = None):
        _check_choice("foot", foot, tuple(FOOT_MODELS))
        _check_choice("obs_mode", obs_mode, OBS_MODES)
        _check_choice("action_mode", action_mode, ACTION_MODES)
        if action_mode == "key_toes" and foot != "two":
            raise ValueError(f"action_mode 'key_toes' drives the toe hinges, which only foot='two' has; got foot={foot!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        if artefacts is not None and not isinstance(artefacts, ArtefactMix):
            raise TypeError(f"artefacts must be an envs.ArtefactMix or None, got {type(artefacts).__name__}")
        if pushes is not None and not isinstance(pushes, Pushes):
            raise TypeError(f"pushes must be an envs.config.Pushes or None, got {type(pushes).__name__}")
        if dynamics is not None and not isinstance(dynamics, Dynamics):
            raise TypeError(f"dynamics must be an envs.config.Dynamics or None, got {type(dynamics).__name__}")
        config = config or MimicConfig()
        if episode_frames is not None:
            config = replace(config, episode_frames=int(episode_frames))
        self.config = config
        self.artefacts = artefacts
        self.pushes = pushes
        self._push_steps_left = 0
        """Control steps the current push (:meth:`_push`) still lasts; 0: none on."""
        self._push_force = np.zeros(3)
        self.render_mode = render_mode
        self._size = (width, height)

        self.humanoid = load_model(FOOT_MODELS[foot])
        self.model = at_physics_rate(self.humanoid.model, config.physics_rate_hz)
        """The simulated model: the humanoid's, stepped at ``config.physics_rate_hz`` (with
        ``dynamics``, a copy of its own whose physics each reset draws)."""
        self.dynamics = dynamics
        self._nominal_model = self.model
        if dynamics is not None:
            self.model = copy.deepcopy(self.model)
        self.physics_draw = PhysicsDraw.nominal(self.model)
        """This episode's factors on the nominal humanoid's physics (all 1 without ``dynamics``)."""
        self.data = mujoco.MjData(self.model)
        m = self.model
        frame_dt = 1.0 / config.frame_rate_hz
        self.substeps = round(frame_dt / m.opt.timestep)
        if self.substeps < 1 or abs(self.substeps * m.opt.timestep - frame_dt) > 1e-4 * frame_dt:
            raise ValueError(f"frame_rate_hz {config.frame_rate_hz} is not a whole number of "
                             f"{m.opt.timestep:.5f} s physics steps")
        self.actuator_qpos = actuator_qpos(m)
        """qpos index of each actuator's hinge."""
        self.actuator_dof = m.jnt_dofadr[m.actuator_trnid[:, 0]]
        """qvel index of each actuator's hinge."""
        self.pd_lead_s = -m.actuator_biasprm[:, 2] / m.actuator_gainprm[:, 0] if config.velocity_feedforward else None
        """``kv / kp`` (s) of each actuator when the PD targets lead the reference (``config.velocity_feedforward``)."""
        names = self.humanoid.body_names
        self.parent = m.body_parentid[1:] - 1
        self.jointed = np.flatnonzero(m.body_jntnum[1:] > 0)
        self.head = names.index("head")
        self.driven = driven_actuators(self.humanoid, action_mode)
        """Actuator index of each action component."""
        self.observed = (slice(None) if obs_mode == "adapt"
                         else np.array([names.index(b) for b in DRECON_BODIES]))
        """Bodies in the observation (all, or DReCon's key bodies)."""
        n_obs_bodies = len(names) if obs_mode == "adapt" else len(DRECON_BODIES)
        n_act = len(self.driven)
        self.obs_slices = self._observation_slices(n_obs_bodies, n_act)
        """Named slices of the observation vector (:mod:`envs.observations`)."""
        lim = config.action_limit_rad
        self.action_space = gym.spaces.Box(-lim, lim, (n_act,), dtype=np.float32)
        self.observation_space = gym.spaces.Box(-np.inf, np.inf, (max(s.stop for s in self.obs_slices.values()),),
                                                dtype=np.float32)

        sites = self.humanoid.foot_point_sites
        self._foot_point_bodies = m.site_bodyid[sites] - 1
        """Index in a :class:`envs.bodies.BodyState` of the body each foot point (LT, RT, LH, RH) is on."""
        self._foot_point_offsets = m.site_pos[sites].copy()
        """``(4, 3)`` each foot point in its body's frame (m)."""
        self._floor = m.geom("floor").id
        self._pelvis = m.body("pelvis").id
        spinal = {names.index(b) + 1 for b in SPINAL_BODIES}
        self._geom_spinal_body = np.where(np.isin(m.geom_bodyid, list(spinal)), m.geom_bodyid, -1)

        self.clips = self._load_clips(clips)
        self._clip_keys = [_content_key(c) for c in self.clips]
        """Per clip: a key of its content (:func:`_content_key`), for :mod:`envs.track_cache`."""
        self._judged = None if judged_clips is None else self._load_judged(judged_clips)
        self._judged_keys = [] if self._judged is None else [_content_key(c) for c in self._judged]
        self._sampler = FailureSampler([self._last_start_frame(c.n_frames) for c in self.clips], sampling)
        """Where episodes start (:mod:`envs.sampling`)."""
        self._plans: dict[tuple[int, int, bool, tuple[str, ...]], _TrackPlan] = {}
        """Per :meth:`track` key ``(clip, variant, as_given, without)``: how that track is made, and
        the content it is kept by in this process's caches (:mod:`envs.track_cache`)."""
        TRACKS.reserve(config.track_cache_size)
        REFERENCES.reserve(config.reference_cache_size)
        self._variant_seeds: dict[tuple[int, int], int] = {}
        self._variant_base: int | None = None if artefacts is None else artefacts.seed
        """Base seed of the corrupted variants: ``artefacts.seed`` if fixed, else the last reset seed."""
        self._renderer: GhostRenderer | None = None
        self.frame_hook: Callable[[mujoco.MjData], None] | None = None
        """Called with the simulation data after every 60 Hz frame (to record the rollout:
        ``qpos``, contact forces); ``None`` (default) records nothing."""
        self.substep_hook: Callable[[mujoco.MjData], None] | None = None
        """Called after every physics substep (to average contact forces over a frame)."""
        self._track: ReferenceTrack | None = None
        self._judge: ReferenceTrack | None = None
        """The track the reward and terminations compare with: ``_track``, or another as
        :meth:`_judging_track` says (``judged_clips``, ``ArtefactMix.judge``)."""
        self._action = np.zeros(n_act)
        self._sim_contacts = np.zeros(4, dtype=bool)
        """The simulated contacts (LT, RT, LH, RH) at the current frame."""
        self._obs = np.zeros(self.observation_space.shape, dtype=np.float32)

    # ------------------------------------------------------------------ setup
    def _load_clips(self, clips: str | Sequence[ClipSpec]) -> list[Motion]:
        sources = named_set(clips) if isinstance(clips, str) else list(clips)
        if not sources:
            raise ValueError("clips is empty: give a named set or at least one motion source")
        need = self.config.min_clip_frames + 1
        fps = self.config.frame_rate_hz
        out = []
        for src in sources:
            if isinstance(src, Motion):
                if src.model != self.humanoid.name:
                    raise ValueError(f"clip {src.name!r} is a Motion for {src.model}, but this env simulates "
                                     f"{self.humanoid.name}; retarget it or pass foot= to match")
                motion = src if abs(src.fps - fps) < 1e-9 else resample(src, fps)
            else:
                motion = load_motion(src, self.humanoid.name, fps=fps,
                                     min_frames=2 * (self.config.episode_frames + 1))
            if motion.n_frames < need:
                raise ValueError(f"clip {motion.name!r} has {motion.n_frames} frames at {fps:g} Hz, fewer than "
                                 f"{need} (min_clip_frames {self.config.min_clip_frames} + 1); use a longer clip")
            out.append(motion)
        return out

    def _load_judged(self, judged_clips: Sequence[ClipSpec]) -> list[Motion]:
        if self.artefacts is not None:
            raise ValueError("judged_clips and artefacts cannot be combined: corrupted episodes are judged as "
                             "ArtefactMix.judge says")
        judged = self._load_clips(judged_clips)
        if len(judged) != len(self.clips):
            raise ValueError(f"judged_clips has {len(judged)} clips, clips has {len(self.clips)}; give one per clip")
        for clip, other in zip(self.clips, judged):
            if other.n_frames != clip.n_frames:
                raise ValueError(f"judged clip {other.name!r} has {other.n_frames} frames, its clip {clip.name!r} "
                                 f"{clip.n_frames}; a clip and the motion it is judged against must match frame by frame")
        return judged

    def last_start(self, clip: int | str) -> int:
        """Latest start frame of an episode on ``clip`` (index or name): one full episode before its
        end, or, for a clip shorter than that, the middle of the clip (episodes then end with it)."""
        return self._last_start_frame(self.clips[self._clip_index(clip)].n_frames)

    def _last_start_frame(self, n_frames: int) -> int:
        span, episode = n_frames - 1, self.config.episode_frames
        return span - episode if span >= episode else span // 2

    @property
    def episode_end(self) -> int:
        """Reference frame at which the running episode is truncated: ``episode_frames`` after its
        start, or the last frame before the clip's end that whole control steps reach."""
        if self._track is None:
            raise RuntimeError("call reset() first")
        return self._episode_end

    def track(self, clip: int, variant: int = -1, *, as_given: bool = False,
              without: tuple[str, ...] = ()) -> ReferenceTrack:
        """The reference track of clip ``clip``: as given (``variant=-1``), its corrupted variant
        ``variant``, or the motion it is judged against (``variant=JUDGED``), built on first use and
        kept by this process for all its environments (:mod:`envs.track_cache`). The clip and its
        corrupted variants are prepared as ``ArtefactMix`` says (:func:`envs.preparation.prepared`: a
        corrupted variant denoised; then the clip or variant set on the floor and swing-lifted) unless
        ``as_given``, which gives them as made (what ``ArtefactMix.judge == "given"`` compares with);
        ``JUDGED`` motions are never prepared. ``without``: a corrupted variant with these artefact
        kinds switched off (with ``as_given``, what ``ArtefactMix.judge == "clean_pose"`` or
        ``"unslid_pose"`` compares with, :data:`envs.config.JUDGED_WITHOUT`; without, prepared as the
        variant is; ignored for the clip and ``JUDGED``). A variant's artefact seed and strength
        depend only on (``artefacts.seed``, or else the last seed given to :meth:`reset`; clip;
        variant), so the same seed always gives the same references whatever order episodes come in."""
        as_given = (as_given and variant != JUDGED and self.artefacts is not None
                    and self.artefacts.prepares(variant >= 0))  # else the same track: one cache slot
        if isinstance(without, str):
            raise TypeError(f"track: without takes a sequence of artefact kinds, e.g. ({without!r},), not a string")
        without = tuple(sorted(set(without))) if variant >= 0 else ()  # one cache slot whatever the order
        key = (clip, variant, as_given, without)
        plan = self._plans.get(key)
        if plan is None:
            plan = self._plans[key] = self._track_plan(clip, variant, as_given, without)
        track = TRACKS.get(plan.track_key)
        if track is None:
            track = TRACKS.put(plan.track_key, self._built_track(plan))
        return track

    def _track_plan(self, clip: int, variant: int, as_given: bool, without: tuple[str, ...]) -> _TrackPlan:
        """How track ``(clip, variant, as_given, without)`` (:meth:`track`'s, checked) is made. Draws a
        variant's seed and strength."""
        corruption = None
        if variant >= 0:
            mix = self.artefacts
            if self._variant_base is None:
                self._variant_base = int(self.np_random.integers(2**31))
            rng = np.random.default_rng([self._variant_base, clip, variant])
            seed = int(rng.integers(2**31))
            recipe = mix.recipe.scaled(float(rng.uniform(*mix.strength)))
            corruption = (recipe.without(without) if without else recipe, seed)
            self._variant_seeds[(clip, variant)] = seed
        judged = variant == JUDGED
        if variant < JUDGED or (judged and self._judged is None):
            raise ValueError(f"track variant {variant}: expected -1 (the clip), a corrupted variant >= 0, or JUDGED "
                             f"({JUDGED}) on an env made with judged_clips")
        mix = None if judged or as_given else self.artefacts
        denoiser = mix.denoiser if mix is not None and corruption is not None else None
        slow_s = mix.denoise_slow_s if denoiser is not None else None
        steps = mix.steps if mix is not None else no_preparation()
        reference_key = (self.humanoid.name, (self._judged_keys if judged else self._clip_keys)[clip], corruption,
                         denoiser, slow_s, *steps.values())
        return _TrackPlan(given=self._judged[clip] if judged else self.clips[clip], corruption=corruption,
                          denoiser=denoiser, slow_s=slow_s, steps=steps, reference_key=reference_key,
                          track_key=(*reference_key, self.config.cube_size_m))

    def _built_track(self, plan: _TrackPlan) -> ReferenceTrack:
        """The track ``plan`` says, from this process's prepared reference when it has it
        (:data:`envs.track_cache.REFERENCES`), else made; its arrays read only (shared between
        environments)."""
        motion = REFERENCES.get(plan.reference_key)
        if motion is None:
            motion = plan.given if plan.corruption is None else corrupt(plan.given, *plan.corruption)
            denoiser = None if plan.denoiser is None else mix_denoiser(plan.denoiser, plan.slow_s)
            motion = REFERENCES.put(plan.reference_key, prepared(motion, denoiser, **plan.steps))
        track = ReferenceTrack.build(motion, self.humanoid, self.actuator_qpos, self.jointed, self.parent,
                                     self.config.cube_size_m)
        for value in vars(track).values():
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
        return track

    # --------------------------------------------------------------- episode
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        fixed = self.artefacts is not None and self.artefacts.seed is not None
        if seed is not None and seed != self._variant_base and not fixed:  # corrupted variants follow the new seed
            self._variant_base = seed
            self._plans = {k: plan for k, plan in self._plans.items() if k[1] < 0}
            self._variant_seeds.clear()
        options = dict(options or {})
        clip = self._clip_index(options.pop("clip", None))
        corrupted = options.pop("corrupted", None)
        if corrupted is None:
            corrupted = self.artefacts is not None and self.np_random.random() < self.artefacts.fraction
        if corrupted and self.artefacts is None:
            raise ValueError("reset(options={'corrupted': True}) needs an env made with artefacts=ArtefactMix(...)")
        variant = int(self.np_random.integers(self.artefacts.variants_per_clip)) if corrupted else -1
        track = self.track(clip, variant)
        last_start = self._last_start_frame(track.n_frames)
        start = options.pop("start_frame", None)
        start = self._sampler.start_frame(clip, last_start, self.np_random) if start is None else int(start)
        if not 0 <= start <= last_start:
            raise ValueError(f"start_frame {start} out of range for clip {self.clips[clip].name!r}: 0..{last_start}")
        state = options.pop("state", None)
        if options:
            raise ValueError(f"unknown reset option(s) {sorted(options)}; expected clip, start_frame, corrupted, state")

        self._track, self._clip, self._variant = track, clip, variant
        self._judge = self._judging_track(clip, variant, track)
        self._start = self._frame = start
        self._push_steps_left = 0  # mj_resetData below clears the push's force
        fpc = self.config.frames_per_control
        self._episode_end = start + fpc * (min(self.config.episode_frames, track.n_frames - 1 - start) // fpc)
        if self.dynamics is not None:
            self.physics_draw = draw_physics(self.dynamics, self.model, self.np_random)
            apply_physics(self.model, self.data, self._nominal_model, self.physics_draw)
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        n_act = len(self.driven)
        qpos, qvel, action = ((track.motion.qpos[start], track.qvel[start], None) if state is None
                              else _state_parts(state, m.nq, m.nv, n_act))
        d.qpos[:], d.qvel[:] = qpos, qvel
        d.ctrl[:] = self._pd_targets(track, start)
        mujoco.mj_forward(m, d)
        depth = -d.contact.dist[(d.contact.geom == self._floor).any(axis=1)].min(initial=0.0)
        if depth > 0 and state is None:  # the reference pose reaches into the floor: start just above it
            d.qpos[2] += depth + self.config.init_clearance_m
        update_kinematics(m, d)
        self._bad_qacc = d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
        self._action = np.zeros(n_act) if action is None else np.array(action, dtype=float)
        self._sim_contacts = region_contacts(floor_contact_geoms(d, self._floor), self.humanoid.geom_contact_channel)
        self._obs = self._observe(read_body_state(m, d))
        info = {"frame": self._frame, "episode_frame": 0, "clip": self.clips[clip].name, "corrupted": variant >= 0,
                "artefact_seed": self._variant_seeds.get((clip, variant)), "contacts": self._sim_contacts.copy(),
                "unstable": False, "ended_by": ""}
        return self._obs, info

    def _judging_track(self, clip: int, variant: int, track: ReferenceTrack) -> ReferenceTrack:
        """What an episode on ``variant`` of ``clip``, tracking ``track``, is judged against: the
        env's ``judged_clips``, else as ``ArtefactMix.judge`` says (``"corrupted"``: ``track``
        itself; ``"clean"``: the clip as given; ``"given"``: the variant as given, before the mix
        prepared it; ``"clean_pose"``, ``"unslid_pose"``: that without the kinds of
        :data:`envs.config.JUDGED_WITHOUT`), else ``track``."""
        if self._judged is not None:
            return self.track(clip, JUDGED)
        mix = self.artefacts
        if mix is None or mix.judge == "corrupted":
            return track
        corrupted = variant >= 0
        if mix.judge == "clean" and corrupted:
            return self.track(clip, -1, as_given=True)
        if mix.judge in JUDGED_WITHOUT and corrupted:
            return self.track(clip, variant, as_given=True, without=JUDGED_WITHOUT[mix.judge])
        return self.track(clip, variant, as_given=True) if mix.prepares(corrupted) else track

    @property
    def smoothed(self) -> np.ndarray:
        """The smoothed action in effect, ``(A,)`` rad (a copy): the offsets the last step added to
        the PD targets, zeros after a reset from the reference state."""
        return self._action.copy()

    def _clip_index(self, clip: int | str | None) -> int:
        """Index of ``clip`` (index or name); ``None`` draws one (:mod:`envs.sampling`)."""
        if clip is None:
            return self._sampler.clip(self.np_random)
        if isinstance(clip, str):
            names = [c.name for c in self.clips]
            if clip not in names:
                raise ValueError(f"unknown clip {clip!r}; this env has {', '.join(names)}")
            return names.index(clip)
        if not 0 <= int(clip) < len(self.clips):
            raise ValueError(f"clip index {clip} out of range 0..{len(self.clips) - 1}")
        return int(clip)

    def _pd_targets(self, track: ReferenceTrack, frames: int | slice) -> np.ndarray:
        """The open-loop PD targets (rad) of reference frame ``frames``, ``(nu,)``, or of a slice of
        frames, ``(n, nu)`` (ADAPT's PD: the reference angles, without gathering the velocities the
        lead would need)."""
        if self.pd_lead_s is None:
            return track.ctrl[frames]
        return pd_targets(track.ctrl[frames], track.qvel[frames][..., self.actuator_dof], self.pd_lead_s)

    def step(self, action: np.ndarray):
        m, d = self.model, self.data
        for ctrl in self._begin_step(action):
            d.ctrl[:] = ctrl
            if self.substep_hook is None:
                mujoco.mj_step(m, d, nstep=self.substeps)
            else:
                for _ in range(self.substeps):
                    mujoco.mj_step(m, d)
                    self.substep_hook(d)
            if self.frame_hook is not None:
                self.frame_hook(d)
        if self._blew_up():
            return self._unstable_step()
        update_kinematics(m, d)
        state = read_body_state(m, d)
        spinal_contacts = self._touch(floor_contact_geoms(d, self._floor))
        reward, terms = self._reward(state)
        return self._end_step(reward, terms, self._observe(state), spinal_contacts)

    # The stages of a step (_begin_step, the physics, _blew_up / _unstable_step, _touch, the reward and
    # observation, _end_step), apart so that :class:`agents.batched_vec_env.BatchedMimicVecEnv` can run
    # the physics of many environments at once between them and compute their rewards and
    # observations as one batch (:meth:`_tracking_terms`, :meth:`_tracking_observation`). They are
    # that class's protocol with this one, not a public API.
    def _begin_step(self, action: np.ndarray) -> np.ndarray:
        """Take the policy's ``action``: clip and smooth it, advance the reference by one control
        step and return the PD targets ``(frames_per_control, nu)`` (rad) of its frames."""
        self._action = smoothed_action(action, self._action, self.config)
        self._push()
        ctrl = np.array(self._advance())  # a copy: the track is read-only
        ctrl[:, self.driven] += self._action
        return ctrl

    def _push(self) -> None:
        """Start, hold or end a random push of the pelvis (:attr:`pushes`) for this control step:
        its force (N, world) in ``data.xfrc_applied`` while it lasts, zero otherwise."""
        if self.pushes is None:
            return
        if self._push_steps_left == 0 and self.np_random.random() < self.pushes.rate_hz / self.config.control_rate_hz:
            self._push_steps_left = max(1, round(self.pushes.duration_s * self.config.control_rate_hz))
            angle = self.np_random.uniform(0.0, 2.0 * np.pi)
            self._push_force = self.np_random.uniform(*self.pushes.force_n) * np.array([np.cos(angle), np.sin(angle), 0.0])
        self.data.xfrc_applied[self._pelvis, :3] = self._push_force if self._push_steps_left > 0 else 0.0
        self._push_steps_left = max(0, self._push_steps_left - 1)

    def _advance(self) -> np.ndarray:
        """Advance the reference by one control step: the open-loop PD targets ``(frames_per_control,
        nu)`` (rad) of its frames, before the action is added (read only)."""
        if self._track is None:
            raise RuntimeError("call reset() before step()")
        start = self._frame + 1
        self._frame += self.config.frames_per_control
        return self._pd_targets(self._track, slice(start, self._frame + 1))

    def _blew_up(self) -> bool:
        """Whether the simulation went unstable in this step (MuJoCo's bad-acceleration warning, or a
        joint speed beyond ``config.max_joint_speed``)."""
        return self._bad_acceleration() or unstable(self.data.qvel, self.config.max_joint_speed)

    def _bad_acceleration(self) -> bool:
        """Whether MuJoCo warned of a bad acceleration since the episode began."""
        return self.data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > self._bad_qacc

    def _touch(self, touching: np.ndarray) -> int:
        """Record the simulated contacts from the floor-touching geoms ``touching`` (before the reward,
        which may read them) and return how many spinal bodies are on the floor."""
        self._sim_contacts = region_contacts(touching, self.humanoid.geom_contact_channel)
        return self._spinal_contacts(touching)

    def _step_info(self) -> dict:
        f = self._frame
        return {"frame": f, "episode_frame": f - self._start, "clip": self.clips[self._clip].name,
                "corrupted": self._variant >= 0, "artefact_seed": self._variant_seeds.get((self._clip, self._variant))}

    def _unstable_step(self):
        """The step's result when the simulation blew up: the episode ends (terminated, reward 0,
        the last good observation), ``info["ended_by"] == "unstable"``."""
        info = self._step_info()
        info.update(dict.fromkeys(self.reward_info_keys, 0.0), reward=0.0,
                    contacts=np.zeros(4, bool), unstable=True, ended_by="unstable")
        self._sampler.record(self._clip, self._start, failed=True)
        return self._obs.copy(), 0.0, True, False, info

    def _end_step(self, reward: float, terms: dict[str, float], obs: np.ndarray, spinal_contacts: int):
        """The step's result from its reward and terms (:meth:`_reward`), the new observation and the
        number of spinal bodies on the floor: the terminations, the failure sampler's record, ``info``."""
        cfg = self.config
        ended_by = ("lagging" if lagging(terms["e_discount"], cfg.discount_threshold)
                    else "fallen" if fallen(spinal_contacts, cfg.fall_contacts) else "")
        truncated = not ended_by and self._frame >= self.episode_end
        if ended_by or truncated:
            self._sampler.record(self._clip, self._start, failed=bool(ended_by))
        self._obs = obs
        info = self._step_info()
        info.update(terms, reward=reward, contacts=self._sim_contacts.copy(), unstable=False,
                    ended_by=ended_by or ("time_limit" if truncated else ""))
        if truncated:  # what an asymmetric critic values the last state with, before a vector env resets
            info["privileged_observation"] = self.privileged_observation()
        return obs, reward, bool(ended_by), truncated, info

    @property
    def max_step_reward(self) -> float:
        """The most one step's reward can be (ADAPT: 3, plus ``config.still_feet_weight`` and
        ``config.com_velocity_weight``; the MRR metric divides by it)."""
        return MAX_STEP_REWARD + self.config.still_feet_weight + self.config.com_velocity_weight

    reward_info_keys: tuple[str, ...] = tuple(RewardTerms.__dataclass_fields__)
    """The ``info`` entries :meth:`_reward` fills (all 0 after an unstable step); they include
    ``e_discount``, which the lag termination reads."""

    def _reward(self, state) -> tuple[float, dict[str, float]]:
        """Reward of the current frame and its terms for ``info`` (keys :attr:`reward_info_keys`),
        from the simulated body state (:class:`envs.bodies.BodyState`, current) and the running
        track: ADAPT's r = e_discount·(r_local + r_p + r_v) (adapt eq. 10), plus
        ``config.still_feet_weight``·r_still and ``config.com_velocity_weight``·r_com inside the bracket."""
        terms = self._tracking_terms(state, self._judge.frame(self._frame))
        return terms.total, terms.as_dict()

    def _tracking_terms(self, state, ref: ReferenceFrame) -> RewardTerms:
        """The reward terms of simulated body state(s) ``state`` against reference frame(s) ``ref``
        (one, or a batch with a leading axis on both): ADAPT's, r_still of the state's foot points
        (weighted by ``config.still_feet_weight``) and r_com of its CoM velocity against the
        reference's steered one (weighted by ``config.com_velocity_weight``)."""
        cfg = self.config
        b = self._foot_point_bodies
        feet, feet_vel = body_points(state.pos[..., b, :], state.axes[..., b, :, :], state.linvel[..., b, :],
                                     state.angvel[..., b, :], self._foot_point_offsets)
        return mimic_reward(
            rot.relative_to_parent(state.quat, self.parent)[..., self.jointed, :], ref.local,
            cube_face_points(state.pos - state.pos[..., :1, :], state.axes, cfg.cube_size_m), ref.faces_rel_root,
            cube_face_velocities(state.linvel, state.angvel, state.axes, cfg.cube_size_m), ref.face_vel,
            state.pos[..., self.head, :], ref.pos[..., self.head, :],
            still_feet_reward(feet_vel, feet[..., 2], cfg.still_feet_height_m, cfg.still_feet_alpha),
            cfg.alpha_local, cfg.alpha_p, cfg.alpha_v, cfg.still_feet_weight,
            com_velocity_reward(state.com_vel, ref.com_vel[..., :2] + steering_pull(
                state.com, ref.com, cfg.steer_gain_hz, cfg.steer_max_speed_mps), cfg.com_velocity_alpha),
            cfg.com_velocity_weight)

    @property
    def judging_track(self) -> ReferenceTrack:
        """The track the running episode's reward and terminations compare with (after
        :meth:`reset`): :attr:`current_track`, unless the env was given ``judged_clips`` or
        ``ArtefactMix.judge`` names another (:meth:`_judging_track`)."""
        if self._judge is None:
            raise RuntimeError("call reset() first")
        return self._judge

    @property
    def current_track(self) -> ReferenceTrack:
        """The reference track of the running episode (after :meth:`reset`)."""
        if self._track is None:
            raise RuntimeError("call reset() first")
        return self._track

    # ---------------------------------------------------------------- pieces
    def _observation_slices(self, n_bodies: int, n_action: int) -> dict[str, slice]:
        """Layout of the observation (:func:`envs.observations.observation_slices`); the observation
        space's size is the end of the last slice."""
        return observation_slices(n_bodies, n_action, com_offset=self.config.observes_com_offset,
                                  lookahead_steps=len(self.config.lookahead),
                                  lookbehind_steps=len(self.config.lookbehind))

    def _observe(self, state) -> np.ndarray:
        return self._tracking_observation(state, self._track.frame(self._frame), self._action, self._window(self._track))

    def observation_against(self, track: ReferenceTrack) -> np.ndarray:
        """The observation ``(D,)`` of the current simulated state against ``track`` at the running
        reference frame, with the running smoothed action: what a policy tracking ``track`` instead
        of :attr:`current_track` would observe now. A privileged teacher reads the clean take so
        while the policy in charge tracks its corrupted variant (``agents/distill.py
        --teacher-reads clean``, with ``track(clip, -1)``). ``track`` must be as long as the running
        track (a clip and its variants are, frame by frame)."""
        if self._track is None:
            raise RuntimeError("call reset() first")
        if track.n_frames != self._track.n_frames:
            raise ValueError(f"observation_against: the track has {track.n_frames} frames, the running track "
                             f"{self._track.n_frames}; it must be the running clip or one of its variants")
        state = read_body_state(self.model, self.data)
        return self._tracking_observation(state, track.frame(self._frame), self._action, self._window(track))

    def privileged_observation(self) -> np.ndarray:
        """What an asymmetric critic sees of the running episode now and the policy does not
        (:func:`envs.privileged.privileged_features`, ``(privileged_size,)``): the tracked reference's
        hidden corruption against the judged reference and the clean clip, and the episode's
        randomised body."""
        if self._track is None:
            raise RuntimeError("call reset() first")
        return privileged_features(self._track, self._judge, self.track(self._clip, -1), self._frame,
                                   self.config.frames_per_control, self.physics_draw)

    @property
    def privileged_size(self) -> int:
        """Length of :meth:`privileged_observation`."""
        return privileged_size(self.model.nu, self.model.nbody)

    @property
    def clip_index(self) -> int:
        """Index in :attr:`clips` of the running episode's clip (after :meth:`reset`)."""
        if self._track is None:
            raise RuntimeError("call reset() first")
        return self._clip

    @property
    def variant_index(self) -> int:
        """The running episode's track variant (after :meth:`reset`): -1 for the clip as given, else
        its corrupted variant (:meth:`track`'s ``variant``)."""
        if self._track is None:
            raise RuntimeError("call reset() first")
        return self._variant

    def _window(self, track: ReferenceTrack) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """What the observation's ``lookahead`` and ``lookbehind`` read of ``track``
        (:attr:`~envs.config.MimicConfig.window_steps` control steps from the current frame,
        clamped to the track's first and last frames): the reference CoM ``(K, 3)``, its velocity
        ``(K, 3)`` and the observed body origins relative to it ``(K, B, 3)`` (world); ``None``
        without either."""
        steps = self.config.window_steps
        if not steps:
            return None
        frames = np.clip(self._frame + self.config.frames_per_control * np.asarray(steps), 0, track.n_frames - 1)
        return track.com[frames], track.com_vel[frames], track.pos_rel_com[frames][:, self.observed]

    def _tracking_observation(self, state, ref: ReferenceFrame, action: np.ndarray,
                              window: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> np.ndarray:
        """The mimic observation of body state(s) ``state`` against reference frame(s) ``ref`` with the
        smoothed action(s) ``action`` (one, or a batch with a leading axis on each), and with
        ``config.lookahead`` or ``config.lookbehind`` the reference around now, ``window``
        (:meth:`_window`, with the same leading axes)."""
        obs = self.observed
        heading = None
        if self.config.obs_frame == "heading":
            heading = heading_rotation(state.axes[..., 0, 0, :])
        elif self.config.obs_frame == "reference":
            heading = ref.to_heading
        ref_com_vel, ref_linvel = steered_velocities(state.com, ref.com, ref.com_vel, ref.linvel[..., obs, :],
                                                     self.config.steer_gain_hz, self.config.steer_max_speed_mps)
        observation = mimic_observation(state.pos[..., obs, :], state.linvel[..., obs, :], state.com, state.com_vel,
                                        ref.pos_rel_com[..., obs, :], ref_linvel, ref_com_vel, action,
                                        heading, ref.com if self.config.observes_com_offset else None)
        if not self.config.window_steps:
            return observation
        if window is None:
            raise ValueError("config.lookahead or lookbehind is set: the observation needs the reference around now "
                             "(window)")
        return np.concatenate([observation, lookahead_observation(ref.com, *window, heading)], axis=-1)

    def _spinal_contacts(self, touching: np.ndarray) -> int:
        """Number of spinal bodies among the bodies of the floor-touching geoms ``touching``."""
        return bodies_touching(touching, self._geom_spinal_body)

    # ---------------------------------------------------------------- render
    def render(self):
        if self.render_mode != "rgb_array":
            return None
        if self._track is None:
            raise RuntimeError("call reset() before render()")
        if self._renderer is None:
            self._renderer = GhostRenderer(self.model, *self._size)
        return self._renderer.render(self.data, self._track.motion.qpos[self._frame])

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def actuator_qpos(model: mujoco.MjModel) -> np.ndarray:
    """``(nu,)`` qpos index of each actuator's hinge."""
    return model.jnt_qposadr[model.actuator_trnid[:, 0]]


def driven_actuators(humanoid: HumanoidModel, action_mode: str) -> np.ndarray:
    """Actuator index ``(A,)`` of each action component of ``action_mode`` on ``humanoid``: the hinges
    of :data:`envs.config.ACTION_BODIES` ``[action_mode]`` in that order, or every actuator
    (``"full"``)."""
    _check_choice("action_mode", action_mode, ACTION_MODES)
    if action_mode not in ACTION_BODIES:
        return np.arange(humanoid.model.nu)
    actuator_of_qpos = {int(q): a for a, q in enumerate(actuator_qpos(humanoid.model))}
    return np.array([actuator_of_qpos[int(q)] for b in ACTION_BODIES[action_mode]
                     for q in humanoid.body_joints[b].qpos_index])


def smoothed_action(action: np.ndarray, previous: np.ndarray, config: MimicConfig) -> np.ndarray:
    """The action the PD targets get: the policy's ``action`` (rad, ``(..., A)``; one environment's or
    a batch's) clipped to ``±config.action_limit_rad`` and smoothed with the ``previous`` one
    (``config.action_smoothing``: weight of the new action)."""
    lim = config.action_limit_rad
    raw = np.minimum(np.maximum(np.asarray(action, dtype=float), -lim), lim)
    return config.action_smoothing * raw + (1.0 - config.action_smoothing) * previous


@dataclass(frozen=True)
class _TrackPlan:
    """How one reference track of a :class:`MimicEnv` is made (:meth:`MimicEnv.track`): ``given`` (a
    clip, or the motion it is judged against) corrupted with ``corruption`` (``(recipe, seed)``, or
    ``None``), passed through ``denoiser`` (its corrections slowed to ``slow_s`` s) and prepared with
    ``steps``. ``reference_key`` is the content that prepared reference is kept by in
    :data:`envs.track_cache.REFERENCES` (model, clip content, corruption, denoiser and its slowing,
    preparation steps; clip names are not part of it: an env reports its own clip's name);
    ``track_key``, that plus the cube size, which only the track depends on, in
    :data:`envs.track_cache.TRACKS`."""

    given: Motion
    corruption: tuple | None
    denoiser: str | None
    slow_s: float | None
    steps: PreparationSteps
    reference_key: tuple
    track_key: tuple


def _state_parts(state: Sequence, nq: int, nv: int, n_act: int) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """``(qpos, qvel, action or None)`` of reset option ``state`` (``(qpos, qvel)`` or ``(qpos, qvel,
    action)``), checked: shapes ``(nq,)``, ``(nv,)``, ``(n_act,)``, all finite."""
    expected = f"(qpos ({nq},), qvel ({nv},)[, action ({n_act},)]) finite arrays"
    if not isinstance(state, (tuple, list)) or len(state) not in (2, 3):
        raise ValueError(f"reset option 'state' must be {expected}")
    shapes = [np.shape(x) for x in state]
    if shapes != [(nq,), (nv,), (n_act,)][:len(state)] or not all(np.all(np.isfinite(x)) for x in state):
        raise ValueError(f"reset option 'state' must be {expected}; got shapes {shapes}")
    return np.asarray(state[0]), np.asarray(state[1]), state[2] if len(state) == 3 else None


def _content_key(motion: Motion) -> str:
    """A key of ``motion``'s content: two clips with the same key have the same frames, rate and model."""
    digest = hashlib.blake2b(np.ascontiguousarray(motion.qpos).tobytes(), digest_size=16).hexdigest()
    return f"{motion.model}:{motion.fps:g}:{digest}"


def _check_choice(name: str, value: str, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(repr(c) for c in choices)}, got {value!r}")
