"""``MimicGait-v0``: ContactVision's gait reconstruction (contactvision §6.4, App. C) on ``humanoid_2seg``
(or, as ContactVision's ablation, ``humanoid_1seg``).

The task is the ADAPT mimic task of :class:`envs.mimic.MimicEnv` (clips, reference tracks,
episode sampling, reset options, PD control at 60 Hz frames / 30 Hz policy steps, contacts,
unstable handling) with ContactVision's three additions:

- **contact targets** ĉ ``(T, 4)`` per clip, in (left_toe, right_toe, left_heel, right_heel)
  order: from VGRFNet + Γ on the reference's joints (``contacts="vgrf"``), from the
  ContactTransformer on 2D keypoints (``"keypoints"``: the reference filmed from the side, or a
  keypoint ``.npz`` of the video front end), or given as arrays (:func:`contact_targets`);
- **toe targets** ``(T, 2)`` (rad; left, right) from the ToeRefEstimator of ĉ
  (:func:`perception.gait.toe_reference_angles`), added to the reference angle of each toe hinge:
  the clip with its toes so bent is the *gait reference* the character mimics (PD targets, the
  pose reward, reference state initialisation, the rendered ghost);
- the reward R = Σ_k w_k r_k of contactvision eq. 6 (:func:`envs.rewards.gait_reward`, constants
  in :class:`envs.config.GaitConfig`), whose r_fc counts the channels where the simulated contacts
  differ from ĉ.

Perception (and with it torch) is imported only when contacts are estimated, so ``import envs``
stays light.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from envs.config import (CONTACT_MODES, DEFAULT_CONTACT_NET, DEFAULT_VGRF_NET, TOE_BODIES, ArtefactMix, GaitConfig,
                         MimicConfig)
from envs.mimic import ClipSpec, MimicEnv, shipped_network
from envs.observations import gait_observation, gait_observation_slices
from envs.rewards import (GAIT_TERMS, contact_reward, end_effector_reward, fall_discount, gait_reward,
                          joint_pose_reward, joint_velocity_reward, root_orientation_reward, torque_reward,
                          upper_body_reward, upper_body_tilt)
from envs.sampling import SamplingConfig
from reference_motion.motion import Motion, read_npz

ContactSpec = str | Path | np.ndarray
"""One clip's contact targets: ``"vgrf"``, ``"keypoints"``, a keypoint ``.npz`` path, or a
``(T, 4)`` bool array."""

_SPEC_HELP = ("expected 'vgrf', 'keypoints', a keypoint .npz file (keypoints, fps), or a (frames, 4) bool array "
              "of (left_toe, right_toe, left_heel, right_heel) contacts; a list gives one per clip")


# --------------------------------------------------------------------------- contact targets
def vgrf_contacts(motion: Motion, vgrf_net: str | Path = DEFAULT_VGRF_NET) -> np.ndarray:
    """Contacts ``(T, 4)`` bool (LT, RT, LH, RH) of ``motion``: VGRFNet's insole vGRF of its 23
    UnderPressure joints, through the contact function Γ (as ``python -m perception contacts``)."""
    from perception.contacts import ContactFunction
    from perception.skeleton import motion_joint_positions
    from perception.vgrf import estimate
    forces = estimate(shipped_network(vgrf_net, "vgrf"), motion_joint_positions(motion))
    return ContactFunction()(forces, motion.fps)


def keypoint_contacts(motion: Motion, contact_net: str | Path = DEFAULT_CONTACT_NET,
                      azimuth_deg: float = 90.0) -> np.ndarray:
    """Contacts ``(T, 4)`` bool (LT, RT, LH, RH) of ``motion`` seen by the ContactTransformer in
    2D: its 13 lower-body keypoints filmed by a camera that follows the pelvis at ContactVision's
    rig distance and height (4 m, 1 m; 1000 px), from direction ``azimuth_deg`` (degrees from +x
    towards +y), without detector noise or dropped points."""
    from perception.contact_transformer import detect_contacts
    from perception.keypoints import follow_camera, motion_keypoints, observe
    points = motion_keypoints(motion)
    camera = follow_camera(points[:, 0], math.radians(azimuth_deg))
    keypoints = observe(points, camera, np.random.default_rng(0), noise_px=0.0, drop_prob=0.0)
    return detect_contacts(shipped_network(contact_net, "keypoints"), keypoints, motion.fps)


def keypoint_file_contacts(path: str | Path, motion: Motion, contact_net: str | Path = DEFAULT_CONTACT_NET) -> np.ndarray:
    """Contacts ``(T, 4)`` bool for ``motion``'s frames from a keypoint ``.npz`` (``keypoints``
    ``(N, 13, 3)`` = pixels and confidence, ``fps``; what ``python -m perception gait VIDEO
    --keypoints-out`` writes): the ContactTransformer's contacts at the file's frame rate, read at
    the clip's frame times (nearest frame). The file must cover the clip's duration."""
    data = read_npz(path, "keypoint")
    if "keypoints" not in data or "fps" not in data:
        raise ValueError(f"{path}: a keypoint file needs the fields 'keypoints' and 'fps', has {sorted(data)}")
    keypoints, fps = data["keypoints"], float(data["fps"])
    if not (np.isfinite(fps) and fps > 0):
        raise ValueError(f"{path}: fps must be positive, got {fps}")
    covered, needed = (len(keypoints) - 1) / fps, motion.duration
    if abs(covered - needed) > 1.0 / min(fps, motion.fps):
        raise ValueError(f"{path}: the keypoints cover {covered:.2f} s ({len(keypoints)} frames at {fps:g} Hz) but clip "
                         f"{motion.name!r} lasts {needed:.2f} s; give the keypoints of that clip's video")
    from perception.contact_transformer import detect_contacts
    contacts = detect_contacts(shipped_network(contact_net, "keypoints"), keypoints, fps)
    at = np.clip(np.round(np.arange(motion.n_frames) / motion.fps * fps).astype(int), 0, len(contacts) - 1)
    return contacts[at]


def checked_contacts(array: np.ndarray, motion: Motion) -> np.ndarray:
    """``array`` as ``(T, 4)`` bool contact targets of ``motion`` (T its frames), or a
    ``ValueError`` saying what shape and values are expected."""
    arr = np.asarray(array)
    if arr.shape != (motion.n_frames, 4):
        raise ValueError(f"contacts for clip {motion.name!r} must have shape ({motion.n_frames}, 4): one row per frame of "
                         f"the clip as loaded ({motion.n_frames} frames at {motion.fps:g} Hz), columns (left_toe, "
                         f"right_toe, left_heel, right_heel); got {arr.shape}")
    if arr.dtype != bool and not np.isin(arr, (0, 1)).all():
        raise ValueError(f"contacts for clip {motion.name!r} must be bool or 0/1, got values such as "
                         f"{arr[~np.isin(arr, (0, 1))].flat[0]!r}")
    return arr.astype(bool)


def contact_source(spec: ContactSpec) -> str:
    """What kind of contact targets ``spec`` names: ``"array"``, ``"vgrf"``, ``"keypoints"`` or
    ``"keypoint_file"``; a ``ValueError`` listing the choices for anything else."""
    if isinstance(spec, np.ndarray):
        return "array"
    if isinstance(spec, str) and spec in CONTACT_MODES:
        return spec
    if isinstance(spec, (str, Path)) and str(spec).endswith(".npz"):
        return "keypoint_file"
    raise ValueError(f"unknown contacts mode {spec!r}; {_SPEC_HELP}")


def contact_targets(spec: ContactSpec, motion: Motion, vgrf_net: str | Path = DEFAULT_VGRF_NET,
                    contact_net: str | Path = DEFAULT_CONTACT_NET, azimuth_deg: float = 90.0) -> np.ndarray:
    """The contact targets ĉ ``(T, 4)`` bool (LT, RT, LH, RH) of ``motion`` from ``spec``:
    ``"vgrf"`` (:func:`vgrf_contacts`), ``"keypoints"`` (:func:`keypoint_contacts` from
    ``azimuth_deg``), a keypoint ``.npz`` path (:func:`keypoint_file_contacts`) or an array
    (:func:`checked_contacts`)."""
    source = contact_source(spec)
    if source == "array":
        return checked_contacts(spec, motion)
    if source == "vgrf":
        return vgrf_contacts(motion, vgrf_net)
    if source == "keypoints":
        return keypoint_contacts(motion, contact_net, azimuth_deg)
    return keypoint_file_contacts(spec, motion, contact_net)


def per_clip_specs(contacts: ContactSpec | Sequence[ContactSpec], n_clips: int) -> list[ContactSpec]:
    """One contact spec per clip: a list or tuple is taken as one per clip; ``"vgrf"`` and
    ``"keypoints"`` apply to every clip; an array or a keypoint file fits a single clip only."""
    if isinstance(contacts, (list, tuple)):
        if len(contacts) != n_clips:
            raise ValueError(f"contacts is a list of {len(contacts)}, but the env has {n_clips} clips; give one per clip")
        for spec in contacts:
            contact_source(spec)
        return list(contacts)
    if contact_source(contacts) in CONTACT_MODES:
        return [contacts] * n_clips
    if n_clips != 1:
        raise ValueError(f"one contacts array or keypoint file fits one clip, but the env has {n_clips} clips; "
                         "give a list with one per clip")
    return [contacts]


def with_toe_targets(motion: Motion, toe_qpos: Sequence[int], toe_targets: np.ndarray) -> Motion:
    """The gait reference: ``motion`` with ``toe_targets (T, 2)`` (rad; left, right) added to its
    toe hinges at qpos columns ``toe_qpos`` (left, right). The name is kept."""
    qpos = motion.qpos.copy()
    qpos[:, list(toe_qpos)] += toe_targets
    return motion.with_qpos(qpos)


# --------------------------------------------------------------------------- environment
class MimicGaitEnv(MimicEnv):
    """Mimic clips on ``humanoid_2seg`` (or ``humanoid_1seg``) while following contact and toe
    targets (``MimicGait-v0``).

    Args:
        clips: the motion set, as for :class:`envs.mimic.MimicEnv` (named set, SOURCE strings or
            paths, :class:`Motion` objects for the ``foot`` model).
        contacts: the contact targets ĉ: ``"vgrf"`` (default; VGRFNet + Γ on each clip's joints),
            ``"keypoints"`` (the ContactTransformer on the clip's 2D keypoints, filmed from
            ``gait.keypoint_azimuth_deg``), a keypoint ``.npz`` path (keypoints of the clip's video,
            e.g. from ``python -m perception gait VIDEO --keypoints-out``), a ``(T, 4)`` bool array
            (T = frames of the clip as loaded: ``env.unwrapped.clips[i].n_frames``), or a list with
            one of these per clip. Targets are found once per clip, on the clip as given, and
            serve its corrupted variants too.
        artefacts: IMU-corrupted references (:class:`envs.config.ArtefactMix`); ``None`` (default)
            mimics the clips as given.
        foot: ``"two"`` (default, ``humanoid_2seg``: the toe hinges are what the task is about) or
            ``"one"`` (``humanoid_1seg``, ContactVision's one-segment-foot ablation: the same
            reward, which then has no toe hinges in r_q and r_v, and toe targets of 0).
        episode_frames: longest episode in reference frames (default 300 = 5 s at 60 Hz).
        obs_mode: ``"adapt"`` (all 22 bodies) or ``"drecon"`` (key bodies), as ``MimicEnv``.
        action_mode: ``"key_toes"`` (the 8 key joints and both toe hinges, 22 values; the default
            with ``foot="two"``), ``"key"`` (toes open loop on their targets; the default with
            ``foot="one"``) or ``"full"`` (every hinge).
        config: timing, action, termination constants (:class:`envs.config.MimicConfig`; its
            ADAPT reward scales are unused here).
        gait: reward weights and scales, preview length, keypoint view (:class:`envs.config.GaitConfig`).
        sampling: episode starts (:class:`envs.sampling.SamplingConfig`).
        render_mode: ``None`` or ``"rgb_array"`` (the gait reference, toes bent, as the ghost).
        width, height: rendered image size (pixels).
        vgrf_net: the VGRFNet of ``contacts="vgrf"`` (a shipped network folder; default ``models/vgrf``).
        contact_net: the ContactTransformer of keypoint contacts (default ``models/contact_transformer``).
        judged_clips: refused (``MimicEnv``'s; a gait episode is judged against its own clip).

    Observation: ``Box(13 + 12·B + A + 6·P + 4,)`` float32 (B bodies, A action size, P =
    ``gait.preview_frames``): the mimic observation, the contact and toe targets of the next P
    frames, the simulated contacts (:func:`envs.observations.gait_observation_slices`; 327 with
    the defaults). Action: ``Box(−1, 1, (A,))`` rad offsets added to the gait reference's PD
    targets of the driven hinges (smoothed, β = 0.2).

    Reward: R = 0.3 r_q + 0.05 r_v + 0.05 r_e + 0.3 r_fc + 0.1 r_up + 0.15 r_root_ori +
    0.05 r_torque ≤ 1 (contactvision eq. 6), evaluated at the last frame of each policy step:
    r_q on all hinge angles against the gait reference, r_v on their rates, r_e on hands and
    feet relative to the pelvis, r_fc on ĉ against the simulated contacts, r_up on the
    pelvis→head tilt against the reference's, r_root_ori on the pelvis z axis against the
    vertical, r_torque on the actuator torques over their limits.

    Terminations (as ``MimicEnv``): fallen (3+ spinal bodies on the floor), lagging (the head
    0.91 m from the reference's: e_discount < 0.025), unstable; truncation at the episode's end.

    ``reset(options=...)``: ``clip``, ``start_frame``, ``corrupted``, ``state`` as ``MimicEnv``.

    ``info``: each reward term (``r_q`` … ``r_torque``), ``total`` = ``reward``, ``e_discount``;
    ``contacts`` (the simulated ones, 4 bools LT, RT, LH, RH), ``contact_targets`` (ĉ of the
    frame) and ``toe_targets`` (rad; left, right); and ``frame``, ``episode_frame``, ``clip``,
    ``corrupted``, ``artefact_seed``, ``unstable``, ``ended_by`` as ``MimicEnv``.
    """

    reward_info_keys = GAIT_TERMS + ("total", "e_discount")

    @property
    def max_step_reward(self) -> float:
        """The most R can be: the sum of the weights (1 with ContactVision's), each term being ≤ 1."""
        return float(sum(self.gait_config.weights.values()))

    def __init__(self, clips: str | Sequence[ClipSpec] = "locomotion",
                 contacts: ContactSpec | Sequence[ContactSpec] = "vgrf", artefacts: ArtefactMix | None = None,
                 foot: str = "two", episode_frames: int | None = None, obs_mode: str = "adapt",
                 action_mode: str | None = None, config: MimicConfig | None = None, gait: GaitConfig | None = None,
                 sampling: SamplingConfig = SamplingConfig(), render_mode: str | None = None, width: int = 480,
                 height: int = 360, vgrf_net: str | Path = DEFAULT_VGRF_NET,
                 contact_net: str | Path = DEFAULT_CONTACT_NET, judged_clips: Sequence[ClipSpec] | None = None):
        if judged_clips is not None:
            raise ValueError("MimicGait-v0 takes no judged_clips: its reward compares the simulation with the clips "
                             "it follows and their contact targets")
        if config is not None and config.window_steps:
            raise ValueError(f"MimicGait-v0 previews its contact and toe targets instead (GaitConfig.preview_frames); "
                             f"MimicConfig.lookahead and lookbehind must be empty, got {config.lookahead} and "
                             f"{config.lookbehind}")
        if config is not None and (config.still_feet_weight or config.com_velocity_weight):
            raise ValueError(f"MimicGait-v0 has ContactVision's own reward (GaitConfig), without the still-feet and "
                             f"CoM-velocity terms; MimicConfig.still_feet_weight and com_velocity_weight must be 0, got "
                             f"{config.still_feet_weight} and {config.com_velocity_weight}")
        if foot not in ("one", "two"):
            raise ValueError(f"MimicGait-v0: foot must be 'two' (humanoid_2seg, toe hinges following the "
                             f"ToeRefEstimator) or 'one' (the one-segment-foot ablation), got {foot!r}")
        if action_mode is None:
            action_mode = "key_toes" if foot == "two" else "key"
        if gait is not None and not isinstance(gait, GaitConfig):
            raise TypeError(f"gait must be an envs.GaitConfig or None, got {type(gait).__name__}")
        self.gait_config = gait or GaitConfig()
        for spec in contacts if isinstance(contacts, (list, tuple)) else [contacts]:
            contact_source(spec)  # fail before the clips load
        self._contacts_arg = contacts
        self._nets = (vgrf_net, contact_net)
        self.contact_targets: list[np.ndarray] = []
        """Per clip: the contact targets ĉ ``(T, 4)`` bool (LT, RT, LH, RH)."""
        self.toe_targets: list[np.ndarray] = []
        """Per clip: the ToeRefEstimator's angles ``(T, 2)`` (rad; left, right) of ĉ (zeros with
        ``gait.toe_reference=False`` or ``foot="one"``)."""
        super().__init__(clips, artefacts, foot, episode_frames, obs_mode, action_mode, config, sampling,
                         render_mode, width, height)
        m, names = self.model, self.humanoid.body_names
        unknown = [b for b in self.gait_config.end_effectors if b not in names]
        if unknown:
            raise ValueError(f"GaitConfig.end_effectors {unknown} are not bodies of {self.humanoid.name}")
        self.end_effectors = np.array([names.index(b) for b in self.gait_config.end_effectors])
        self.hinge_dof = m.jnt_dofadr[m.actuator_trnid[:, 0]]
        """qvel index of each actuator's hinge."""
        self.torque_limit = np.abs(m.actuator_forcerange).max(axis=1)
        """Each actuator's force limit (N·m): r_torque reads the torques as fractions of it."""
        self._preview = np.arange(1, self.gait_config.preview_frames + 1)

    def _load_clips(self, clips: str | Sequence[ClipSpec]) -> list[Motion]:
        """The clips as :class:`MimicEnv` loads them, their contact and toe targets, and the gait
        references (the clips with their toes bent by the toe targets) that the env then mimics."""
        motions = super()._load_clips(clips)
        specs = per_clip_specs(self._contacts_arg, len(motions))
        vgrf_net, contact_net = self._nets
        azimuth = self.gait_config.keypoint_azimuth_deg
        self.contact_targets = [contact_targets(s, mo, vgrf_net, contact_net, azimuth) for s, mo in zip(specs, motions)]
        if not self.gait_config.toe_reference or not all(b in self.humanoid.body_joints for b in TOE_BODIES):
            self.toe_targets = [np.zeros((len(c), 2)) for c in self.contact_targets]
            return motions  # toes held straight, or no toes to bend
        from perception.gait import toe_reference_angles  # numpy only: no torch
        self.toe_targets = [toe_reference_angles(c) for c in self.contact_targets]
        toe_qpos = [int(self.humanoid.body_joints[b].qpos_index[0]) for b in TOE_BODIES]
        return [with_toe_targets(mo, toe_qpos, toe) for mo, toe in zip(motions, self.toe_targets)]

    # ----------------------------------------------------------------- hooks
    def _observation_slices(self, n_bodies: int, n_action: int) -> dict[str, slice]:
        return gait_observation_slices(n_bodies, n_action, self.gait_config.preview_frames,
                                       com_offset=self.config.observes_com_offset)

    def _observe(self, state) -> np.ndarray:
        ahead = np.minimum(self._frame + self._preview, len(self.contact_targets[self._clip]) - 1)
        return gait_observation(super()._observe(state), self.contact_targets[self._clip][ahead],
                                self.toe_targets[self._clip][ahead], self._sim_contacts)

    def _reward(self, state) -> tuple[float, dict[str, float]]:
        """ContactVision's R (eq. 6) of the current frame, its terms, and e_discount (for the lag
        termination)."""
        g, d, track, f = self.gait_config, self.data, self._judge, self._frame
        ee, head = self.end_effectors, self.head
        terms = {
            "r_q": joint_pose_reward(d.qpos[self.actuator_qpos], track.ctrl[f], g.alpha_q),
            "r_v": joint_velocity_reward(d.qvel[self.hinge_dof], track.qvel[f, self.hinge_dof], g.alpha_v),
            "r_e": end_effector_reward(state.pos[ee], state.pos[0], track.pos[f, ee], track.pos[f, 0], g.alpha_e),
            "r_fc": contact_reward(self.contact_targets[self._clip][f], self._sim_contacts, g.alpha_fc),
            "r_up": upper_body_reward(upper_body_tilt(state.pos[0], state.pos[head]),
                                      upper_body_tilt(track.pos[f, 0], track.pos[f, head]), g.alpha_up),
            "r_root_ori": root_orientation_reward(state.axes[0, 2], g.alpha_root_ori),
            "r_torque": torque_reward(d.actuator_force / self.torque_limit, g.alpha_torque),
        }
        result = gait_reward(terms, g.weights)
        return result.total, {**result.as_dict(), "e_discount": fall_discount(state.pos[head], track.pos[f, head])}

    def _targets_info(self) -> dict[str, np.ndarray]:
        f = self._frame
        return {"contact_targets": self.contact_targets[self._clip][f].copy(),
                "toe_targets": self.toe_targets[self._clip][f].copy()}

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        obs, info = super().reset(seed=seed, options=options)
        info.update(self._targets_info())
        return obs, info

    def step(self, action: np.ndarray):
        obs, reward, terminated, truncated, info = super().step(action)
        info.update(self._targets_info())
        return obs, reward, terminated, truncated, info
