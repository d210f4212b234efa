"""Rewards, terminations and observation pieces of the mimic task on hand-made states."""

import math

import numpy as np
import pytest

from envs.observations import mimic_observation, observation_size, observation_slices
from envs.rewards import (MAX_STEP_REWARD, cube_face_points, cube_face_velocities, fall_discount, fallen, lagging,
                          local_pose_reward, mimic_reward, point_reward, unstable)
from reference_motion import rotations as rot

Z = np.array([0.0, 0.0, 1.0])


def _pose(n_bodies=3, seed=0):
    rng = np.random.default_rng(seed)
    quat = rot.normalize(rng.standard_normal((n_bodies, 4)))
    pos = rng.standard_normal((n_bodies, 3))
    return pos, quat, rot.to_matrix(quat).transpose(0, 2, 1)


def test_identical_pose_gives_all_ones():
    pos, quat, axes = _pose()
    faces = cube_face_points(pos - pos[0], axes)
    vel = cube_face_velocities(np.ones((3, 3)), np.full((3, 3), 0.5), axes)
    local = rot.relative_to_parent(quat, np.array([-1, 0, 1]))
    terms = mimic_reward(local, local, faces, faces, vel, vel, pos[2], pos[2])
    assert (terms.r_local, terms.r_p, terms.r_v, terms.e_discount) == (1.0, 1.0, 1.0, 1.0)
    assert terms.total == MAX_STEP_REWARD == 3.0


def test_cube_faces_sit_half_an_edge_from_the_origin_along_each_axis():
    axes = np.eye(3)[None]
    faces = cube_face_points(np.array([[1.0, 2.0, 3.0]]), axes)[0]
    assert np.allclose(faces, [[1.5, 2, 3], [1, 2.5, 3], [1, 2, 3.5], [0.5, 2, 3], [1, 1.5, 3], [1, 2, 2.5]])
    # spinning at 2 rad/s about z: the +x face moves at (0, 1, 0), the +z face not at all
    vel = cube_face_velocities(np.zeros((1, 3)), np.array([[0.0, 0.0, 2.0]]), axes)[0]
    assert np.allclose(vel[0], [0, 1, 0]) and np.allclose(vel[2], 0) and np.allclose(vel[3], [0, -1, 0])


def test_known_offsets_give_the_hand_computed_rewards():
    # r_local: two joints, one turned 0.4 rad -> mean angle 0.2 rad -> exp(-2.5 * 0.2)
    ident = np.array([[1.0, 0, 0, 0], [1.0, 0, 0, 0]])
    turned = ident.copy()
    turned[1] = rot.from_axis_angle(Z, 0.4)
    assert local_pose_reward(turned, ident, 2.5) == pytest.approx(math.exp(-0.5))
    # r_p: two bodies, one moved 0.1 m -> 6 faces x 0.1 m / 2 bodies = 0.3 -> exp(-0.3)
    axes = np.stack([np.eye(3)] * 2)
    pos = np.zeros((2, 3))
    ref = cube_face_points(pos, axes)
    moved = cube_face_points(pos + [[0, 0, 0], [0.1, 0, 0]], axes)
    assert point_reward(moved, ref, 1.0) == pytest.approx(math.exp(-0.3))
    # r_p: one body yawed by 60 deg -> its ±x and ±y faces each move sin(30 deg) = 0.5 m: 4 x 0.5 / 2
    yawed = cube_face_points(pos, np.stack([np.eye(3), rot.to_matrix(rot.from_axis_angle(Z, np.pi / 3)).T]))
    assert point_reward(yawed, ref, 1.0) == pytest.approx(math.exp(-1.0))
    # r_v: one body 1 m/s faster -> 6 x 1 / 2 = 3 -> exp(-0.1 * 3)
    v0 = cube_face_velocities(np.zeros((2, 3)), np.zeros((2, 3)), axes)
    v1 = cube_face_velocities(np.array([[0, 0, 0], [1.0, 0, 0]]), np.zeros((2, 3)), axes)
    assert point_reward(v1, v0, 0.1) == pytest.approx(math.exp(-0.3))
    # total: e_discount scales the sum
    terms = mimic_reward(turned, ident, moved, ref, v1, v0, np.zeros(3), np.array([0.0, 0.5, 0.0]))
    assert terms.e_discount == pytest.approx(0.6)
    assert terms.total == pytest.approx(0.6 * (math.exp(-0.5) + math.exp(-0.3) + math.exp(-0.3)))


def test_fall_discount_of_eq_9():
    head = np.array([0.0, 0.0, 1.6])
    assert fall_discount(head, head + [0.9, 0, 0]) == pytest.approx(0.04)
    assert fall_discount(head, head + [0, 0.1, 0]) == 1.0  # 1.16 clamped
    assert fall_discount(head, head + [0, 0, -1.0]) == 0.0  # -0.1 clamped


def test_terminations():
    assert fallen(3) and fallen(6) and not fallen(2)
    assert lagging(0.02) and not lagging(0.04)
    qvel = np.zeros(49)
    assert not unstable(qvel, 200.0)
    qvel[10] = np.nan
    assert unstable(qvel, 200.0)
    qvel[10] = 1e4
    assert unstable(qvel, 200.0)


def test_local_rotations_undo_the_parent():
    q_root = rot.from_axis_angle(Z, 0.7)
    q_child_local = rot.from_axis_angle(np.array([0.0, 1.0, 0.0]), -0.3)
    world = np.stack([q_root, rot.multiply(q_root, q_child_local)])
    local = rot.relative_to_parent(world, np.array([-1, 0]))
    assert np.allclose(local[0], q_root) and np.allclose(local[1], q_child_local)
    # batched over frames too
    assert np.allclose(rot.relative_to_parent(np.stack([world, world]), np.array([-1, 0]))[1], local)


def test_observation_layout_is_adapt_table_1():
    slices = observation_slices(20, 20)
    assert observation_size(20, 20) == 273 == slices["prev_action"].stop
    assert [k for k in slices] == ["v_com", "ref_v_com", "dv_com", "ref_v_hor", "dv_hor", "p", "v", "dp", "dv",
                                   "prev_action"]
    rng = np.random.default_rng(1)
    pos, vel = rng.standard_normal((20, 3)), rng.standard_normal((20, 3))
    com, com_vel, ref_com_vel = np.array([1.0, 2, 3]), np.array([0.5, 0, 0]), np.array([0.2, 0.1, 0])
    action = np.arange(20.0)
    obs = mimic_observation(pos, vel, com, com_vel, pos - com, vel + 1.0, ref_com_vel, action)
    assert obs.dtype == np.float32 and obs.shape == (273,)
    assert np.allclose(obs[slices["dv_com"]], [0.3, -0.1, 0])
    assert np.allclose(obs[slices["ref_v_hor"]], [0.2, 0.1])
    assert np.allclose(obs[slices["p"]], (pos - com).ravel(), atol=1e-6)
    assert np.allclose(obs[slices["dp"]], 0.0) and np.allclose(obs[slices["dv"]], -1.0)
    assert np.array_equal(obs[slices["prev_action"]], action)
