"""Steering the observed reference velocities back onto the reference's position
(MimicConfig.steer_gain_hz): the pure function, the config's checks, the observation it changes,
and what it does for a shipped policy that never trained with it."""

from pathlib import Path

import numpy as np
import pytest

from agents.evaluation import evaluate
from agents.policy import load_policy
from envs.config import MimicConfig
from envs.mimic import MimicEnv
from envs.observations import steered_velocities

MODELS = Path(__file__).parents[1] / "models"


def test_steering_adds_the_gain_times_the_horizontal_offset_to_every_reference_velocity():
    com, ref_com = np.array([0.0, 0.0, 0.90]), np.array([0.2, -0.1, 0.95])
    ref_com_vel = np.array([1.0, 0.0, 0.1])
    ref_linvel = np.array([[1.0, 0.0, 0.1], [0.5, 0.5, -0.2]], dtype=np.float32)
    com_vel, linvel = steered_velocities(com, ref_com, ref_com_vel, ref_linvel, gain_hz=2.0, max_speed_mps=1.0)
    # pull = 2/s × (0.2, −0.1) m = (0.4, −0.2) m/s on the ground; z untouched
    np.testing.assert_allclose(com_vel, [1.4, -0.2, 0.1])
    np.testing.assert_allclose(linvel, [[1.4, -0.2, 0.1], [0.9, 0.3, -0.2]], rtol=1e-6)
    assert linvel.dtype == np.float32 and com_vel.dtype == ref_com_vel.dtype
    np.testing.assert_array_equal(ref_com_vel, [1.0, 0.0, 0.1])  # inputs not modified


def test_steering_caps_the_pull_and_keeps_its_direction():
    # offset (0.3, 0.4) m (0.5 m) at 4/s would pull at 2 m/s; capped at 0.5 m/s along (0.6, 0.8)
    com_vel, _ = steered_velocities(np.zeros(3), np.array([0.3, 0.4, 0.0]), np.zeros(3), np.zeros((1, 3)),
                                    gain_hz=4.0, max_speed_mps=0.5)
    np.testing.assert_allclose(com_vel, [0.3, 0.4, 0.0])


def test_no_gain_and_a_batch():
    ref_com_vel, ref_linvel = np.ones(3), np.ones((4, 3))
    unchanged = steered_velocities(np.zeros(3), np.ones(3), ref_com_vel, ref_linvel, 0.0, 0.5)
    assert unchanged[0] is ref_com_vel and unchanged[1] is ref_linvel
    # two characters at once: each gets its own pull
    com = np.array([[0.0, 0.0, 1.0], [0.1, 0.0, 1.0]])
    com_vel, linvel = steered_velocities(com, np.zeros((2, 3)), np.zeros((2, 3)), np.zeros((2, 4, 3)), 1.0, 0.5)
    np.testing.assert_allclose(com_vel, [[0, 0, 0], [-0.1, 0, 0]])
    np.testing.assert_allclose(linvel[1], np.tile([-0.1, 0, 0], (4, 1)))


@pytest.mark.parametrize("gain, cap", [(-1.0, 0.5), (np.nan, 0.5), (1.0, 0.0), (1.0, np.inf)])
def test_the_config_refuses_a_bad_gain_or_cap(gain, cap):
    with pytest.raises(ValueError, match="steer_gain_hz must be finite and >= 0"):
        MimicConfig(steer_gain_hz=gain, steer_max_speed_mps=cap)


def test_the_observation_shows_the_pull_towards_the_reference(walk):
    """The character started 0.3 m behind the reference (along −x) observes, at gain 1/s, a reference
    CoM velocity 0.3 m/s higher along +x than without steering, and the same in every other entry
    but the body velocity differences; at the reference state the two observations are equal."""
    def observe(gain, shift):
        env = MimicEnv([walk], episode_frames=60, config=MimicConfig(steer_gain_hz=gain))
        obs, _ = env.reset(seed=0, options={"clip": 0, "start_frame": 10})
        qpos, qvel = env.data.qpos.copy(), env.data.qvel.copy()
        qpos[0] -= shift
        obs, _ = env.reset(seed=0, options={"clip": 0, "start_frame": 10, "state": (qpos, qvel)})
        return obs, env.obs_slices

    plain, slices = observe(0.0, 0.3)
    steered, _ = observe(1.0, 0.3)
    np.testing.assert_allclose(steered[slices["ref_v_com"]] - plain[slices["ref_v_com"]], [0.3, 0.0, 0.0], atol=1e-4)
    np.testing.assert_allclose(steered[slices["dv_com"]] - plain[slices["dv_com"]], [-0.3, 0.0, 0.0], atol=1e-4)
    np.testing.assert_allclose(steered[slices["dv"]].reshape(-1, 3) - plain[slices["dv"]].reshape(-1, 3),
                               np.tile([-0.3, 0.0, 0.0], (len(steered[slices["dv"]]) // 3, 1)), atol=1e-4)
    for name in ("v_com", "p", "v", "dp", "prev_action"):
        np.testing.assert_array_equal(steered[slices[name]], plain[slices[name]])
    np.testing.assert_allclose(observe(1.0, 0.0)[0], observe(0.0, 0.0)[0], atol=1e-6)


def test_a_shipped_policy_steered_keeps_closer_to_the_reference():
    """``mimic_general_robust`` never trained with steering; run with a gain of 1/s on a held-out
    DeepMimic walker it still performs it whole and its root keeps much closer to the reference's
    (RDE 0.176 → 0.109 m² when measured)."""
    policy = load_policy(MODELS / "mimic_general_robust")
    steered = policy.steering(1.0)
    assert steered.record.extra["steered_at"] == 0.0 and policy.steering(0.0) is policy
    capped = policy.steering(1.0, 0.8)
    assert capped.record.env.mimic_config().steer_max_speed_mps == 0.8
    assert capped.record.extra["steer_capped_at"] == 0.5 and capped.record.extra["steered_at"] == 0.0
    assert policy.steering(0.0, 0.5) is policy
    with pytest.raises(ValueError, match="steer_max_speed_mps"):
        policy.steering(1.0, -1.0)
    results = {}
    for name, p in (("plain", policy), ("steered", steered)):
        env = p.make_env(["deepmimic:walker/turn_left1"], artefacts=None)
        assert env.unwrapped.config.steer_gain_hz == (1.0 if name == "steered" else 0.0)
        results[name] = evaluate(env, p, episodes=1)[0]
    assert results["plain"]["ELR_mean"] == results["steered"]["ELR_mean"] == 1.0
    assert results["steered"]["RDE_mean"] < 0.75 * results["plain"]["RDE_mean"]


def test_clean_performs_with_the_gain_asked_for():
    from agents.clean import build_parser, performing_policy

    policy = load_policy(MODELS / "mimic_general_robust")
    args = build_parser().parse_args(["deepmimic:walk", "--policy", str(MODELS / "mimic_general_robust"),
                                      "--out", "x.npz", "--steer-gain", "0.5", "--physics-rate-hz", "240"])
    task = performing_policy(policy, args).record.env.mimic_config()
    assert (task.steer_gain_hz, task.physics_rate_hz) == (0.5, 240.0)
    as_given = build_parser().parse_args(["deepmimic:walk", "--policy", str(MODELS / "mimic_general_robust"),
                                        "--out", "x.npz"])
    assert performing_policy(policy, as_given) is policy
