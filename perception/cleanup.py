"""Footskate cleanup guided by the vGRF network (underpressure §6) on a :class:`Motion`.

1. Ψ estimates the clip's cell vGRF F̃ and Γ turns them into contacts C (CONTACT_CHANNELS order).
2. Each contact phase of a channel pins that channel's *contact joint* (the sole point under the
   ball or the heel, :class:`~perception.kinematics.TorchKinematics`) to one position: its mean
   position over the phase.
3. Hinge angles, root position and root quaternion are optimised with L-BFGS for
   ``L = ω_q L_quat + ω_f L_foot + ω_t L_traj + ω_v L_vGRF``: L_quat keeps the root quaternion
   unit-norm (eq. 3); L_foot pulls contact joints to their pins, weighted by a rectangular window
   with smoothed edges (eq. 4); L_traj keeps the root's speed profile (eq. 5); L_vGRF keeps
   Ψ's estimate of the edited motion equal to F̃ (eq. 6).

Weights are ours (see :class:`CleanupConfig`): the paper's (ω_q 1e-3, ω_f 1e-5, ω_t 1e2, ω_v 5e-5)
go with its units and sums, which it does not state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
from torch import nn

from perception.contacts import ContactFunction
from perception.kinematics import torch_kinematics
from perception.vgrf import msle
from reference_motion.footskate import contact_windows
from reference_motion.motion import Motion


@dataclass(frozen=True)
class CleanupConfig:
    """Settings of :func:`cleanup`.

    Attributes:
        iterations: L-BFGS iterations (UnderPressure: N = 100 gradient steps).
        w_quat, w_foot, w_traj, w_vgrf: loss weights (means over frames, SI units).
        edge_s: duration of the smoothed ramps at both ends of a contact window.
    """

    iterations: int = 100
    w_quat: float = 1.0
    w_foot: float = 100.0
    w_traj: float = 1.0
    w_vgrf: float = 1.0
    edge_s: float = 0.05


@dataclass
class CleanupResult:
    """The cleaned motion, the contacts used, and the before/after measurements.

    Attributes:
        motion: the cleaned clip.
        contacts: ``(T, 4)`` contacts from Ψ and Γ on the input.
        foot_speed_before, foot_speed_after: mean horizontal speed (m/s) of the contact joints
            over their contact frames (UnderPressure's footskate measure).
        joint_shift_m: mean displacement of the 23 joints between input and output (m).
    """

    motion: Motion
    contacts: np.ndarray
    foot_speed_before: float
    foot_speed_after: float
    joint_shift_m: float


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
    """Pin positions ``(T, 4, 3)`` for the sole points ``(T, 4, 3)``: in each contact phase, the
    phase's mean position; NaN outside contact. (Moving the pins to the floor would also remove
    floating and penetration, at the price of shifting the whole body; that is the physics
    cleanup's job, :mod:`agents.clean`.)"""
    out = np.full(soles.shape, np.nan)
    for c in range(contacts.shape[1]):
        for start, stop in contact_windows(contacts[:, c]):
            out[start:stop, c] = soles[start:stop, c].mean(axis=0)
    return out


def contact_speed(soles: np.ndarray, contacts: np.ndarray, fps: float) -> float:
    """Mean horizontal speed (m/s) of sole points ``(T, 4, 3)`` over frames in ``contacts (T, 4)``."""
    speed = np.linalg.norm(np.gradient(soles[..., :2], axis=0), axis=-1) * fps
    return float(speed[contacts].mean()) if contacts.any() else 0.0


def cleanup(motion: Motion, net: nn.Module, config: CleanupConfig = CleanupConfig(),
            gamma: ContactFunction = ContactFunction(), progress=None) -> CleanupResult:
    """Remove foot skate from ``motion`` with the vGRF network ``net`` (module doc)."""
    if motion.n_frames < 3:
        raise ValueError(f"{motion.name}: footskate cleanup needs at least 3 frames, got {motion.n_frames}")
    kin = torch_kinematics(motion.model)
    fps = motion.fps
    net.eval()
    for p in net.parameters():
        p.requires_grad_(False)
    q0 = torch.tensor(motion.qpos, dtype=torch.float32)
    with torch.no_grad():
        joints0, soles0 = kin.points(q0)
        forces0 = net(joints0[None])[0]
    contacts = gamma(forces0.numpy(), fps)
    targets = contact_targets(soles0.numpy(), contacts)
    window = torch.tensor(contact_weights(contacts, int(round(config.edge_s * fps))), dtype=torch.float32)
    pins = torch.tensor(np.nan_to_num(targets), dtype=torch.float32)
    root_speed0 = torch.linalg.norm(torch.diff(q0[:, :3], dim=0), dim=-1) * fps

    qpos = q0.clone().requires_grad_(True)
    # L-BFGS: a least-squares problem whose variables (rad, m) differ in scale by orders of magnitude;
    # Adam would move every variable by about its step size, however small its gradient.
    optimiser = torch.optim.LBFGS([qpos], lr=1.0, max_iter=config.iterations, history_size=20,
                                  line_search_fn="strong_wolfe")
    evaluations = [0]

    def closure() -> torch.Tensor:
        joints, soles = kin.points(qpos)
        l_quat = ((qpos[:, 3:7].norm(dim=-1) - 1.0) ** 2).mean()
        l_foot = (window * ((soles - pins) ** 2).sum(-1)).sum() / max(float(window.sum()), 1.0)
        l_traj = ((torch.linalg.norm(torch.diff(qpos[:, :3], dim=0), dim=-1) * fps - root_speed0) ** 2).mean()
        l_vgrf = msle(net(joints[None])[0], forces0)
        loss = config.w_quat * l_quat + config.w_foot * l_foot + config.w_traj * l_traj + config.w_vgrf * l_vgrf
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
    return CleanupResult(cleaned, contacts, contact_speed(soles0.numpy(), contacts, fps),
                         contact_speed(soles.numpy(), contacts, fps),
                         float(torch.linalg.norm(joints - joints0, dim=-1).mean()))
