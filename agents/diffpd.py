"""Neural PhysCap's dynamic cycle (neural_physcap §3.4, Appendix A) in PyTorch.

One *cycle iteration* at the current state ``(q, q̇)`` of a MuJoCo humanoid:

1. MuJoCo gives the mass matrix ``M(q)`` (``nv × nv``, armature included), the bias
   ``h(q, q̇)`` (gravity, Coriolis and centripetal forces, minus passive forces) and the
   translational Jacobians ``J`` of the foot contact points (the model's ``*_point`` sites), all
   as constants for autograd (:class:`MujocoDynamics`), as the paper does with RBDL.
2. DyNet (or the fixed baseline ``s_g = ½, s_f = 0``) gives per-DoF gain scales ``s_g ∈ (0, 1)``
   and offsets ``s_f ∈ [−1, 1]``: ``k_p = 2 s_g k_p_ini``, ``α = γ s_f`` (γ = 10).
3. The PD rule with force compensation (eq. 7): ``τ = k_p ∘ d(q̂, q) − k_d ∘ q̇ + α + h`` over
   all ``nv`` DoF; its first six rows ``τ_root`` are the virtual root force that would track
   the root.
4. GRFNet gives a force ``λ_c`` inside the friction cone (μ = 0.8) at each contact point in
   contact (:func:`friction_cone`); ``f_c = Σ_c J_cᵀ λ_c``.
5. ``τ* = τ − f_c`` (eq. 13). The hinges apply ``τ*`` (the joint torques compensate the contact
   load, as in the paper; :attr:`DiffPDConfig.contact_compensation`). The six unactuated root DoF
   get no actuation of their own: only ``f_c`` and a *bounded* residual
   ``r = ρ ∘ tanh(τ*_root / ρ)`` (``ρ`` = :attr:`DiffPDConfig.residual_bound`; 0 disables it).
   The paper's root applies ``τ*_root`` unbounded (ρ → ∞); ``τ*_root`` is what its ``L_force``
   (eq. 8) minimises and is reported, as is ``r``.
6. Forward dynamics (eq. 13): ``q̈ = (M + Δt K_d)⁻¹(τ_applied + f_c − h)`` — the hinges'
   damping taken at the end-of-step velocity, as MuJoCo's ``implicitfast`` does for the same
   actuators (the paper's explicit update diverges with the MJCF's ``kv`` at Δt = 1/360 s; see
   :class:`DynamicCycle`); one Cholesky factorisation, ``torch.cholesky_solve``.
7. Semi-implicit Euler (eq. 14) with the constrained velocity update (eq. 15): ``q̇ ← q̇ + Δt q̈``,
   then ``q̇`` is projected (:func:`project_velocity`) so that no contact point moves into the
   floor, then ``q ← q ⊕ Δt q̇`` (the root quaternion by the exponential map, renormalised).
   Eq. 15's projection is frictionless (tangential support from λ alone, and the feet skate);
   here contact points in contact and within :attr:`DiffPDConfig.no_slip_height` of the floor also
   stick (:func:`stick_velocity`: their horizontal velocity is projected to zero in the same metric),
   so the floor's impulses, not a root force, hold a planted foot and propel the body.

A frame (1/60 s) is ``k = 6`` iterations (``Δt = 1/360 s``) towards that frame's target pose.

Layouts and frames: ``q`` is MuJoCo's qpos (pelvis position m world, pelvis quaternion w,x,y,z,
hinge angles rad), ``q̇`` MuJoCo's qvel (pelvis linear velocity world m/s, pelvis angular velocity
in the pelvis frame rad/s, hinge rates rad/s); generalised forces are in qvel layout (N on the
root position rows, N·m elsewhere). The floor is the plane z = 0 with normal +z, so the floor
frame is the world frame (the paper's ``T`` is the identity). Forces are in N unless said.

Not applied (as in the paper): the MJCF's joint ranges, actuator force ranges and collisions other
than the foot points' floor constraint.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Literal, Sequence

import mujoco
import numpy as np
import torch
from torch import nn

from reference_motion.humanoid.model import CONTACT_CHANNELS, load_model

FOOT_POINT_SITES = tuple(f"{side[0]}_{region}_point" for side, region in (c.split("_") for c in CONTACT_CHANNELS))
"""The four foot point sites (``l_toe_point``, ``r_toe_point``, ``l_heel_point``,
``r_heel_point``), in :data:`~reference_motion.humanoid.model.CONTACT_CHANNELS` order."""

SOLE_CORNER_SITES = tuple(f"{side}_cell{cell}" for side in "lr" for cell in ("00", "01", "14", "15"))
"""The insole cell sites at the four corners of each sole (heel inner/outer, toe inner/outer; on the
sole plane, under the corner sole spheres): as contact points they keep the whole sole out of the
floor when the foot rolls, which the four centre-line points do not (measured with the trained
DyNet on the held-out takes: lowest body point within 5 mm of the floor in 88.0% of frames with
:data:`FOOT_POINT_SITES`, 100% with these; at twice the projection's cost, 2^8 active sets)."""

ROOT_DOF = 6
"""Unactuated DoF of the free root (linear world xyz, angular pelvis-frame xyz)."""

MAX_PROJECTION_POINTS = 8
"""The projection enumerates all ``2^P`` active sets; more contact points than this are refused."""


# ============================================================== configuration
@dataclass(frozen=True)
class DiffPDConfig:
    """Settings of the differentiable dynamic cycle (defaults: the paper's where it gives one).

    Attributes:
        model: ``"humanoid_1seg"`` or ``"humanoid_2seg"``.
        fps: frame rate of the target poses (Hz); one frame is :attr:`iterations` cycle iterations.
        iterations: cycle iterations per frame (the paper's k = 6), so Δt = 1/(fps·k) = 1/360 s.
        gamma: offset scale γ of ``α = γ s_f`` (the paper's 10; N on root position rows, N·m else).
        mu: friction coefficient of the cone constraining λ (the paper's 0.8).
        contact_sites: MJCF site names of the contact points (default: the four foot points).
        contact_height: a point at most this high (m) is in contact (GRFNet's λ is applied there)
            when no contact labels are given.
        root_kp: ``k_p_ini`` of the virtual root PD (linear N/m, angular N·m/rad); the MJCF has no
            root actuator. 5000 N/m ≈ 70 kg at 1.3 Hz; 1000 N·m/rad as the spine's hinges.
        root_kd: ``k_d_ini`` of the virtual root PD (N·s/m, N·m·s/rad): ``k_p_ini/10``, the
            ratio of every hinge gain in the MJCF.
        residual_bound: bound ρ of the root residual force ``r = ρ tanh(τ*_root/ρ)`` (linear N,
            angular N·m); 0 gives a root moved by contact forces only, ``math.inf`` the paper's
            root, which applies ``τ*_root`` unbounded. Default: half the body weight of the 70 kg humanoid
            (343.35 N) and 200 N·m, measured on the held-out IMU takes (bench/diffpd.py's cleaning-time
            sweep, ``residual_bound.sweep_imu``, model trained at 0.5 BW / 200 N·m): at 100 N·m the
            character falls on some takes (re-anchors, penetration), at 0.2 BW non-penetration drops
            to 93.7%, at 1 BW the linear residual drags the planted feet (foot skate 0.295 m/s vs 0.213).
        contact_compensation: hinges apply ``τ* = τ − Jᵀλ`` (the paper) rather than ``τ``.
        projection_metric: norm of the velocity projection ``min ‖q̇* − q̇‖``: ``"mass"``
            (``W = M + Δt K_d``, the step's effective inertia with its implicit hinge damping:
            the change is then ``W⁻¹J_zᵀp``, the response to impulses ``p ≥ 0`` along the floor
            normal — an inelastic, frictionless contact by Gauss's principle) or
            ``"euclidean"`` (the paper's eq. 15, which mixes m/s and rad/s and changes velocities
            no floor push could).
        push_out: fraction β of a point's penetration depth removed per iteration: a point below
            the floor (z < 0) must move up at ``−β z / Δt`` at least; 0 only stops it moving deeper.
        no_slip_height: contact points in contact and at most this high (m) do not slide: the
            velocity projection also holds their horizontal velocity at zero (:func:`stick_velocity`;
            sticking friction, as a planted foot; they may still lift). 0 gives the paper's
            frictionless projection (eq. 15), where tangential support comes from λ alone.
        damping: how ``k_d`` follows ``k_p`` (neither the paper nor SPEC gives ``k_d``):
            ``"ratio"`` keeps each DoF's damping ratio, ``k_d = k_d_ini √(2 s_g)``;
            ``"constant"`` keeps ``k_d = k_d_ini``. Both are the MJCF's ``kv`` at ``s_g = ½``, so
            the fixed-gains baseline is the same. With the damping on the absolute velocity
            (eq. 7: ``−k_d q̇``) a joint following a ramp lags by ``k_d/k_p`` s (0.1 s = 6
            frames at the MJCF's ``kv = kp/10``): under ``"ratio"`` even ``s_g → 1`` only
            takes it to ``0.1/√2`` s (measured on DeepMimic run, spinkick, turn_left1: lag cut
            23–30%), under ``"constant"`` to 0.05 s (measured 41–53%); the MJCF's hinges are
            over-damped (ζ ≈ 0.05√(k_p/I) > 1), so halving ζ does not make them oscillate.
        dynet_hidden: DyNet's two hidden layer widths.
        grfnet_hidden: GRFNet's three hidden layer widths (4 FC layers in all, as the paper).
        dtype: torch dtype of the cycle (float64: ``cond(M)`` ≈ 1e3–1e4 and stiff PD at 360 Hz).
    """

    model: str = "humanoid_1seg"
    fps: float = 60.0
    iterations: int = 6
    gamma: float = 10.0
    mu: float = 0.8
    contact_sites: tuple[str, ...] = FOOT_POINT_SITES
    contact_height: float = 0.03
    root_kp: tuple[float, float] = (5000.0, 1000.0)
    root_kd: tuple[float, float] = (500.0, 100.0)
    residual_bound: tuple[float, float] = (343.35, 200.0)
    contact_compensation: bool = True
    projection_metric: Literal["mass", "euclidean"] = "mass"
    push_out: float = 0.1
    no_slip_height: float = 0.01
    damping: Literal["ratio", "constant"] = "ratio"
    dynet_hidden: tuple[int, int] = (256, 256)
    grfnet_hidden: tuple[int, int, int] = (256, 256, 256)
    dtype: torch.dtype = field(default=torch.float64)

    def __post_init__(self) -> None:
        if self.iterations < 1:
            raise ValueError(f"iterations must be at least 1, got {self.iterations}")
        if self.fps <= 0:
            raise ValueError(f"fps must be positive, got {self.fps}")
        if not 0 < len(self.contact_sites) <= MAX_PROJECTION_POINTS:
            raise ValueError(f"1 to {MAX_PROJECTION_POINTS} contact sites, got {len(self.contact_sites)}")
        if self.projection_metric not in ("mass", "euclidean"):
            raise ValueError(f"projection_metric must be 'mass' or 'euclidean', got {self.projection_metric!r}")
        if self.damping not in ("ratio", "constant"):
            raise ValueError(f"damping must be 'ratio' or 'constant', got {self.damping!r}")
        if self.no_slip_height < 0:
            raise ValueError(f"no_slip_height must be non-negative, got {self.no_slip_height}")
        if not 0.0 <= self.push_out <= 1.0:
            raise ValueError(f"push_out must lie in [0, 1], got {self.push_out}")
        if min(self.residual_bound) < 0 or self.mu < 0:
            raise ValueError("residual_bound and mu must be non-negative")

    @property
    def dt(self) -> float:
        """Iteration time step Δt (s)."""
        return 1.0 / (self.fps * self.iterations)


# ======================================================= quaternions and poses
def quat_multiply(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """Hamilton product ``a ⊗ b`` of quaternions ``(..., 4)`` (w, x, y, z)."""
    aw, ax, ay, az = a.unbind(-1)
    bw, bx, by, bz = b.unbind(-1)
    return torch.stack([aw * bw - ax * bx - ay * by - az * bz,
                        aw * bx + ax * bw + ay * bz - az * by,
                        aw * by - ax * bz + ay * bw + az * bx,
                        aw * bz + ax * by - ay * bx + az * bw], dim=-1)


def quat_conjugate(q: torch.Tensor) -> torch.Tensor:
    """Conjugate ``(..., 4)`` (the inverse of a unit quaternion)."""
    return q * q.new_tensor([1.0, -1.0, -1.0, -1.0])


_TINY = 1e-24  # added under square roots so that their gradients stay finite at zero rotation


def quat_exp(v: torch.Tensor) -> torch.Tensor:
    """Unit quaternion ``(..., 4)`` of rotation vectors ``v (..., 3)`` (axis × angle, rad)."""
    angle = torch.sqrt((v * v).sum(-1, keepdim=True) + _TINY)
    half_sinc = 0.5 * torch.sinc(angle / (2.0 * math.pi))  # sin(θ/2)/θ, smooth at θ = 0
    return torch.cat([torch.cos(0.5 * angle), half_sinc * v], dim=-1)


def quat_log(q: torch.Tensor) -> torch.Tensor:
    """Rotation vector ``(..., 3)`` (rad) of quaternions ``(..., 4)``, shortest way (angle ≤ π).

    Scale-invariant (``q`` need not be unit) and smooth at the identity."""
    q = torch.where(q[..., :1] < 0, -q, q)
    w, v = q[..., :1], q[..., 1:]
    n = torch.sqrt((v * v).sum(-1, keepdim=True) + _TINY)
    return 2.0 * torch.atan2(n, w) / n * v


def pose_difference(target: torch.Tensor, q: torch.Tensor) -> torch.Tensor:
    """The paper's ``d(q̂, q)`` in qvel layout ``(..., nv)`` from qpos ``(..., nq)``.

    Root position difference (world, m), root rotation ``log(q_root⁻¹ ⊗ q̂_root)`` (pelvis frame,
    rad, matching qvel's angular velocity), hinge differences (rad)."""
    rot = quat_log(quat_multiply(quat_conjugate(q[..., 3:7]), target[..., 3:7]))
    return torch.cat([target[..., :3] - q[..., :3], rot, target[..., 7:] - q[..., 7:]], dim=-1)


def integrate_position(q: torch.Tensor, qd: torch.Tensor, dt: float) -> torch.Tensor:
    """``q ⊕ dt·q̇`` ``(..., nq)``: positions and hinges by Euler, the root quaternion by
    ``q_root ⊗ exp(dt ω)`` (ω in the pelvis frame), renormalised — as ``mj_integratePos``."""
    quat = quat_multiply(q[..., 3:7], quat_exp(dt * qd[..., 3:6]))
    quat = quat / quat.norm(dim=-1, keepdim=True)
    return torch.cat([q[..., :3] + dt * qd[..., :3], quat, q[..., 7:] + dt * qd[..., 6:]], dim=-1)


# ===================================================================== MuJoCo
@dataclass(frozen=True)
class DynamicsTerms:
    """Dynamics of a batch of states from MuJoCo, detached (constants for autograd).

    Attributes:
        mass: ``(B, nv, nv)`` joint-space inertia ``M(q)`` (kg, kg·m, kg·m²; armature included).
        bias: ``(B, nv)`` ``h(q, q̇)`` = MuJoCo's ``qfrc_bias − qfrc_passive`` (gravity, Coriolis,
            centripetal, minus joint damping/springs; zero passive forces in our models).
        jacobian: ``(B, P, 3, nv)`` world-frame translational Jacobians of the contact points.
        points: ``(B, P, 3)`` world positions of the contact points (m).
    """

    mass: torch.Tensor
    bias: torch.Tensor
    jacobian: torch.Tensor
    points: torch.Tensor


class MujocoDynamics:
    """``M``, ``h`` and contact-point Jacobians of a humanoid, per state, from MuJoCo.

    Runs ``mj_kinematics, mj_comPos, mj_makeM, mj_comVel, mj_passive, mj_rne`` (no collision
    detection: ~15 µs a state) and ``mj_jacSite`` per contact site.

    Args:
        model: ``"humanoid_1seg"`` or ``"humanoid_2seg"``.
        sites: MJCF site names of the contact points.
    """

    def __init__(self, model: str, sites: Sequence[str] = FOOT_POINT_SITES):
        self.humanoid = load_model(model)
        self.model = self.humanoid.model
        self._data = mujoco.MjData(self.model)
        try:
            self.site_ids = np.array([self.model.site(s).id for s in sites])
        except KeyError as err:
            raise KeyError(f"model {model} has no site {err}") from err
        self.nq, self.nv = self.model.nq, self.model.nv

    @property
    def n_points(self) -> int:
        return len(self.site_ids)

    def __call__(self, q: torch.Tensor, qd: torch.Tensor) -> DynamicsTerms:
        """Dynamics at ``q (B, nq)``, ``q̇ (B, nv)``; returned in ``q``'s dtype and device."""
        arrays = self.compute(q.detach().cpu().double().numpy(), qd.detach().cpu().double().numpy())
        return DynamicsTerms(*(torch.from_numpy(x).to(dtype=q.dtype, device=q.device) for x in arrays))

    def compute(self, qn: np.ndarray, vn: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(M, h, J, points)`` as new float64 arrays (see :class:`DynamicsTerms`) at ``qpos (B, nq)``,
        ``qvel (B, nv)``."""
        m, d = self.model, self._data
        B, P, nv = qn.shape[0], self.n_points, self.nv
        mass, bias = np.empty((B, nv, nv)), np.empty((B, nv))
        jac, points = np.empty((B, P, 3, nv)), np.empty((B, P, 3))
        for b in range(B):
            d.qpos[:], d.qvel[:] = qn[b], vn[b]
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            mujoco.mj_makeM(m, d)
            mujoco.mj_comVel(m, d)
            mujoco.mj_passive(m, d)
            mujoco.mj_rne(m, d, 0, bias[b])
            bias[b] -= d.qfrc_passive
            mujoco.mj_fullM(m, d, mass[b])
            for p, site in enumerate(self.site_ids):
                mujoco.mj_jacSite(m, d, jac[b, p], None, site)
            points[b] = d.site_xpos[self.site_ids]
        return mass, bias, jac, points

    def actuator_gains(self) -> tuple[np.ndarray, np.ndarray]:
        """Per hinge DoF (``nv − 6``, qvel order): the MJCF position actuators' ``(kp, kv)``."""
        m = self.model
        kp, kd = np.zeros(self.nv - ROOT_DOF), np.zeros(self.nv - ROOT_DOF)
        for a in range(m.nu):
            if m.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
                raise ValueError(f"actuator {m.actuator(a).name} does not drive a joint")
            dof = int(m.jnt_dofadr[m.actuator_trnid[a, 0]]) - ROOT_DOF
            kp[dof], kd[dof] = m.actuator_gainprm[a, 0], -m.actuator_biasprm[a, 2]
        if np.any(kp <= 0):
            raise ValueError(f"model {self.humanoid.name}: hinges without a position actuator")
        return kp, kd


# =================================================================== networks
def _mlp(sizes: Sequence[int]) -> nn.Sequential:
    """Fully connected layers ``sizes[0] → … → sizes[-1]`` with ReLU between them (not after the last)."""
    layers: list[nn.Module] = []
    for i, (a, b) in enumerate(zip(sizes[:-1], sizes[1:])):
        layers.append(nn.Linear(a, b))
        if i < len(sizes) - 2:
            layers.append(nn.ReLU())
    return nn.Sequential(*layers)


def _zero_last(net: nn.Sequential) -> None:
    last = net[-1]
    assert isinstance(last, nn.Linear)
    nn.init.zeros_(last.weight)
    nn.init.zeros_(last.bias)


class DyNet(nn.Module):
    """Gain scales and offsets of the PD controller (neural_physcap §3.4.1, Appendix A).

    Input (concatenated, ``nq + nq + nv + nv(nv+1)/2 + nv`` values; 1423 for ``humanoid_1seg``,
    1532 for ``humanoid_2seg``): target pose ``q̂`` and current pose ``q`` (qpos, with the current
    root's x, y subtracted from both, so the net sees no absolute horizontal position), current
    velocity ``q̇``, the upper triangle of ``M`` divided by the body mass, and the pose error
    ``d(q̂, q)``. Two hidden FC+ReLU layers, then two heads: ``s_g = sigmoid(·) ∈ (0, 1)`` and
    ``s_f = tanh(·) ∈ (−1, 1)``, both ``(B, nv)``. The heads start at zero, so an untrained DyNet
    is the fixed-gains baseline (``s_g = ½``, ``s_f = 0``).
    """

    def __init__(self, nq: int, nv: int, total_mass: float, hidden: Sequence[int] = (256, 256)):
        super().__init__()
        self.nq, self.nv, self.total_mass = nq, nv, total_mass
        self.register_buffer("triu", torch.triu_indices(nv, nv), persistent=False)
        n_in = 2 * nq + 2 * nv + nv * (nv + 1) // 2
        self.body = _mlp([n_in, *hidden])
        self.body.append(nn.ReLU())
        self.gain_head = nn.Linear(hidden[-1], nv)
        self.offset_head = nn.Linear(hidden[-1], nv)
        for head in (self.gain_head, self.offset_head):
            nn.init.zeros_(head.weight)
            nn.init.zeros_(head.bias)

    def forward(self, target: torch.Tensor, q: torch.Tensor, qd: torch.Tensor, mass: torch.Tensor,
                error: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """``(s_g, s_f)``, each ``(B, nv)``, from ``q̂, q (B, nq)``, ``q̇ (B, nv)``,
        ``M (B, nv, nv)`` and ``d(q̂, q) (B, nv)``."""
        origin = torch.cat([q[:, :2], q.new_zeros(q.shape[0], self.nq - 2)], dim=1)
        m_upper = mass[:, self.triu[0], self.triu[1]] / self.total_mass
        x = torch.cat([target - origin, q - origin, qd, m_upper, error], dim=1)
        hidden = self.body(x)
        return torch.sigmoid(self.gain_head(hidden)), torch.tanh(self.offset_head(hidden))


def friction_cone(raw: torch.Tensor, mu: float, scale: torch.Tensor | float) -> torch.Tensor:
    """Map unconstrained ``raw (..., 3)`` (tangential x, y, normal) to forces ``λ (..., 3)``
    (world x, y, z; N) inside the friction cone ``‖λ_t‖ ≤ μ λ_n``, ``λ_n ≥ 0``.

    ``λ_n = scale · softplus(raw_n) / ln 2`` (so ``raw = 0`` gives ``scale``);
    ``λ_t = μ λ_n · tanh(‖raw_t‖) · raw_t / ‖raw_t‖`` (smooth at ``raw_t = 0``)."""
    normal = scale * nn.functional.softplus(raw[..., 2:]) / math.log(2.0)
    t = raw[..., :2]
    norm = torch.sqrt((t * t).sum(-1, keepdim=True) + _TINY)
    return torch.cat([mu * normal * torch.tanh(norm) / norm * t, normal], dim=-1)


class GRFNet(nn.Module):
    """Ground reaction forces at the contact points (neural_physcap §3.4.2, Appendix A).

    Input (concatenated, ``6 + 18P + 2P`` values; 86 for the four foot points): the virtual root
    force ``τ_root`` divided by the body weight, the root columns of the contact Jacobians
    ``J_1`` (``P × 3 × 6``), the contact labels ``(P,)`` and the point heights ``(P,)`` (m).
    Four FC layers (ReLU between), ``3P`` outputs mapped by :func:`friction_cone` and zeroed at
    points not in contact. The normal scale is the body weight shared by the points in contact,
    so an untrained GRFNet (last layer zero) starts by sharing the weight evenly, vertically.
    """

    def __init__(self, n_points: int, weight: float, mu: float = 0.8, hidden: Sequence[int] = (256, 256, 256)):
        super().__init__()
        self.n_points, self.weight, self.mu = n_points, weight, mu
        self.net = _mlp([ROOT_DOF + 20 * n_points, *hidden, 3 * n_points])
        _zero_last(self.net)

    def forward(self, tau_root: torch.Tensor, jac_root: torch.Tensor, contact: torch.Tensor,
                heights: torch.Tensor) -> torch.Tensor:
        """``λ (B, P, 3)`` (N, world) from ``τ_root (B, 6)``, ``J_1 (B, P, 3, 6)``, contact
        labels ``(B, P)`` in [0, 1] and point heights ``(B, P)``."""
        B = tau_root.shape[0]
        x = torch.cat([tau_root / self.weight, jac_root.reshape(B, -1), contact, heights], dim=1)
        raw = self.net(x).view(B, self.n_points, 3)
        share = self.weight / contact.sum(1, keepdim=True).clamp(min=1.0)
        return friction_cone(raw, self.mu, share.unsqueeze(-1)) * contact.unsqueeze(-1)


# ============================================================ the projection
_SUBSET_CACHE: dict[int, torch.Tensor] = {}


def _subsets(n: int) -> torch.Tensor:
    """All ``2^n`` subsets of ``n`` points as a bool ``(2^n, n)``, smallest first."""
    if n not in _SUBSET_CACHE:
        rows = sorted(itertools.product((False, True), repeat=n), key=sum)
        _SUBSET_CACHE[n] = torch.tensor(rows, dtype=torch.bool)
    return _SUBSET_CACHE[n]


def _masked_solve(delassus: torch.Tensor, rhs: torch.Tensor, active: torch.Tensor) -> torch.Tensor:
    """``p`` with ``p_A = D_AA⁻¹ r_A`` on the active set and 0 elsewhere; shapes
    ``D (..., P, P)``, ``r (..., P)``, ``active (..., P)`` bool (broadcast)."""
    a = active.to(delassus.dtype)
    d = delassus * a.unsqueeze(-1) * a.unsqueeze(-2) + torch.diag_embed(1.0 - a)
    return torch.linalg.solve(d, (rhs * a).unsqueeze(-1)).squeeze(-1)


def project_velocity(qd: torch.Tensor, rows: torch.Tensor, lower: torch.Tensor,
                     response: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Differentiable projection ``min ½‖q̇* − q̇‖²_W s.t. rows·q̇* ≥ lower`` (neural_physcap eq. 15).

    Args:
        qd: ``(B, nv)`` velocity to project.
        rows: ``(B, P, nv)`` constraint rows ``A`` (the contact points' normal Jacobians ``J_z``).
        lower: ``(B, P)`` lower bounds on ``A q̇*`` (m/s).
        response: ``(B, nv, P)`` ``W⁻¹Aᵀ`` for the SPD metric ``W`` (``Aᵀ`` itself for the
            Euclidean norm); the caller has ``W`` factorised already.

    Returns:
        ``q̇* = q̇ + W⁻¹Aᵀp`` ``(B, nv)`` and the multipliers ``p (B, P)`` (≥ 0; with ``W`` the
        inertia, the impulses along the floor normal, N·s).

    Solved exactly through the dual ``min ½pᵀDp − pᵀr, p ≥ 0`` (``D = A W⁻¹ Aᵀ``,
    ``r = lower − A q̇``): the active set is found without gradients by a primal-dual active-set
    iteration (:func:`_active_set_newton`, 1–3 solves); states where it does not settle on a set
    meeting the KKT conditions fall back to trying all ``2^P`` sets at once (batched) and keeping the
    one of least violation. ``p`` is then recomputed in closed form on that set with autograd. That
    is the exact QP solution, and its gradient is the implicit-function gradient that
    OptNet/cvxpylayers would give wherever the active set does not change, without an iterative
    solver or extra dependency.
    """
    delassus = rows @ response
    P = rows.shape[1]
    delassus = delassus + 1e-12 * delassus.diagonal(dim1=1, dim2=2).mean(-1)[:, None, None] * torch.eye(
        P, dtype=rows.dtype, device=rows.device)
    rhs = lower - (rows @ qd.unsqueeze(-1)).squeeze(-1)
    with torch.no_grad():
        active, p_fast, ok = _active_set_newton(delassus, rhs)
        if not bool(ok.all()):  # rare: enumerate every active set for the unsettled states
            bad = torch.nonzero(~ok).flatten()
            d_b, r_b = delassus[bad], rhs[bad]
            sets = _subsets(P).to(rows.device)  # (S, P)
            p_all = _masked_solve(d_b.unsqueeze(1), r_b.unsqueeze(1), sets)  # (b, S, P)
            best = _kkt_violation(d_b.unsqueeze(1), r_b.unsqueeze(1), p_all, sets).argmin(dim=1)
            active = active.clone()
            p_fast = p_fast.clone()
            active[bad] = sets[best]  # first minimum: the smallest such set
            p_fast[bad] = p_all[torch.arange(len(bad), device=rows.device), best]
    if torch.is_grad_enabled():
        p = _masked_solve(delassus, rhs, active)
    else:  # no gradient wanted: the active-set solution is the same solve
        p = p_fast
    return qd + (response @ p.unsqueeze(-1)).squeeze(-1), p


def _kkt_violation(delassus: torch.Tensor, rhs: torch.Tensor, p: torch.Tensor, active: torch.Tensor) -> torch.Tensor:
    """Largest violation of the LCP's KKT conditions (``p ≥ 0`` on the active set, ``Dp − r ≥ 0``
    off it), scaled by ``D``'s diagonal to velocity units (m/s); shapes broadcast, reduced over ``P``."""
    slack = (delassus @ p.unsqueeze(-1)).squeeze(-1) - rhs
    scale = delassus.diagonal(dim1=-2, dim2=-1)
    return torch.where(active, (-p).clamp(min=0) * scale, (-slack).clamp(min=0)).amax(-1)


KKT_TOLERANCE = 1e-9
"""Relative KKT violation (m/s per unit of ``1 + max|r|``) at which the projection's active-set
iteration accepts a solution (both the torch cycle and :mod:`agents.diffpd_fast`)."""


def _active_set_newton(delassus: torch.Tensor, rhs: torch.Tensor, iterations: int = 8,
                       tol: float = KKT_TOLERANCE) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Primal-dual active-set (semismooth Newton) iterations for ``min ½pᵀDp − pᵀr, p ≥ 0``: start
    from the violated constraints, solve on the set, move each constraint in or out by the sign of
    ``p_i − s_i`` (``s = Dp − r``), until the set repeats. Returns the set ``(B, P)``, ``p`` and
    which states meet the KKT conditions (violation at most ``tol·(1 + max|r|)`` m/s; the others
    go to the exhaustive enumeration). Typically 1–3 solves of a ``P × P`` system instead of ``2^P``."""
    active = rhs > 0
    for _ in range(iterations):
        p = _masked_solve(delassus, rhs, active)
        slack = (delassus @ p.unsqueeze(-1)).squeeze(-1) - rhs
        new = torch.where(active, p > 0, slack < 0)
        if bool((new == active).all()):
            break
        active = new
    p = _masked_solve(delassus, rhs, active)
    ok = _kkt_violation(delassus, rhs, p, active) <= tol * (1.0 + rhs.abs().amax(-1))
    return active, p, ok


def stick_velocity(qd: torch.Tensor, tangent_rows: torch.Tensor, stuck: torch.Tensor, tangent_response: torch.Tensor,
                   normal_response: torch.Tensor, regulariser: float = 1e-9) -> tuple[torch.Tensor, torch.Tensor]:
    """No-slip contact: the projection of ``q̇ (B, nv)`` onto ``{T q̇ = 0}`` (``T``: the tangential
    rows, ``(B, 2P, nv)``, of the points with ``stuck (B, P)``) in the metric ``W``, and the normal
    rows' response restricted to that subspace.

    Args:
        tangent_rows: ``(B, 2P, nv)`` the contact points' world x, y Jacobian rows (point-major).
        stuck: ``(B, P)`` bool, the points whose horizontal velocity must vanish.
        tangent_response: ``(B, nv, 2P)`` ``W⁻¹Tᵀ``; normal_response: ``(B, nv, P)`` ``W⁻¹J_zᵀ``.
        regulariser: relative Tikhonov term on ``T W⁻¹ Tᵀ`` (singular: the four corners of a rigid
            sole give 8 rows of rank 3), so the solve picks the least-impulse multipliers.

    Returns:
        ``q̇' = q̇ − W⁻¹Tᵀ(TW⁻¹Tᵀ)⁻¹T q̇`` and ``R' = (I − W⁻¹Tᵀ(TW⁻¹Tᵀ)⁻¹T) W⁻¹J_zᵀ``. Projecting
        ``q̇'`` on the floor with ``R'`` (:func:`project_velocity`) solves the KKT system of
        ``min ½‖q̇* − q̇‖²_W`` s.t. ``T q̇* = 0`` and ``J_z q̇* ≥ lower`` exactly (the Schur complement
        of the equality block): the stuck points' multipliers are impulses along the floor, of any
        sign and size (infinite friction: sticking, not Coulomb-limited).
    """
    active = stuck.repeat_interleave(2, dim=1)                                    # (B, 2P)
    a = active.to(qd.dtype)
    gram = tangent_rows @ tangent_response                                        # T W⁻¹ Tᵀ
    eye = torch.eye(gram.shape[-1], dtype=qd.dtype, device=qd.device)
    reg = regulariser * (gram.diagonal(dim1=1, dim2=2) * a).sum(-1).div(a.sum(-1).clamp(min=1.0))
    gram = gram * a.unsqueeze(-1) * a.unsqueeze(-2) + eye * (1.0 - a).unsqueeze(-1) + eye * reg[:, None, None]
    rhs = torch.cat([-(tangent_rows @ qd.unsqueeze(-1)), tangent_rows @ normal_response], dim=2) * a.unsqueeze(-1)
    mult = torch.linalg.solve(gram, rhs)                                          # (B, 2P, 1 + P)
    update = tangent_response @ mult
    return qd + update[..., 0], normal_response - update[..., 1:]


def penetration_bounds(heights: torch.Tensor, dt: float, push_out: float) -> torch.Tensor:
    """Lower bounds ``(B, P)`` on the normal velocities of points at ``heights (B, P)``:
    ``−z/Δt`` above the floor (it may reach the floor, not cross it, in this step) and
    ``−β z/Δt ≥ 0`` below it (it may not go deeper, and leaves at rate β)."""
    return -(heights.clamp(min=0.0) + push_out * heights.clamp(max=0.0)) / dt


# =============================================================== the cycle
@dataclass(frozen=True)
class CycleOutput:
    """One cycle iteration (``B`` states; ``P`` contact points).

    Attributes:
        q, qd: ``(B, nq)``, ``(B, nv)`` the new state.
        tau: ``(B, nv)`` ``τ`` of eq. 7 (root rows: the virtual root force).
        force: ``(B, P, 3)`` ground reaction forces λ (N, world).
        root_virtual: ``(B, 6)`` ``τ*_root = τ_root − J_1ᵀλ`` (N, N·m): the root force GRF leave
            unexplained, what ``L_force`` (eq. 8) penalises.
        root_residual: ``(B, 6)`` the bounded part of it actually applied (N, N·m).
        impulse: ``(B, P)`` projection multipliers (N·s with the mass metric).
        s_g, s_f: ``(B, nv)`` the gain scales and offsets used.
        contact: ``(B, P)`` the contact labels used.
    """

    q: torch.Tensor
    qd: torch.Tensor
    tau: torch.Tensor
    force: torch.Tensor
    root_virtual: torch.Tensor
    root_residual: torch.Tensor
    impulse: torch.Tensor
    s_g: torch.Tensor
    s_f: torch.Tensor
    contact: torch.Tensor

    @staticmethod
    def stack(outputs: Sequence["CycleOutput"], dim: int = 1) -> "CycleOutput":
        """The fields of several outputs stacked along a new dimension ``dim``."""
        return CycleOutput(*(torch.stack([getattr(o, f) for o in outputs], dim=dim)
                             for f in CycleOutput.__dataclass_fields__))


class DynamicCycle(nn.Module):
    """The dynamic cycle of Neural PhysCap (see the module docstring) on one humanoid model.

    Args:
        config: :class:`DiffPDConfig`.
        dynet: gain network, or ``None`` for the fixed-gains baseline (``s_g = ½, s_f = 0``:
            the MJCF's ``kp, kv``, no offsets).
        grfnet: GRF network, or ``None`` for no ground reaction force (λ = 0: the root then moves
            by the bounded residual and the floor projection alone).

    Gains: ``k_p = 2 s_g k_p_ini`` with ``k_p_ini`` the MJCF actuators' ``kp`` (hinges) and
    :attr:`DiffPDConfig.root_kp`. Neither the paper nor SPEC gives ``k_d``; it keeps each DoF's
    damping ratio ``ζ = k_d / (2√(k_p I))`` (critical-damping relation) at the MJCF's value as
    ``k_p`` changes: ``k_d = k_d_ini √(k_p / k_p_ini) = k_d_ini √(2 s_g)``, so the baseline runs
    exactly the MJCF's ``(kp, kv)`` (or keeps ``k_d = k_d_ini``: :attr:`DiffPDConfig.damping`).

    Damping is linearly implicit on the hinges: ``q̈ = (M + Δt K_d)⁻¹(τ_applied + Jᵀλ − h)``
    with ``τ`` evaluated at the current ``q̇`` — the same as applying the hinges' ``−k_d ∘ q̇``
    at the end-of-step velocity, which is how MuJoCo's ``implicitfast`` integrates these
    actuators. The paper's fully explicit update is unstable with the MJCF's ``kv``: at
    Δt = 1/360 s, ``Δt·λ_max(M⁻¹K_d)`` ≈ 4.5 (> 2) in a walk pose (the light feet and head).
    The root's virtual damping stays explicit (it passes through the residual bound; small).
    """

    def __init__(self, config: DiffPDConfig = DiffPDConfig(), dynet: DyNet | None = None,
                 grfnet: GRFNet | None = None):
        super().__init__()
        self.config = config
        self.dynamics = MujocoDynamics(config.model, config.contact_sites)
        self.nq, self.nv, self.n_points = self.dynamics.nq, self.dynamics.nv, self.dynamics.n_points
        self.total_mass = self.dynamics.humanoid.total_mass
        self.weight = self.total_mass * float(-self.dynamics.model.opt.gravity[2])
        kp, kd = self.dynamics.actuator_gains()
        (lin_p, ang_p), (lin_d, ang_d) = config.root_kp, config.root_kd
        root_p, root_d = [lin_p] * 3 + [ang_p] * 3, [lin_d] * 3 + [ang_d] * 3
        rho = [config.residual_bound[0]] * 3 + [config.residual_bound[1]] * 3

        def as_tensor(values: Sequence[float] | np.ndarray) -> torch.Tensor:
            return torch.as_tensor(np.asarray(values, dtype=float), dtype=config.dtype)

        self.register_buffer("kp_ini", as_tensor(np.concatenate([root_p, kp])))
        self.register_buffer("kd_ini", as_tensor(np.concatenate([root_d, kd])))
        self.register_buffer("residual_bound", as_tensor(rho))
        self.register_buffer("hinge_mask", as_tensor([0.0] * ROOT_DOF + [1.0] * (self.nv - ROOT_DOF)))
        self.dynet = dynet
        self.grfnet = grfnet

    @classmethod
    def neural(cls, config: DiffPDConfig = DiffPDConfig(), dynet: bool = True, grfnet: bool = True) -> "DynamicCycle":
        """A cycle with fresh (untrained) networks sized for ``config.model`` and
        ``config.dynet_hidden`` / ``grfnet_hidden``: DyNet only if ``dynet`` (else fixed gains),
        GRFNet only if ``grfnet`` (else no GRF)."""
        cycle = cls(config)
        if dynet:
            cycle.dynet = DyNet(cycle.nq, cycle.nv, cycle.total_mass, config.dynet_hidden).to(config.dtype)
        if grfnet:
            cycle.grfnet = GRFNet(cycle.n_points, cycle.weight, config.mu, config.grfnet_hidden).to(config.dtype)
        return cycle

    # ------------------------------------------------------------- one step
    def step(self, q: torch.Tensor, qd: torch.Tensor, target: torch.Tensor,
             contact: torch.Tensor | None = None, s_g: torch.Tensor | None = None,
             s_f: torch.Tensor | None = None) -> CycleOutput:
        """One cycle iteration of Δt from ``q (B, nq)``, ``q̇ (B, nv)`` towards ``target (B, nq)``.

        ``contact (B, P)``: contact labels (default: points at most ``contact_height`` high);
        ``s_g, s_f (B, nv)``: override the gains (default: DyNet's, or the fixed baseline).
        """
        cfg = self.config
        dyn = self.dynamics(q, qd)
        heights = dyn.points[..., 2]
        if torch.is_grad_enabled():  # the heights as functions of q to first order (exact value, gradient J_z)
            heights = heights + (dyn.jacobian[..., 2, :] @ pose_difference(q, q.detach()).unsqueeze(-1)).squeeze(-1)
        if contact is None:
            contact = (heights.detach() <= cfg.contact_height).to(q.dtype)
        error = pose_difference(target, q)
        if (s_g is None) != (s_f is None):
            raise ValueError("give both s_g and s_f, or neither")
        if s_g is None or s_f is None:
            if self.dynet is None:
                s_g, s_f = torch.full_like(qd, 0.5), torch.zeros_like(qd)
            else:
                s_g, s_f = self.dynet(target, q, qd, dyn.mass, error)
        kp = 2.0 * s_g * self.kp_ini
        kd = self.kd_ini * torch.sqrt(2.0 * s_g) if cfg.damping == "ratio" else self.kd_ini.expand_as(s_g)
        tau = kp * error - kd * qd + cfg.gamma * s_f + dyn.bias                     # eq. 7
        jac_t = dyn.jacobian.flatten(1, 2).transpose(1, 2)                          # (B, nv, 3P)
        if self.grfnet is None:
            force = q.new_zeros(q.shape[0], self.n_points, 3)
        else:
            force = self.grfnet(tau[:, :ROOT_DOF], dyn.jacobian[..., :ROOT_DOF], contact, heights)
        f_contact = (jac_t @ force.flatten(1).unsqueeze(-1)).squeeze(-1)           # Jᵀλ, (B, nv)
        tau_star = tau - f_contact
        root_virtual = tau_star[:, :ROOT_DOF]
        residual = self.bound_residual(root_virtual)
        hinges = tau_star[:, ROOT_DOF:] if cfg.contact_compensation else tau[:, ROOT_DOF:]
        applied = torch.cat([residual, hinges], dim=1)
        # eq. 13 with the hinges' damping taken at the end-of-step velocity (class docstring);
        # one Cholesky factor of M + Δt K_d also gives the projection's response W⁻¹J_zᵀ
        rows = dyn.jacobian[..., 2, :]                                              # J_z, (B, P, nv)
        P = self.n_points
        stuck = (contact > 0.5) & (heights.detach() <= cfg.no_slip_height) if cfg.no_slip_height > 0 else None
        sticking = stuck is not None and bool(stuck.any())
        columns = [rows.transpose(1, 2)]
        if sticking:
            tangent = dyn.jacobian[..., :2, :].flatten(1, 2)                        # (B, 2P, nv), point-major
            columns.append(tangent.transpose(1, 2))
        chol = torch.linalg.cholesky(dyn.mass + cfg.dt * torch.diag_embed(kd * self.hinge_mask))
        force_rhs = (applied + f_contact - dyn.bias).unsqueeze(-1)
        if cfg.projection_metric == "mass":
            solved = torch.cholesky_solve(torch.cat([force_rhs, *columns], dim=2), chol)
            qdd, response = solved[..., 0], solved[..., 1:]
        else:
            qdd, response = torch.cholesky_solve(force_rhs, chol)[..., 0], torch.cat(columns, dim=2)
        qd_free = qd + cfg.dt * qdd                                                 # eq. 14
        if sticking:  # no-slip: stuck points' horizontal velocity vanishes (class docstring)
            qd_free, response = stick_velocity(qd_free, tangent, stuck, response[..., P:], response[..., :P])
        lower = penetration_bounds(heights, cfg.dt, cfg.push_out)
        qd_new, impulse = project_velocity(qd_free, rows, lower, response)         # eq. 15
        q_new = integrate_position(q, qd_new, cfg.dt)                               # eq. 14
        return CycleOutput(q_new, qd_new, tau, force, root_virtual, residual, impulse, s_g, s_f, contact)

    def bound_residual(self, root_virtual: torch.Tensor) -> torch.Tensor:
        """The root force applied of ``τ*_root (…, 6)``: ``ρ tanh(τ*_root/ρ)`` per component
        (0 where ρ = 0, ``τ*_root`` itself where ρ = ∞)."""
        rho = self.residual_bound
        finite = torch.isfinite(rho) & (rho > 0)
        safe = torch.where(finite, rho, torch.ones_like(rho))
        bounded = torch.where(finite, safe * torch.tanh(root_virtual / safe), torch.zeros_like(root_virtual))
        return torch.where(torch.isinf(rho), root_virtual, bounded)

    # ------------------------------------------------------- frames, clips
    def frame(self, q: torch.Tensor, qd: torch.Tensor, target: torch.Tensor,
              contact: torch.Tensor | None = None) -> CycleOutput:
        """One frame: :attr:`DiffPDConfig.iterations` iterations towards ``target (B, nq)``.

        Returns the fields stacked over the iterations ``(B, k, …)``, except ``q, qd``: the
        state at the end of the frame."""
        steps = []
        for _ in range(self.config.iterations):
            out = self.step(q, qd, target, contact)
            q, qd = out.q, out.qd
            steps.append(out)
        stacked = CycleOutput.stack(steps)
        return CycleOutput(q, qd, *(getattr(stacked, f) for f in list(CycleOutput.__dataclass_fields__)[2:]))

    def rollout(self, q0: torch.Tensor, qd0: torch.Tensor, targets: torch.Tensor,
                contacts: torch.Tensor | None = None) -> "ClipResult":
        """Run a batch of clips: from ``q0 (B, nq)``, ``q̇0 (B, nv)`` (frame 0) through
        ``targets (B, T, nq)`` (frames 1 … T−1 are the targets; frame 0's is unused).

        ``contacts (B, T, P)``: optional per-frame contact labels. Gradients flow unless called
        under ``torch.no_grad()``."""
        qs, qds, frames = [q0], [qd0], []
        q, qd = q0, qd0
        for t in range(1, targets.shape[1]):
            out = self.frame(q, qd, targets[:, t], None if contacts is None else contacts[:, t])
            q, qd = out.q, out.qd
            qs.append(q)
            qds.append(qd)
            frames.append(out)
        per_frame = CycleOutput.stack(frames)  # (B, T-1, k, ...)
        return ClipResult(q=torch.stack(qs, 1), qd=torch.stack(qds, 1), tau=per_frame.tau,
                          force=per_frame.force, root_virtual=per_frame.root_virtual,
                          root_residual=per_frame.root_residual, impulse=per_frame.impulse,
                          weight=self.weight, s_g=per_frame.s_g)


@dataclass(frozen=True)
class ClipResult:
    """A rollout of ``B`` clips of ``T`` frames (``k`` iterations per frame).

    Attributes:
        q, qd: ``(B, T, nq)``, ``(B, T, nv)`` states at the frames (frame 0: the initial state).
        tau, force, root_virtual, root_residual, impulse: per iteration, ``(B, T−1, k, …)``, as
            in :class:`CycleOutput`.
        weight: body weight (N) for normalising forces.
        s_g: ``(B, T−1, k, nv)`` the gain scales used (``None`` where not recorded).
    """

    q: torch.Tensor
    qd: torch.Tensor
    tau: torch.Tensor
    force: torch.Tensor
    root_virtual: torch.Tensor
    root_residual: torch.Tensor
    impulse: torch.Tensor
    weight: float
    s_g: torch.Tensor | None = None

    def report(self) -> dict[str, float]:
        """Magnitudes of the root forces over the clip: mean and max of the residual actually
        applied (linear in body weights, angular N·m), of ``τ*_root`` (what GRF leave
        unexplained), and the mean total vertical GRF (body weights)."""
        r, v = self.root_residual.detach(), self.root_virtual.detach()
        lin, ang = r[..., :3].norm(dim=-1), r[..., 3:].norm(dim=-1)
        vlin, vang = v[..., :3].norm(dim=-1), v[..., 3:].norm(dim=-1)
        return {"residual_linear_bw_mean": float(lin.mean()) / self.weight,
                "residual_linear_bw_max": float(lin.max()) / self.weight,
                "residual_angular_nm_mean": float(ang.mean()), "residual_angular_nm_max": float(ang.max()),
                "root_virtual_linear_bw_mean": float(vlin.mean()) / self.weight,
                "root_virtual_angular_nm_mean": float(vang.mean()),
                "grf_vertical_bw_mean": float(self.force.detach()[..., 2].sum(-1).mean()) / self.weight}
