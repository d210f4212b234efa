"""The differentiable dynamic cycle (`agents/diffpd.py`): MuJoCo terms, gradients, the floor
projection, fixed-gains tracking and the friction cone."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest
import torch

from agents.diffpd import (DiffPDConfig, DynamicCycle, DyNet, GRFNet, MujocoDynamics, friction_cone,
                           integrate_position, penetration_bounds, pose_difference, project_velocity)
from reference_motion.library import load_motion

F64 = torch.float64


pytestmark = pytest.mark.usefixtures("one_thread")


@pytest.fixture(scope="module")
def walk():
    """DeepMimic walk on humanoid_1seg at 60 Hz (76 frames)."""
    return load_motion("deepmimic:walk")


def _random_state(model: mujoco.MjModel, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    qpos = model.qpos0.copy()
    qpos[:3] += rng.normal(0, 0.1, 3)
    quat = rng.normal(size=4)
    qpos[3:7] = quat / np.linalg.norm(quat)
    qpos[7:] += rng.normal(0, 0.3, model.nq - 7)
    return qpos, rng.normal(0, 1.0, model.nv)


def _lowered(walk, frames: list[int], drop: float, vz: float) -> tuple[torch.Tensor, torch.Tensor]:
    """Walk frames with the pelvis ``drop`` m lower and ``vz`` m/s added to its vertical velocity."""
    q = torch.tensor(walk.qpos[frames])
    qd = torch.tensor(walk.qvel[frames])
    q[:, 2] -= drop
    qd[:, 2] += vz
    return q, qd


@pytest.mark.parametrize("name", ["humanoid_1seg", "humanoid_2seg"])
def test_dynamics_terms_match_mujoco(name):
    """M·v equals mj_mulM, h equals qfrc_bias, J q̇ equals the sites' velocities, for random states."""
    dyn = MujocoDynamics(name)
    m = dyn.model
    d = mujoco.MjData(m)
    rng = np.random.default_rng(7)
    states = [_random_state(m, rng) for _ in range(3)]
    terms = dyn(torch.tensor(np.stack([s[0] for s in states])), torch.tensor(np.stack([s[1] for s in states])))
    for b, (qpos, qvel) in enumerate(states):
        d.qpos[:], d.qvel[:] = qpos, qvel
        mujoco.mj_forward(m, d)
        v = rng.normal(size=m.nv)
        mv = np.zeros(m.nv)
        mujoco.mj_mulM(m, d, mv, v)
        np.testing.assert_allclose(terms.mass[b].numpy() @ v, mv, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(terms.mass[b].numpy(), terms.mass[b].numpy().T, atol=1e-12)
        np.testing.assert_allclose(terms.bias[b].numpy(), d.qfrc_bias - d.qfrc_passive, rtol=1e-10, atol=1e-10)
        for p, site in enumerate(dyn.site_ids):
            vel = np.zeros(6)  # (angular, linear), world frame
            mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_SITE, site, vel, 0)
            np.testing.assert_allclose(terms.jacobian[b, p].numpy() @ qvel, vel[3:], rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(terms.points[b, p].numpy(), d.site_xpos[site], atol=1e-12)


def test_pose_helpers_match_mujoco():
    """integrate_position is mj_integratePos; pose_difference is mj_differentiatePos × dt."""
    dyn = MujocoDynamics("humanoid_1seg")
    m = dyn.model
    rng = np.random.default_rng(3)
    qpos, qvel = _random_state(m, rng)
    dt = 0.05
    expected = qpos.copy()
    mujoco.mj_integratePos(m, expected, qvel, dt)
    q_new = integrate_position(torch.tensor(qpos), torch.tensor(qvel), dt)
    np.testing.assert_allclose(q_new.numpy(), expected, atol=1e-12)
    other, _ = _random_state(m, rng)
    diff = np.zeros(m.nv)
    mujoco.mj_differentiatePos(m, diff, 1.0, qpos, other)
    np.testing.assert_allclose(pose_difference(torch.tensor(other), torch.tensor(qpos)).numpy(), diff, atol=1e-10)


def _random_heads(cycle: DynamicCycle, seed: int) -> None:
    """Give the networks' zero-initialised output layers random weights (inputs then matter)."""
    gen = torch.Generator().manual_seed(seed)
    layers = [cycle.grfnet.net[-1]] if cycle.grfnet is not None else []
    if cycle.dynet is not None:
        layers += [cycle.dynet.gain_head, cycle.dynet.offset_head]
    with torch.no_grad():
        for layer in layers:
            layer.weight.copy_(0.05 * torch.randn(layer.weight.shape, generator=gen, dtype=F64))
            layer.bias.copy_(0.05 * torch.randn(layer.bias.shape, generator=gen, dtype=F64))


@pytest.mark.parametrize("no_slip_height", [0.0, 0.01])
def test_step_gradcheck(walk, no_slip_height):
    """One cycle iteration (PD, GRFNet, forward dynamics, projection with active contacts; with
    and without the no-slip constraint) against central finite differences w.r.t. the target
    pose, s_g and s_f; and through DyNet."""
    torch.manual_seed(0)
    cycle = DynamicCycle.neural(DiffPDConfig(no_slip_height=no_slip_height))
    _random_heads(cycle, 1)
    q, qd = _lowered(walk, [20], drop=0.01, vz=-0.3)
    target = torch.tensor(walk.qpos[21:22], requires_grad=True)
    s_g = torch.full((1, cycle.nv), 0.5, dtype=F64).add(0.1 * torch.rand(1, cycle.nv, dtype=F64)).requires_grad_()
    s_f = (0.2 * torch.randn(1, cycle.nv, dtype=F64)).requires_grad_()
    out = cycle.step(q, qd, target, s_g=s_g, s_f=s_f)
    if no_slip_height:  # a sticking foot (two points) and the floor pushing it
        heights = cycle.dynamics(q, qd).points[..., 2]
        assert ((heights <= no_slip_height) & (out.contact > 0)).sum() >= 2
        assert (out.impulse > 1e-3).sum() >= 1, "the projection must be active for this check"
    else:
        assert (out.impulse > 1e-3).sum() >= 2, "the projection must be active for this check"
    assert out.force[..., 2].sum() > 0

    def one_step(target, s_g, s_f):
        o = cycle.step(q, qd, target, s_g=s_g, s_f=s_f)
        return o.q, o.qd, o.impulse, o.force

    # a stuck foot's tangential rows are ill-conditioned (toe and heel of one sole): the central
    # differences' round-off then grows as 1/eps (measured 2e-5 at eps 1e-6, 2e-7 at 1e-4)
    eps = 1e-4 if no_slip_height else 1e-6
    assert torch.autograd.gradcheck(one_step, (target, s_g, s_f), eps=eps, atol=1e-5, rtol=1e-4)
    assert torch.autograd.gradcheck(lambda t: cycle.step(q, qd, t).qd, (target,), eps=eps, atol=1e-5, rtol=1e-4)


def test_frame_gradient_close_to_true_finite_differences(walk):
    """Over a whole frame (k = 6 iterations, contacts active) M, h, J are constants for autograd
    while finite differences recompute them: the gradient of a tracking loss w.r.t. the offsets
    still agrees to a few per mille (measured 0.46%)."""
    cycle = DynamicCycle(DiffPDConfig())
    q0, qd0 = _lowered(walk, [20], drop=0.01, vz=-0.3)
    target = torch.tensor(walk.qpos[21:22])

    def loss(s_f: torch.Tensor) -> torch.Tensor:
        q, qd = q0, qd0
        for _ in range(cycle.config.iterations):
            out = cycle.step(q, qd, target, s_g=torch.full_like(s_f, 0.5), s_f=s_f)
            q, qd = out.q, out.qd
        return ((q - target) ** 2).sum() * 1e4

    s_f = torch.zeros(1, cycle.nv, dtype=F64, requires_grad=True)
    (grad,) = torch.autograd.grad(loss(s_f), s_f)
    eps = 1e-6
    numeric = torch.zeros_like(grad)
    with torch.no_grad():
        for i in range(cycle.nv):
            step = torch.zeros_like(s_f)
            step[0, i] = eps
            numeric[0, i] = (loss(s_f + step) - loss(s_f - step)) / (2 * eps)
    assert float((grad - numeric).norm() / numeric.norm()) < 0.02


@pytest.mark.parametrize("metric", ["mass", "euclidean"])
def test_projection_keeps_points_out_of_the_floor(walk, metric):
    """Feet at and under z = 0 moving down: after the projection no point moves into the floor
    (z + Δt J_z q̇* ≥ 0 above it, J_z q̇* ≥ −β z/Δt ≥ 0 below it), the solution meets the KKT
    conditions, and integrating it through MuJoCo leaves no point deeper than before."""
    rng = np.random.default_rng(5)
    frames = list(range(0, 64, 2))
    q, qd = _lowered(walk, frames, drop=0.0, vz=0.0)
    q[:, 2] -= torch.tensor(rng.uniform(0.0, 0.02, len(frames)))
    qd[:, :3] += torch.tensor(rng.normal(0, 0.3, (len(frames), 3)))
    qd[:, 2] -= torch.tensor(rng.uniform(0.5, 2.0, len(frames)))
    qd[:, 6:] += torch.tensor(rng.normal(0, 1.0, (len(frames), qd.shape[1] - 6)))
    cfg = DiffPDConfig()
    dyn = MujocoDynamics(cfg.model)
    terms = dyn(q, qd)
    rows, heights = terms.jacobian[..., 2, :], terms.points[..., 2]
    lower = penetration_bounds(heights, cfg.dt, cfg.push_out)
    response = torch.linalg.solve(terms.mass, rows.transpose(1, 2)) if metric == "mass" else rows.transpose(1, 2)
    before = (rows @ qd.unsqueeze(-1)).squeeze(-1)
    assert (heights <= 0).sum() >= 20 and (before < lower).sum() >= 40  # a demanding start
    projected, impulse = project_velocity(qd, rows, lower, response)
    after = (rows @ projected.unsqueeze(-1)).squeeze(-1)
    tol = 1e-7  # m/s (3e-10 m over a step)
    assert torch.all(after >= lower - tol)
    above = heights > 0
    assert torch.all((heights + cfg.dt * after)[above] >= -tol * cfg.dt)  # first order: no point crosses z = 0 …
    assert torch.all(after[heights <= 0] >= -tol)                # … and none under it moves further down
    assert torch.all(impulse >= 0)
    assert float((impulse * (after - lower)).abs().max()) < 1e-6  # complementarity
    # the same through MuJoCo's kinematics of the integrated pose (second-order error only)
    data = mujoco.MjData(dyn.model)
    for b in range(len(frames)):
        qpos = q[b].numpy().copy()
        mujoco.mj_integratePos(dyn.model, qpos, projected[b].numpy(), cfg.dt)
        data.qpos[:] = qpos
        mujoco.mj_kinematics(dyn.model, data)
        z_new = data.site_xpos[dyn.site_ids, 2]
        assert np.all(z_new >= np.minimum(heights[b].numpy(), 0.0) - 1e-4)


def test_fixed_gains_track_walk(walk):
    """The baseline (s_g = ½, s_f = 0: the MJCF's kp, kv) from three walk frames, the reference
    as target, 10 frames, batched. With GRFNet's initial output (the body weight shared evenly by
    the points in contact) the pelvis stays within 3 cm of the reference height (measured at most
    1.43 cm); with no GRF at all (λ = 0) nothing compensates the body's load on the legs and the
    frictionless points slide, so it sags (measured 1.8–5.8 cm; bound 8 cm). Hinges stay within
    0.1 rad on average (measured ≤ 0.06), the residual within its bound; batching changes nothing."""
    starts, n = [0, 20, 40], 11
    targets = torch.tensor(np.stack([walk.qpos[s:s + n] for s in starts]))
    qd0 = torch.tensor(np.stack([walk.qvel[s] for s in starts]))
    cfg = DiffPDConfig()
    prior = GRFNet(4, DynamicCycle(cfg).weight, cfg.mu).to(F64)  # untrained: zero last layer
    for grfnet, bound in ((prior, 0.03), (None, 0.08)):
        cycle = DynamicCycle(cfg, grfnet=grfnet)
        with torch.no_grad():
            result = cycle.rollout(targets[:, 0], qd0, targets)
        drift = (result.q[..., 2] - targets[..., 2]).abs()
        assert float(drift.max()) < bound, drift.max(1).values
        hinge_error = (result.q[:, -1, 7:] - targets[:, -1, 7:]).abs().mean(1)
        assert float(hinge_error.max()) < 0.1, hinge_error
        report = result.report()
        assert report["residual_linear_bw_max"] <= np.sqrt(3) * cfg.residual_bound[0] / cycle.weight + 1e-9
        assert report["residual_angular_nm_max"] <= np.sqrt(3) * cfg.residual_bound[1] + 1e-9
        if grfnet is not None:
            assert report["grf_vertical_bw_mean"] > 0.5
        with torch.no_grad():
            single = cycle.rollout(targets[1:2, 0], qd0[1:2], targets[1:2])
        torch.testing.assert_close(single.q[0], result.q[1], rtol=0, atol=1e-9)


def test_friction_cone():
    """λ from any raw output lies in the cone ‖λ_t‖ ≤ μ λ_n, λ_n ≥ 0; GRFNet zeroes points out
    of contact and starts by sharing the body weight among the points in contact."""
    gen = torch.Generator().manual_seed(0)
    raw = torch.randn(10000, 3, generator=gen, dtype=F64) * torch.logspace(-3, 2, 10000, dtype=F64)[:, None]
    lam = friction_cone(raw, 0.8, 100.0)
    assert torch.all(lam[:, 2] >= 0)
    assert torch.all(lam[:, :2].norm(dim=1) <= 0.8 * lam[:, 2] * (1 + 1e-12))
    torch.testing.assert_close(friction_cone(torch.zeros(3, dtype=F64), 0.8, 100.0),
                               torch.tensor([0.0, 0.0, 100.0], dtype=F64))
    net = GRFNet(4, weight=700.0).to(F64)
    contact = torch.tensor([[1.0, 0.0, 1.0, 0.0]], dtype=F64)
    inputs = (torch.randn(1, 6, dtype=F64), torch.randn(1, 4, 3, 6, dtype=F64), contact, torch.zeros(1, 4, dtype=F64))
    lam = net(*inputs)
    torch.testing.assert_close(lam[0, :, 2], torch.tensor([350.0, 0.0, 350.0, 0.0], dtype=F64))
    with torch.no_grad():
        net.net[-1].weight.normal_(0, 1.0, generator=gen)
    lam = net(*inputs)
    assert torch.all(lam[0, [1, 3]] == 0)
    assert torch.all(lam[..., :2].norm(dim=-1) <= 0.8 * lam[..., 2] * (1 + 1e-12))


def test_dynet_starts_at_the_baseline_and_config_checks():
    """An untrained DyNet gives s_g = ½, s_f = 0 (the fixed gains); bad settings are refused."""
    cycle = DynamicCycle.neural(DiffPDConfig())
    assert isinstance(cycle.dynet, DyNet)
    q = torch.tensor(cycle.dynamics.model.qpos0)[None]
    qd = torch.zeros(1, cycle.nv, dtype=F64)
    terms = cycle.dynamics(q, qd)
    s_g, s_f = cycle.dynet(q, q, qd, terms.mass, pose_difference(q, q))
    assert torch.all(s_g == 0.5) and torch.all(s_f == 0)
    torch.testing.assert_close(cycle.kp_ini[6:9], torch.tensor([1000.0] * 3, dtype=F64))  # spine kp
    for bad in (dict(iterations=0), dict(projection_metric="l1"), dict(push_out=2.0),
                dict(contact_sites=tuple(f"s{i}" for i in range(9)))):
        with pytest.raises(ValueError):
            dataclasses.replace(DiffPDConfig(), **bad)


def test_planted_foot_does_not_slide(walk):
    """A hand-made stance: walk frame 20 lowered onto the floor, the body thrown sideways and
    forwards at 1 m/s. After one step's projection the sole points in contact and within
    ``no_slip_height`` have zero horizontal velocity (they may still rise); without the no-slip
    constraint (the paper's frictionless projection) they slide on."""
    q, qd = _lowered(walk, [20], drop=0.0, vz=-0.3)
    qd[:, :2] += torch.tensor([[1.0, 1.0]], dtype=F64)
    speeds = {}
    for height in (0.0, 0.01):
        cycle = DynamicCycle(DiffPDConfig(no_slip_height=height), grfnet=None)
        terms = cycle.dynamics(q, qd)
        z = terms.points[0, :, 2]
        q_low = q.clone()
        q_low[0, 2] -= float(z.min()) + 0.002  # the lowest sole point 2 mm under the floor
        with torch.no_grad():
            out = cycle.step(q_low, qd, q_low)
        terms = cycle.dynamics(q_low, qd)
        planted = (terms.points[0, :, 2] <= 0.01)
        assert planted.sum() >= 2
        v = (terms.jacobian[0, :, :, :] @ out.qd[0])  # (P, 3) point velocities after the step
        speeds[height] = v[planted, :2].norm(dim=-1)
        z = terms.points[0, :, 2]
        assert torch.all(z + cycle.config.dt * v[:, 2] >= z.clamp(max=0.0) - 1e-9)  # none moves into the floor
    assert float(speeds[0.01].max()) < 1e-5, speeds[0.01]
    assert float(speeds[0.0].max()) > 0.1, speeds[0.0]


def test_fast_cycle_matches_torch_cycle(walk):
    """The NumPy forward pass used for cleaning (agents/diffpd_fast.py) is the torch cycle: 10 frames
    of DeepMimic walk from two starts with random network heads agree to round-off."""
    from agents.diffpd_fast import FastCycle

    torch.manual_seed(0)
    cycle = DynamicCycle.neural(DiffPDConfig(residual_bound=(200.0, 50.0)))
    _random_heads(cycle, 2)
    fast = FastCycle(cycle)
    q, qd = _lowered(walk, [0, 30], drop=0.005, vz=-0.2)
    qn, qdn = q.numpy().copy(), qd.numpy().copy()
    with torch.no_grad():
        for t in range(1, 11):
            target = torch.tensor(walk.qpos[[t, 30 + t]])
            out = cycle.frame(q, qd, target)
            q, qd = out.q, out.qd
            f = fast.frame(qn, qdn, target.numpy())
            qn, qdn = f.q, f.qd
            np.testing.assert_allclose(f.force, out.force.numpy(), rtol=1e-7, atol=1e-6)
            np.testing.assert_allclose(f.root_residual, out.root_residual.numpy(), rtol=1e-7, atol=1e-6)
    np.testing.assert_allclose(qn, q.numpy(), atol=1e-9)
    np.testing.assert_allclose(qdn, qd.numpy(), atol=1e-7)
