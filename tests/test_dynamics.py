"""Randomised physics for training (envs.config.Dynamics, envs.physics.draw_physics/apply_physics,
MimicEnv(dynamics=...), train_ppo.py --dynamics)."""

import copy
import json

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import envs  # noqa: F401  (registers the environments)
from agents.policy import load_policy
from agents.train_ppo import main
from envs.bodies import read_body_state
from envs.config import Dynamics
from envs.physics import PhysicsDraw, apply_physics, draw_physics
from reference_motion.humanoid.model import load_model

WALK = ["deepmimic:walk"]


def test_apply_physics_scales_the_nominal_fields_and_nothing_adds_up():
    nominal = load_model("humanoid_1seg").model
    model = copy.deepcopy(nominal)
    mass, strength = np.ones(model.nbody), np.ones(model.nu)
    mass[1], strength[0] = 2.0, 1.5
    data = mujoco.MjData(model)
    draw = PhysicsDraw(mass=mass, friction=0.5, strength=strength)
    for _ in range(2):  # a second call gives the same model, not the factors squared
        apply_physics(model, data, nominal, draw)
        assert model.body_mass[1] == pytest.approx(2.0 * nominal.body_mass[1])
        assert model.body_subtreemass[1] == pytest.approx(model.body_mass[1:].sum())  # derived anew
        np.testing.assert_allclose(model.body_inertia[1], 2.0 * nominal.body_inertia[1])
        np.testing.assert_array_equal(model.body_mass[2:], nominal.body_mass[2:])
        np.testing.assert_allclose(model.geom_friction[:, 0], 0.5 * nominal.geom_friction[:, 0])
        np.testing.assert_array_equal(model.geom_friction[:, 1:], nominal.geom_friction[:, 1:])  # torsion, rolling
        kp, kv = nominal.actuator_gainprm[0, 0], -nominal.actuator_biasprm[0, 2]
        assert (model.actuator_gainprm[0, 0], -model.actuator_biasprm[0, 1], -model.actuator_biasprm[0, 2]) == \
            pytest.approx((1.5 * kp, 1.5 * kp, 1.5 * kv))
        np.testing.assert_array_equal(model.actuator_gainprm[1:, 0], nominal.actuator_gainprm[1:, 0])
    assert nominal.body_mass.sum() == pytest.approx(70.0)  # the shared, cached model is untouched
    with pytest.raises(ValueError, match="draw for 3 bodies"):
        apply_physics(model, data, nominal, PhysicsDraw(np.ones(3), 1.0, strength))


def test_a_stronger_actuator_pushes_harder_by_its_factor():
    """A position actuator's force kp·(ctrl − q) − kv·q̇ scales with the strength factor."""
    nominal = load_model("humanoid_1seg").model
    model = copy.deepcopy(nominal)
    forces = []
    for factor in (1.0, 1.2):
        data = mujoco.MjData(model)
        apply_physics(model, data, nominal, PhysicsDraw(np.ones(model.nbody), 1.0, np.full(model.nu, factor)))
        data.qvel[6:] = 0.5
        data.ctrl[:] = 0.3
        mujoco.mj_forward(model, data)
        forces.append(data.actuator_force.copy())
    assert np.abs(forces[0]).min() > 1.0
    np.testing.assert_allclose(forces[1], 1.2 * forces[0], rtol=1e-9)


def test_a_target_offset_moves_where_the_actuator_holds_the_joint():
    """With offset b the actuator applies kp·(ctrl + b − q) − kv·q̇: the force of a target b further."""
    nominal = load_model("humanoid_1seg").model
    model = copy.deepcopy(nominal)
    offset = np.radians(np.linspace(-3.0, 3.0, model.nu))
    middle = model.actuator_ctrlrange.mean(axis=1)  # targets well inside every control range
    forces = []
    for ctrl, draw in ((middle + offset, PhysicsDraw.nominal(model)),
                       (middle, PhysicsDraw(np.ones(model.nbody), 1.0, np.full(model.nu, 1.2), offset))):
        data = mujoco.MjData(model)
        apply_physics(model, data, nominal, draw)
        data.qpos[model.jnt_qposadr[model.actuator_trnid[:, 0]]] = middle
        data.qvel[6:] = 0.1
        data.ctrl[:] = ctrl
        mujoco.mj_forward(model, data)
        forces.append(data.actuator_force.copy())
    assert np.abs(forces[0]).max() < 300.0 and np.abs(forces[0]).mean() > 5.0  # inside the force limits, not zero
    np.testing.assert_allclose(forces[1], 1.2 * forces[0], rtol=1e-9)  # strength 1.2 on the same PD error
    apply_physics(model, data, nominal, PhysicsDraw.nominal(model))
    assert not model.actuator_biasprm[:, 0].any()  # no offset left behind


def test_draws_fall_in_their_ranges_and_a_zero_range_is_the_nominal_body():
    model = load_model("humanoid_1seg").model
    rng = np.random.default_rng(0)
    draws = [draw_physics(Dynamics(mass=0.2, friction=0.4, strength=0.1), model, rng) for _ in range(50)]
    masses = np.stack([d.mass for d in draws])
    assert masses.min() >= 0.8 and masses.max() <= 1.2 and masses.std() > 0.08  # uniform on ±0.2: std 0.115
    assert all(0.6 <= d.friction <= 1.4 for d in draws) and len({d.friction for d in draws}) == 50
    assert all(0.9 <= d.strength.min() and d.strength.max() <= 1.1 for d in draws)
    still = draw_physics(Dynamics(0.0, 0.0, 0.0), model, rng)
    assert still.friction == 1.0 and (still.mass == 1.0).all() and (still.strength == 1.0).all()
    assert still.offset is None
    offsets = np.degrees(np.stack([draw_physics(Dynamics(offset_deg=3.5), model, rng).offset for _ in range(20)]))
    assert offsets.shape == (20, model.nu) and np.abs(offsets).max() <= 3.5 and 1.6 < offsets.std() < 2.4  # 3.5/√3
    with pytest.raises(ValueError, match=r"Dynamics.offset_deg must be a half-range in \[0, 30\] degrees"):
        Dynamics(offset_deg=45.0)
    for bad in ({"mass": 1.0}, {"friction": -0.1}, {"strength": float("nan")}):
        with pytest.raises(ValueError, match=r"Dynamics\.\w+ must be a half-range in \[0, 1\)"):
            Dynamics(**bad)


def test_each_training_episode_gets_its_own_body_and_evaluation_the_nominal_one():
    varied = gym.make("MimicIMU-v0", clips=WALK, dynamics=Dynamics()).unwrapped
    nominal = gym.make("MimicIMU-v0", clips=WALK).unwrapped
    varied.reset(seed=3, options={"start_frame": 0})
    first = varied.model.body_mass.copy()
    assert abs(first.sum() - 70.0) > 0.01 and varied.physics_draw.friction != 1.0
    varied.reset(options={"start_frame": 240})  # 4 s into the walk: metres from the origin
    assert not np.allclose(varied.model.body_mass, first)
    np.testing.assert_allclose(varied.model.body_mass, varied._nominal_model.body_mass * varied.physics_draw.mass)
    varied.step(np.zeros(20, np.float32))
    m, d = varied.model, varied.data  # away from the origin, where a stale subtree mass would shift the CoM
    true_com = (m.body_mass[1:, None] * d.xipos[1:]).sum(axis=0) / m.body_mass[1:].sum()
    assert np.linalg.norm(d.xipos[1, :2]) > 1.0
    np.testing.assert_allclose(read_body_state(m, d).com, true_com, atol=1e-9)
    nominal.reset(seed=3, options={"start_frame": 0})
    assert nominal.model.body_mass.sum() == pytest.approx(70.0) and nominal.physics_draw.friction == 1.0
    assert load_model("humanoid_1seg").model.body_mass.sum() == pytest.approx(70.0)  # the cached model untouched
    # zero half-ranges: the very episode the nominal env plays, step for step (the first episode: the
    # draws still take numbers from the env's generator, so later episodes start elsewhere)
    zero = gym.make("MimicIMU-v0", clips=WALK, dynamics=Dynamics(0.0, 0.0, 0.0)).unwrapped
    for env in (zero, nominal):
        env.reset(seed=5, options={"start_frame": 30})
        for _ in range(10):
            env.step(np.full(20, 0.1, np.float32))
    np.testing.assert_array_equal(zero.data.qpos, nominal.data.qpos)
    with pytest.raises(TypeError, match="dynamics must be an envs.config.Dynamics"):
        gym.make("MimicIMU-v0", clips=WALK, dynamics={"mass": 0.1})


def test_a_run_with_randomised_physics_records_it_and_its_policy_acts_in_the_nominal_body(tmp_path):
    run = tmp_path / "dr"
    main(["--clips", "deepmimic:walk", "--dynamics", "0.1", "0.2", "0.05", "--total-steps", "256", "--run-dir",
          str(run), "--no-progress", "--n-envs", "2", "--n-steps", "128", "--batch-size", "64", "--eval-every", "256",
          "--eval-episodes", "1", "--net", "16,16"])
    policy = load_policy(run / "best")
    assert policy.record.training.dynamics == {"mass": 0.1, "friction": 0.2, "strength": 0.05, "offset_deg": 0.0}
    assert json.loads((run / "args.json").read_text())["dynamics"] == [0.1, 0.2, 0.05]
    assert policy.make_env(WALK).unwrapped.dynamics is None  # what the policy is judged and cleans on
    with pytest.raises(SystemExit, match=r"--dynamics 0.1 0.1 1.5 --pd-offset 0: Dynamics.strength must be"):
        main(["--clips", "no:such_clip", "--dynamics", "0.1", "0.1", "1.5", "--run-dir", str(tmp_path / "x")])
    with pytest.raises(SystemExit, match="--dynamics and --pd-offset randomise MimicEnv's humanoid; MimicGait-v0"):
        main(["--env-id", "MimicGait-v0", "--clips", "deepmimic:walk", "--pd-offset", "2",
              "--run-dir", str(tmp_path / "x")])
