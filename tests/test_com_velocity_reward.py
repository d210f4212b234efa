"""The CoM-velocity term of the reward (MimicConfig.com_velocity_weight): the pure function on a
hand-made case, the steering pull it targets, the config's checks, and the term as the
environment computes it from MuJoCo's own CoM velocity."""

import math

import gymnasium as gym
import mujoco
import numpy as np
import pytest

from agents.sidecar import EnvSpec
from envs.config import MimicConfig
from envs.mimic import MimicEnv
from envs.observations import steering_pull
from envs.rewards import com_velocity_reward, mimic_reward


def test_the_term_is_exp_of_minus_alpha_times_the_horizontal_speed_error():
    # error (0.3, -0.4) on the ground: 0.5 m/s; the vertical velocity is not read
    assert com_velocity_reward(np.array([1.0, 0.2, 0.5]), np.array([0.7, 0.6]), 2.0) == pytest.approx(math.exp(-1.0))
    assert com_velocity_reward(np.array([1.0, 0.2, -3.0]), np.array([1.0, 0.2, 0.0]), 2.0) == 1.0
    batch = com_velocity_reward(np.array([[1.0, 0.2, 0.5], [0.0, 0.0, 0.0]]), np.array([[0.7, 0.6], [0.0, -0.1]]), 2.0)
    np.testing.assert_allclose(batch, [math.exp(-1.0), math.exp(-0.2)])


def test_the_term_is_weighted_inside_the_discount():
    faces, vel = np.zeros((2, 6, 3)), np.zeros((2, 6, 3))
    local = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    head = np.array([0.0, 0.0, 1.6])
    terms = mimic_reward(local, local, faces, faces, vel, vel, head, head + [0, 0.5, 0], r_still=0.5,
                         still_weight=2.0, r_com=0.25, com_weight=4.0)
    assert terms.r_com == 0.25 and terms.total == pytest.approx(0.6 * (3.0 + 2.0 * 0.5 + 4.0 * 0.25))
    assert mimic_reward(local, local, faces, faces, vel, vel, head, head, r_com=0.0).total == 3.0  # weight 0: ADAPT's


def test_the_pull_is_the_gain_times_the_offset_capped():
    com, ref_com = np.array([0.0, 0.0, 0.9]), np.array([0.3, -0.4, 1.0])
    np.testing.assert_allclose(steering_pull(com, ref_com, 1.0, 1.0), [0.3, -0.4])
    np.testing.assert_allclose(steering_pull(com, ref_com, 2.0, 0.5), [0.3, -0.4])  # |(0.6, -0.8)| = 1 capped to 0.5
    np.testing.assert_allclose(steering_pull(com, ref_com, 0.0, 0.5), [0.0, 0.0])
    np.testing.assert_allclose(steering_pull(np.zeros((2, 3)), np.stack([ref_com, -ref_com]), 1.0, 1.0),
                               [[0.3, -0.4], [-0.3, 0.4]])


@pytest.mark.parametrize("bad", [dict(com_velocity_weight=-1.0), dict(com_velocity_weight=math.inf),
                                 dict(com_velocity_alpha=0.0), dict(com_velocity_alpha=math.nan)])
def test_the_config_refuses_bad_settings(bad):
    with pytest.raises(ValueError, match="com_velocity_weight must be finite and >= 0"):
        MimicConfig(**bad)


def test_the_gait_task_refuses_the_term(walk):
    with pytest.raises(ValueError, match="MimicGait-v0 has ContactVision's own reward.*com_velocity_weight must be 0"):
        gym.make("MimicGait-v0", clips=[walk], config=MimicConfig(com_velocity_weight=1.0))


def test_the_env_rewards_its_com_velocity_against_the_steered_reference(walk):
    """Started 0.3 m behind the reference and stepped with random actions, the env's r_com equals
    the term of MuJoCo's own CoM velocity (subtree of the world body) against the judged
    reference's CoM velocity plus the pull back onto it, and w_com weighs it into the reward and its
    maximum."""
    config = MimicConfig(com_velocity_weight=1.5, steer_gain_hz=1.0)
    env = MimicEnv([walk], episode_frames=60, config=config)
    assert env.max_step_reward == 4.5
    env.reset(seed=0, options={"clip": 0, "start_frame": 10})
    qpos, qvel = env.data.qpos.copy(), env.data.qvel.copy()
    qpos[0] -= 0.3
    env.reset(seed=0, options={"clip": 0, "start_frame": 10, "state": (qpos, qvel)})
    rng = np.random.default_rng(0)
    values = []
    for _ in range(6):
        _, reward, _, _, info = env.step(rng.uniform(-0.2, 0.2, env.action_space.shape).astype(np.float32))
        m, d = env.model, env.data
        mujoco.mj_subtreeVel(m, d)
        ref, frame = env.judging_track, info["frame"]
        pull = 1.0 * (ref.com[frame, :2] - d.subtree_com[0, :2])  # gain 1/s, capped at 0.5 m/s
        target = ref.com_vel[frame, :2] + pull * min(1.0, 0.5 / np.linalg.norm(pull))
        expected = math.exp(-config.com_velocity_alpha * np.linalg.norm(d.subtree_linvel[0, :2] - target))
        assert info["r_com"] == pytest.approx(expected, rel=1e-5)
        assert reward == pytest.approx(info["e_discount"] * (info["r_local"] + info["r_p"] + info["r_v"]
                                                              + 1.5 * info["r_com"]))
        values.append(info["r_com"])
    assert min(values) < 0.9  # 0.3 m behind: the pull alone is 0.3 m/s of error


def test_a_config_recorded_before_the_term_existed_is_the_same_spec():
    legacy = {k: v for k, v in EnvSpec().config.items() if not k.startswith("com_velocity")}
    assert EnvSpec(config=legacy) == EnvSpec()
    assert EnvSpec(config=legacy).mimic_config() == MimicConfig()
