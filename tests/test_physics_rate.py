"""The physics rate of a mimic task (MimicConfig.physics_rate_hz, envs.physics): finer steps, stiffer contacts."""

import copy
from pathlib import Path

import gymnasium as gym
import mujoco
import numpy as np
import pytest

import envs  # noqa: F401  (registers the environments)
from agents.adaptation import adaptation_key
from agents.policy import load_policy
from envs.config import MimicConfig
from envs.physics import at_physics_rate, contact_time_constants, model_rate_hz
from reference_motion.humanoid.model import load_model


def test_the_models_own_rate_is_the_model_itself():
    model = load_model("humanoid_1seg").model
    assert model_rate_hz(model) == pytest.approx(120.0, rel=1e-5)
    assert at_physics_rate(model, 120.0) is model


def test_mujoco_raises_a_contact_time_constant_to_two_steps_unless_its_guard_is_off():
    model = copy.deepcopy(load_model("humanoid_1seg").model)
    assert np.allclose(model.geom_solref[:, 0], 0.01)
    assert np.allclose(contact_time_constants(model), 2 / 120)  # the 0.01 s asked for is under two steps
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_REFSAFE)
    assert np.allclose(contact_time_constants(model), 0.01)


def test_a_finer_rate_copies_the_model_with_contacts_two_steps_stiff():
    model = load_model("humanoid_1seg").model
    own = model.geom_solref.copy()
    fine = at_physics_rate(model, 480.0)
    assert fine is not model and fine.opt.timestep == pytest.approx(1 / 480)
    # the model asks for 0.01 s, which MuJoCo raises to two 1/120 s steps; at 480 Hz two steps are 1/240 s
    assert np.allclose(fine.geom_solref[:, 0], 2 / 480) and np.array_equal(fine.geom_solref[:, 1], own[:, 1])
    # the shared, cached model is untouched
    assert model.opt.timestep == pytest.approx(1 / 120) and np.array_equal(model.geom_solref, own)
    # a coarser rate never makes contacts softer than MuJoCo's floor at that rate would anyway
    assert np.allclose(at_physics_rate(model, 60.0).geom_solref[:, 0], 2 / 120)


def test_rates_that_are_not_whole_steps_per_frame_are_refused():
    with pytest.raises(ValueError, match="physics_rate_hz must be a whole multiple of frame_rate_hz"):
        MimicConfig(physics_rate_hz=100.0)
    with pytest.raises(ValueError, match="physics_rate_hz"):
        MimicConfig(physics_rate_hz=30.0)
    with pytest.raises(ValueError, match="physics rate must be positive"):
        at_physics_rate(load_model("humanoid_1seg").model, 0.0)


def lowest_points(rate_hz: float, steps: int = 12) -> np.ndarray:
    """Lowest body point (m) after each of ``steps`` zero-action control steps from walk's first frame."""
    env = gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=None,
                   config=MimicConfig(physics_rate_hz=rate_hz))
    base = env.unwrapped
    env.reset(seed=0, options={"start_frame": 0})
    low = []
    for _ in range(steps):
        env.step(np.zeros(env.action_space.shape, np.float32))
        low.append(base.humanoid.forward_kinematics(base.data.qpos[None]).lowest[0])
    return np.array(low), base


def test_at_480_hz_the_stance_foot_sinks_a_tenth_as_deep():
    coarse, base_120 = lowest_points(120.0)
    fine, base_480 = lowest_points(480.0)
    assert base_120.substeps == 2 and base_480.substeps == 8
    # measured: 5.1 mm at most at 120 Hz, 0.4 mm at 480 Hz (the same reference, the same actions)
    assert -coarse.min() > 0.003
    assert -fine.min() < 0.1 * -coarse.min()


def test_a_policy_can_run_at_a_finer_physics_rate(walk):
    policy = load_policy(Path(__file__).parents[1] / "models" / "mimic_walk")
    assert policy.record.env.mimic_config().physics_rate_hz == 120.0  # every sidecar before the field: 120 Hz
    assert policy.simulating(120.0) is policy
    fine = policy.simulating(480.0)
    assert fine.record.env.mimic_config().physics_rate_hz == 480.0 and fine.record.extra["simulated_at"] == 120.0
    assert fine.model is policy.model
    env = fine.make_env([walk], artefacts=None)
    assert env.unwrapped.substeps == 8
    # adapting the weights at another rate is adapting another policy; back at 120 Hz it is the original
    assert adaptation_key(walk, fine) != adaptation_key(walk, policy)
    assert adaptation_key(walk, fine.simulating(120.0)) == adaptation_key(walk, policy)
    with pytest.raises(ValueError, match="physics_rate_hz"):
        policy.simulating(100.0)
