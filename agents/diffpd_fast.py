"""The dynamic cycle's forward pass in NumPy, for cleaning (no gradients).

:class:`FastCycle` runs exactly the iteration of :meth:`agents.diffpd.DynamicCycle.step` (same
equations, same float64 arithmetic up to round-off; ``tests/test_diffpd.py`` checks it against the
torch cycle) on NumPy arrays with the networks' weights copied out once. A torch step costs ~100
small-tensor operations of 5–10 µs of dispatch each, more than their arithmetic on a batch of one
clip; NumPy's per-call overhead is ~1 µs, and the networks run as one ``addmm`` a layer. Training
keeps the torch cycle (it needs autograd).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch

from agents.diffpd import KKT_TOLERANCE, ROOT_DOF, DynamicCycle, _subsets

_TINY = 1e-24


def _layers(seq: torch.nn.Sequential) -> list[tuple[torch.Tensor, torch.Tensor]]:
    """``(Wᵀ, b)`` of the ``nn.Linear`` layers of ``seq`` as float64 tensors (detached copies)."""
    return [(m.weight.detach().double().T.contiguous(), m.bias.detach().double().clone())
            for m in seq if isinstance(m, torch.nn.Linear)]


def _mlp(x: np.ndarray, layers: list[tuple[torch.Tensor, torch.Tensor]], relu_last: bool) -> np.ndarray:
    """The layers on ``x (B, n)``. The products go through torch (its thread setting; one ``addmm``
    a layer): NumPy's BLAS may start threads of its own, which on a shared 2-core machine made a
    batch-of-12 DyNet product 100x slower."""
    h = torch.from_numpy(np.ascontiguousarray(x))
    with torch.inference_mode():
        for i, (w, b) in enumerate(layers):
            h = torch.addmm(b, h, w)
            if relu_last or i < len(layers) - 1:
                h.relu_()
    return h.numpy()


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    aw, ax, ay, az = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    bw, bx, by, bz = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def pose_difference(target: np.ndarray, q: np.ndarray) -> np.ndarray:
    """:func:`agents.diffpd.pose_difference` on arrays."""
    conj = q[:, 3:7] * np.array([1.0, -1.0, -1.0, -1.0])
    rel = quat_multiply(conj, target[:, 3:7])
    rel = np.where(rel[:, :1] < 0, -rel, rel)
    n = np.sqrt((rel[:, 1:] ** 2).sum(-1, keepdims=True) + _TINY)
    rot = 2.0 * np.arctan2(n, rel[:, :1]) / n * rel[:, 1:]
    return np.concatenate([target[:, :3] - q[:, :3], rot, target[:, 7:] - q[:, 7:]], axis=1)


def integrate_position(q: np.ndarray, qd: np.ndarray, dt: float) -> np.ndarray:
    """:func:`agents.diffpd.integrate_position` on arrays."""
    v = dt * qd[:, 3:6]
    angle = np.sqrt((v * v).sum(-1, keepdims=True) + _TINY)
    half_sinc = 0.5 * np.sinc(angle / (2.0 * math.pi))
    quat = quat_multiply(q[:, 3:7], np.concatenate([np.cos(0.5 * angle), half_sinc * v], axis=1))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    return np.concatenate([q[:, :3] + dt * qd[:, :3], quat, q[:, 7:] + dt * qd[:, 6:]], axis=1)


def _masked_solve(delassus: np.ndarray, rhs: np.ndarray, active: np.ndarray) -> np.ndarray:
    a = active.astype(delassus.dtype)
    eye = np.eye(delassus.shape[-1])
    d = delassus * a[..., :, None] * a[..., None, :] + eye * (1.0 - a)[..., None, :]
    return np.linalg.solve(d, (rhs * a)[..., None])[..., 0]


def _violation(delassus: np.ndarray, rhs: np.ndarray, p: np.ndarray, active: np.ndarray) -> np.ndarray:
    slack = (delassus @ p[..., None])[..., 0] - rhs
    scale = np.diagonal(delassus, axis1=-2, axis2=-1)
    return np.where(active, np.maximum(-p, 0.0) * scale, np.maximum(-slack, 0.0)).max(-1)


def project_velocity(qd: np.ndarray, rows: np.ndarray, lower: np.ndarray, response: np.ndarray,
                     iterations: int = 8, tol: float = KKT_TOLERANCE) -> tuple[np.ndarray, np.ndarray]:
    """:func:`agents.diffpd.project_velocity` on arrays (the same active-set iteration and fallback)."""
    P = rows.shape[1]
    delassus = rows @ response
    delassus = delassus + 1e-12 * np.diagonal(delassus, axis1=1, axis2=2).mean(-1)[:, None, None] * np.eye(P)
    rhs = lower - (rows @ qd[..., None])[..., 0]
    active = rhs > 0
    for _ in range(iterations):
        p = _masked_solve(delassus, rhs, active)
        slack = (delassus @ p[..., None])[..., 0] - rhs
        new = np.where(active, p > 0, slack < 0)
        if np.array_equal(new, active):
            break
        active = new
    p = _masked_solve(delassus, rhs, active)
    bad = np.nonzero(_violation(delassus, rhs, p, active) > tol * (1.0 + np.abs(rhs).max(-1)))[0]
    if len(bad):
        sets = _subsets(P).numpy()
        p_all = _masked_solve(delassus[bad, None], rhs[bad, None], sets)
        best = _violation(delassus[bad, None], rhs[bad, None], p_all, sets).argmin(1)
        p[bad] = p_all[np.arange(len(bad)), best]
    return qd + (response @ p[..., None])[..., 0], p


def stick_velocity(qd: np.ndarray, tangent_rows: np.ndarray, stuck: np.ndarray, tangent_response: np.ndarray,
                   normal_response: np.ndarray, regulariser: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    """:func:`agents.diffpd.stick_velocity` on arrays."""
    a = np.repeat(stuck, 2, axis=1).astype(qd.dtype)
    gram = tangent_rows @ tangent_response
    eye = np.eye(gram.shape[-1])
    reg = regulariser * (np.diagonal(gram, axis1=1, axis2=2) * a).sum(-1) / np.maximum(a.sum(-1), 1.0)
    gram = gram * a[:, :, None] * a[:, None, :] + eye * (1.0 - a)[:, :, None] + eye * reg[:, None, None]
    rhs = np.concatenate([-(tangent_rows @ qd[..., None]), tangent_rows @ normal_response], axis=2) * a[..., None]
    update = tangent_response @ np.linalg.solve(gram, rhs)
    return qd + update[..., 0], normal_response - update[..., 1:]


@dataclass
class FastFrame:
    """One frame of :meth:`FastCycle.frame` (``B`` clips, ``k`` iterations, ``P`` points): the end
    state ``q (B, nq)``, ``qd (B, nv)`` and, per iteration, ``force (B, k, P, 3)``,
    ``root_virtual``, ``root_residual (B, k, 6)``, ``s_g (B, k, nv)`` and the floor projection's
    normal multipliers ``impulse (B, k, P)`` (N·s with the mass metric)."""

    q: np.ndarray
    qd: np.ndarray
    force: np.ndarray
    root_virtual: np.ndarray
    root_residual: np.ndarray
    s_g: np.ndarray
    impulse: np.ndarray


class FastCycle:
    """A trained :class:`~agents.diffpd.DynamicCycle`'s forward pass in NumPy (see the module docstring)."""

    def __init__(self, cycle: DynamicCycle):
        self.cycle, self.config = cycle, cycle.config
        self.dynamics = cycle.dynamics
        self.nq, self.nv, self.n_points, self.weight = cycle.nq, cycle.nv, cycle.n_points, cycle.weight
        self.kp_ini = cycle.kp_ini.double().numpy().copy()
        self.kd_ini = cycle.kd_ini.double().numpy().copy()
        self.rho = cycle.residual_bound.double().numpy().copy()
        self.hinge_mask = cycle.hinge_mask.double().numpy().copy()
        if cycle.dynet is None:
            self.dynet = None
        else:
            (wg, bg), (wf, bf) = _layers(torch.nn.Sequential(cycle.dynet.gain_head, cycle.dynet.offset_head))
            self.dynet = (_layers(cycle.dynet.body), [(torch.cat([wg, wf], 1), torch.cat([bg, bf]))])
        if cycle.dynet is not None:
            triu = cycle.dynet.triu.numpy()
            self.triu = (triu[0], triu[1])
            self.total_mass = cycle.dynet.total_mass
        self.grfnet = None if cycle.grfnet is None else _layers(cycle.grfnet.net)

    def _gains(self, target, q, qd, mass, error):
        if self.dynet is None:
            return np.full_like(qd, 0.5), np.zeros_like(qd)
        body, heads = self.dynet
        origin = np.zeros_like(q)
        origin[:, :2] = q[:, :2]
        m_upper = mass[:, self.triu[0], self.triu[1]] / self.total_mass
        hidden = _mlp(np.concatenate([target - origin, q - origin, qd, m_upper, error], axis=1), body, True)
        out = _mlp(hidden, heads, False)  # both heads in one product
        nv = self.nv
        return 1.0 / (1.0 + np.exp(-out[:, :nv])), np.tanh(out[:, nv:])

    def _forces(self, tau_root, jac, contact, heights):
        B, P = contact.shape
        if self.grfnet is None:
            return np.zeros((B, P, 3))
        x = np.concatenate([tau_root / self.weight, jac[..., :ROOT_DOF].reshape(B, -1), contact, heights], axis=1)
        raw = _mlp(x, self.grfnet, False).reshape(B, P, 3)
        share = self.weight / np.maximum(contact.sum(1, keepdims=True), 1.0)
        normal = share[..., None] * np.logaddexp(0.0, raw[..., 2:]) / math.log(2.0)
        t = raw[..., :2]
        norm = np.sqrt((t * t).sum(-1, keepdims=True) + _TINY)
        return np.concatenate([self.config.mu * normal * np.tanh(norm) / norm * t, normal], axis=-1) * contact[..., None]

    def _bound(self, virtual):
        rho = self.rho
        finite = np.isfinite(rho) & (rho > 0)
        safe = np.where(finite, rho, 1.0)
        bounded = np.where(finite, safe * np.tanh(virtual / safe), 0.0)
        return np.where(np.isinf(rho), virtual, bounded)

    def step(self, q: np.ndarray, qd: np.ndarray, target: np.ndarray):
        """One iteration (:meth:`agents.diffpd.DynamicCycle.step` without contact labels or gain
        overrides): ``(q, qd, force, root_virtual, residual, s_g, impulse)``."""
        cfg, P = self.config, self.n_points
        mass, bias, jac, points = self.dynamics.compute(q, qd)
        heights = points[..., 2]
        contact = (heights <= cfg.contact_height).astype(float)
        error = pose_difference(target, q)
        s_g, s_f = self._gains(target, q, qd, mass, error)
        kp = 2.0 * s_g * self.kp_ini
        kd = self.kd_ini * np.sqrt(2.0 * s_g) if cfg.damping == "ratio" else np.broadcast_to(self.kd_ini, s_g.shape)
        tau = kp * error - kd * qd + cfg.gamma * s_f + bias
        force = self._forces(tau[:, :ROOT_DOF], jac, contact, heights)
        f_contact = np.einsum("bpkn,bpk->bn", jac, force)
        tau_star = tau - f_contact
        virtual = tau_star[:, :ROOT_DOF]
        residual = self._bound(virtual)
        hinges = tau_star[:, ROOT_DOF:] if cfg.contact_compensation else tau[:, ROOT_DOF:]
        applied = np.concatenate([residual, hinges], axis=1)
        rows = jac[..., 2, :]
        stuck = (contact > 0.5) & (heights <= cfg.no_slip_height) if cfg.no_slip_height > 0 else None
        sticking = stuck is not None and bool(stuck.any())
        columns = [rows.transpose(0, 2, 1)]
        if sticking:
            tangent = jac[..., :2, :].reshape(q.shape[0], 2 * P, -1)
            columns.append(tangent.transpose(0, 2, 1))
        w = mass + cfg.dt * (kd * self.hinge_mask)[:, None, :] * np.eye(self.nv)
        rhs = (applied + f_contact - bias)[..., None]
        if cfg.projection_metric == "mass":
            solved = np.linalg.solve(w, np.concatenate([rhs, *columns], axis=2))
            qdd, response = solved[..., 0], solved[..., 1:]
        else:
            qdd, response = np.linalg.solve(w, rhs)[..., 0], np.concatenate(columns, axis=2)
        qd_free = qd + cfg.dt * qdd
        if sticking:
            qd_free, response = stick_velocity(qd_free, tangent, stuck, response[..., P:], response[..., :P])
        lower = -(np.maximum(heights, 0.0) + cfg.push_out * np.minimum(heights, 0.0)) / cfg.dt
        qd_new, impulse = project_velocity(qd_free, rows, lower, response)
        return integrate_position(q, qd_new, cfg.dt), qd_new, force, virtual, residual, s_g, impulse

    def frame(self, q: np.ndarray, qd: np.ndarray, target: np.ndarray) -> FastFrame:
        """:attr:`~agents.diffpd.DiffPDConfig.iterations` iterations towards ``target (B, nq)``."""
        outs = []
        for _ in range(self.config.iterations):
            q, qd, *rest = self.step(q, qd, target)
            outs.append(rest)
        force, virtual, residual, s_g, impulse = (np.stack(x, axis=1) for x in zip(*outs))
        return FastFrame(q, qd, force, virtual, residual, s_g, impulse)
