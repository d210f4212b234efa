"""Footskate cleanup guided by the vGRF network (underpressure §6) on a :class:`Motion`.

1. Ψ estimates the clip's cell vGRF F̃ and Γ turns them into contacts C (CONTACT_CHANNELS order).
2. Each contact phase of a channel pins that channel's *contact joint* (the sole point under the
   ball or the heel, :class:`~perception.kinematics.TorchKinematics`) to one position
   (:func:`contact_targets`); off the floor the contact joints follow their input path shifted by
   their foot's interpolated correction (:func:`foot_targets`).
3. Hinge angles, root position and root quaternion are optimised with L-BFGS for
   ``L = ω_q L_quat + ω_f L_foot + ω_t L_traj + ω_v L_vGRF + ω_p L_pose + ω_l L_limit + L_smooth``:
   L_quat keeps the root quaternion unit-norm (eq. 3); L_foot pulls contact joints to their
   targets, weighted by a rectangular window with smoothed edges (eq. 4) that is raised to
   ``swing_weight`` off the floor; L_traj keeps the root's speed profile (eq. 5); L_vGRF keeps
   Ψ's estimate of the edited motion equal to F̃ (eq. 6); L_pose keeps the 23 joints near their
   input positions; L_limit keeps hinges in their ranges; L_smooth keeps the edit smooth in time.

Departures from the paper, measured in the README (``bench/footskate_cleanup.py``): per-foot pins
that a rigid foot can meet; targets between contacts (without them the foot jumps where a contact
begins or ends, and that jump is foot skate too); L_pose, which makes the legs, not the whole
body, absorb a drifting root; and L_limit and L_smooth, which keep those leg edits anatomical and
free of jitter. Weights are ours (see :class:`CleanupConfig`): the
paper's (ω_q 1e-3, ω_f 1e-5, ω_t 1e2, ω_v 5e-5) go with its units and sums, which it does not state.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import torch
from torch import nn

from perception.contacts import ContactFunction
from perception.kinematics import torch_kinematics
from perception.vgrf import msle
from reference_motion.footskate import contact_windows
from reference_motion.humanoid.model import FOOT_CHANNELS, load_model
from reference_motion.motion import Motion
from reference_motion.quality import horizontal_speed


@dataclass(frozen=True)
class CleanupConfig:
    """Settings of :func:`cleanup`.

    Attributes:
        iterations: L-BFGS iterations (UnderPressure: N = 100 gradient steps; on our held-out IMU
            clips at strength 1, 100 → −83% at 2.9 cm of joint displacement, 300 → −84% at 2.6 cm).
        w_quat, w_foot, w_traj, w_vgrf: loss weights of eqs. 3–6 (means over frames, SI units).
        w_pose: weight of L_pose, the mean squared displacement (m²) of the 23 joints from the
            input. It sets the trade between skate removed and motion kept: on the held-out IMU
            clips at strength 1, 300 → −89% at 3.2 cm, 700 → −84% at 2.6 cm, 1000 → −80% at 2.3 cm.
        edge_s: duration of the smoothed ramps at both ends of a contact window.
        swing_weight: weight of L_foot on frames where a contact joint is off the floor (1 in contact).
        w_limit: weight of L_limit, the squared excursion (rad²) of the hinges beyond their MJCF
            ranges (without it the legs bend through the knee and ankle limits).
        w_smooth, w_smooth_legs: weights of L_smooth, the squared second difference (m², rad² per
            frame²) of the *edit* ``q − q̃``: for the root position and the hinges above the hips,
            and for the leg hinges. Legs get a weaker one because cancelling per-frame hinge noise
            under a planted foot takes a per-frame edit; elsewhere an unsmoothed edit adds jitter
            (spine jerk ×10 on a skating walk).
    """

    iterations: int = 300
    w_quat: float = 1.0
    w_foot: float = 1000.0
    w_traj: float = 1.0
    w_vgrf: float = 1.0
    w_pose: float = 700.0
    edge_s: float = 0.05
    swing_weight: float = 0.1
    w_limit: float = 1000.0
    w_smooth: float = 300.0
    w_smooth_legs: float = 10.0

    def __post_init__(self) -> None:
        if self.iterations < 1:
            raise ValueError(f"cleanup iterations must be at least 1, got {self.iterations}")
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name != "iterations" and not (np.isfinite(value) and value >= 0):
                raise ValueError(f"cleanup setting {f.name} must be a finite number >= 0, got {value}")
        if self.swing_weight > 1:
            raise ValueError(f"cleanup setting swing_weight must be in [0, 1], got {self.swing_weight}")


@dataclass
class CleanupResult:
    """The cleaned motion, the contacts used, and the before/after measurements.

    Attributes:
        motion: the cleaned clip.
        contacts: ``(T, 4)`` contacts from Ψ and Γ on the input.
        soles_before, soles_after: ``(T, 4, 3)`` world positions (m) of the contact joints in the
            input and in the output, CONTACT_CHANNELS order.
        joint_shift_m: mean displacement of the 23 joints between input and output (m).
    """

    motion: Motion
    contacts: np.ndarray
    soles_before: np.ndarray
    soles_after: np.ndarray
    joint_shift_m: float

    @property
    def foot_speed_before(self) -> float:
        """Mean horizontal speed (m/s) of the contact joints over their contact frames in the input
        (UnderPressure's footskate measure)."""
        return contact_speed(self.soles_before, self.contacts, self.motion.fps)

    @property
    def foot_speed_after(self) -> float:
        """The same in the output."""
        return contact_speed(self.soles_after, self.contacts, self.motion.fps)


def contact_weights(contacts: np.ndarray, edge_frames: int) -> np.ndarray:
    """Per-frame weights ``(T, 4)`` in [0, 1]: 1 inside each contact phase, smoothstep ramps over
    its first and last ``edge_frames`` frames, 0 outside (the Π of underpressure eq. 4)."""
    out = np.zeros(contacts.shape)
    for c in range(contacts.shape[1]):
        for start, stop in contact_windows(contacts[:, c]):
            n = stop - start
            k = np.arange(n)
            ramp = np.minimum(np.minimum(k + 1, n - k) / max(edge_frames, 1), 1.0)
            out[start:stop, c] = ramp * ramp * (3 - 2 * ramp)
    return out


def contact_targets(soles: np.ndarray, contacts: np.ndarray) -> np.ndarray:
    """Pin positions ``(T, 4, 3)`` for the sole points ``(T, 4, 3)`` in CONTACT_CHANNELS order;
    NaN outside contact.

    Each foot's heel and toe pins come from one foot placement, so a rigid foot can meet both: in
    every run of frames where a foot touches the floor, its longest contact phase is pinned at its
    mean position, and each other phase overlapping it at that pin plus the phase's mean offset from
    the pinned point over their common frames. (Separate means would sit a slide's length apart:
    the toe's mean is taken later in the step than the heel's.) A phase that overlaps no other is
    pinned at its own mean. (Moving the pins to the floor would also remove floating and
    penetration, at the price of shifting the whole body; that is the physics cleanup's job,
    :mod:`agents.clean`.)
    """
    out = np.full(soles.shape, np.nan)
    for foot in FOOT_CHANNELS:
        for start, stop in contact_windows(contacts[:, list(foot)].any(axis=1)):
            phases = [(c, start + a, start + b) for c in foot for a, b in contact_windows(contacts[start:stop, c])]
            main, m0, m1 = max(phases, key=lambda phase: phase[2] - phase[1])
            pin = soles[m0:m1, main].mean(axis=0)
            for c, a, b in phases:
                lo, hi = max(a, m0), min(b, m1)
                if c == main or lo >= hi:
                    out[a:b, c] = soles[a:b, c].mean(axis=0)
                else:
                    out[a:b, c] = pin + (soles[lo:hi, c] - soles[lo:hi, main]).mean(axis=0)
    return out


def foot_targets(soles: np.ndarray, pins: np.ndarray) -> np.ndarray:
    """Targets ``(T, 4, 3)`` for the sole points ``(T, 4, 3)`` on every frame: the ``pins``
    (:func:`contact_targets`) where a point is in contact; elsewhere its input position moved by
    its foot's correction. A foot's correction is the mean ``pin − input`` of its points in contact
    on frames where it touches the floor, interpolated linearly in between (held before its first
    and after its last contact), so the foot is carried along and does not jump where a contact
    begins or ends (Kovar et al. 2002). A foot never in contact keeps its input path."""
    out = soles.copy()
    frames = np.arange(len(soles))
    for foot in FOOT_CHANNELS:
        pinned = ~np.isnan(pins[:, foot, 0])                                    # (T, 2)
        touching = np.flatnonzero(pinned.any(axis=1))
        if touching.size:
            offsets = np.where(pinned[..., None], pins[:, foot] - soles[:, foot], 0.0)[touching]
            correction = offsets.sum(axis=1) / pinned[touching].sum(axis=1, keepdims=True)
            shift = np.stack([np.interp(frames, touching, correction[:, k]) for k in range(3)], axis=-1)
            out[:, foot] += shift[:, None]
    contact = ~np.isnan(pins)
    out[contact] = pins[contact]
    return out


def contact_speed(soles: np.ndarray, contacts: np.ndarray, fps: float) -> float:
    """Mean horizontal speed (m/s) of sole points ``(T, 4, 3)`` over frames in ``contacts (T, 4)``."""
    return float(horizontal_speed(soles, fps)[contacts].mean()) if contacts.any() else 0.0


class CleanupObjective:
    """The loss ``L`` of the module doc as a function of ``qpos (T, nq)``, with everything it
    compares against fixed from the input ``q0 (T, nq)``: its joints ``joints0 (T, 23, 3)``,
    contact joints ``soles0 (T, 4, 3)`` (numpy), Ψ's cell forces ``forces0 (T, 2, 16)`` and Γ's
    ``contacts (T, 4)``.

    Args:
        q0: the input's qpos (torch, float32).
        fps: frame rate (Hz).
        kin: the model's differentiable kinematics.
        net: the vGRF network Ψ (frozen).
        gamma: the contact function Γ.
        config: weights and settings.
    """

    def __init__(self, q0: torch.Tensor, fps: float, kin, net: nn.Module, gamma: ContactFunction,
                 config: CleanupConfig):
        self.q0, self.fps, self.kin, self.net, self.config = q0, fps, kin, net, config
        with torch.no_grad():
            self.joints0, soles0 = kin.points(q0)
            self.forces0 = net(self.joints0[None])[0]
        soles0 = soles0.numpy()
        self.soles0 = soles0.astype(float)
        self.contacts = contacts = gamma(self.forces0.numpy(), fps)
        self.targets = torch.tensor(foot_targets(soles0, contact_targets(soles0, contacts)), dtype=torch.float32)
        window = contact_weights(contacts, int(round(config.edge_s * fps)))
        self.window = torch.tensor(config.swing_weight + (1 - config.swing_weight) * window, dtype=torch.float32)
        self.window_total = max(float(self.window.sum()), 1.0)
        hm = load_model(kin.model_name)
        self.limited, ranges = hm.hinge_ranges
        self.lower, self.upper = torch.tensor(ranges, dtype=torch.float32).unbind(-1)
        self.smoothing = torch.full((q0.shape[1],), config.w_smooth)   # per qpos column
        self.smoothing[3:7] = 0.0                                      # the root quaternion: L_quat's job
        self.smoothing[hm.leg_qpos_columns] = config.w_smooth_legs
        self.root_speed0 = self.root_speed(q0)

    def root_speed(self, qpos: torch.Tensor) -> torch.Tensor:
        """Root speed ``(T - 1,)`` (m/s) by forward differences."""
        return torch.linalg.norm(torch.diff(qpos[:, :3], dim=0), dim=-1) * self.fps

    def terms(self, qpos: torch.Tensor) -> dict[str, torch.Tensor]:
        """Each unweighted loss term of ``qpos`` (L_smooth with its per-column weights applied)."""
        joints, soles = self.kin.points(qpos)
        angles = qpos[:, self.limited]
        edit = qpos - self.q0
        return {
            "quat": ((qpos[:, 3:7].norm(dim=-1) - 1.0) ** 2).mean(),
            "foot": (self.window * ((soles - self.targets) ** 2).sum(-1)).sum() / self.window_total,
            "traj": ((self.root_speed(qpos) - self.root_speed0) ** 2).mean(),
            "vgrf": msle(self.net(joints[None])[0], self.forces0),
            "pose": ((joints - self.joints0) ** 2).sum(-1).mean(),
            "limit": (torch.relu(angles - self.upper) ** 2 + torch.relu(self.lower - angles) ** 2).sum(-1).mean(),
            "smooth": ((edit[2:] - 2 * edit[1:-1] + edit[:-2]) ** 2 * self.smoothing).sum(-1).mean(),
        }

    def __call__(self, qpos: torch.Tensor) -> torch.Tensor:
        c = self.config
        weights = {"quat": c.w_quat, "foot": c.w_foot, "traj": c.w_traj, "vgrf": c.w_vgrf, "pose": c.w_pose,
                   "limit": c.w_limit, "smooth": 1.0}
        return sum(weights[name] * term for name, term in self.terms(qpos).items())


def cleanup(motion: Motion, net: nn.Module, config: CleanupConfig = CleanupConfig(),
            gamma: ContactFunction = ContactFunction(), progress=None) -> CleanupResult:
    """Remove foot skate from ``motion`` with the vGRF network ``net`` (module doc)."""
    if motion.n_frames < 3:
        raise ValueError(f"{motion.name}: footskate cleanup needs at least 3 frames, got {motion.n_frames}")
    kin = torch_kinematics(motion.model)
    net.eval()
    for p in net.parameters():
        p.requires_grad_(False)
    q0 = torch.tensor(motion.qpos, dtype=torch.float32)
    objective = CleanupObjective(q0, motion.fps, kin, net, gamma, config)

    qpos = q0.clone().requires_grad_(True)
    # L-BFGS: a least-squares problem whose variables (rad, m) differ in scale by orders of magnitude;
    # Adam would move every variable by about its step size, however small its gradient.
    optimiser = torch.optim.LBFGS([qpos], lr=1.0, max_iter=config.iterations, history_size=20,
                                  line_search_fn="strong_wolfe")
    evaluations = [0]

    def closure() -> torch.Tensor:
        loss = objective(qpos)
        optimiser.zero_grad()
        loss.backward()
        if progress is not None:
            progress(evaluations[0], loss.item())
        evaluations[0] += 1
        return loss

    optimiser.step(closure)
    with torch.no_grad():
        final = qpos.detach().clone()
        final[:, 3:7] /= final[:, 3:7].norm(dim=-1, keepdim=True)
        joints, soles = kin.points(final)
    cleaned = motion.with_qpos(final.numpy().astype(float), source=dict(motion.source, footskate_cleanup="vgrf"))
    return CleanupResult(cleaned, objective.contacts, objective.soles0, soles.numpy().astype(float),
                         float(torch.linalg.norm(joints - objective.joints0, dim=-1).mean()))
