"""Rewards, terminations and observation pieces of the mimic task on hand-made states."""

import math

import numpy as np
import pytest

from envs.config import GaitConfig
from envs.observations import (gait_observation, gait_observation_slices, heading_rotation, lookahead_observation,
                               mimic_observation, observation_size, observation_slices)
from envs.rewards import (GAIT_TERMS, MAX_STEP_REWARD, body_points, com_velocity_reward, contact_mismatches,
                          contact_reward, cube_face_points, cube_face_velocities, end_effector_reward, fall_discount, fallen,
                          gait_reward, joint_pose_reward, joint_velocity_reward, lagging, local_pose_reward,
                          mimic_reward, point_reward, root_orientation_reward, still_feet_reward, torque_reward,
                          unstable, upper_body_reward, upper_body_tilt)
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


def test_body_points_by_hand():
    # a body at (1, 0, 0) yawed 90 deg, spinning at 2 rad/s about z and moving at (0, 0, 1) m/s; a point
    # 0.5 m along its x axis sits at (1, 0.5, 0) and moves at (0, 0, 1) + 2 z x (0, 0.5, 0) = (-1, 0, 1)
    axes = rot.to_matrix(rot.from_axis_angle(Z, np.pi / 2)).T[None]
    points, vel = body_points(np.array([[1.0, 0, 0]]), axes, np.array([[0, 0, 1.0]]), np.array([[0, 0, 2.0]]),
                              np.array([[0.5, 0, 0]]))
    assert np.allclose(points, [[1, 0.5, 0]]) and np.allclose(vel, [[-1, 0, 1]])


def test_still_feet_reward_counts_the_horizontal_speed_of_points_near_the_floor():
    vel = np.array([[0.3, 0.4, 0.0],    # 0.5 m/s sliding, 1 cm up: counts
                    [0.0, 0.2, -0.9],   # 0.2 m/s sliding (its vertical speed does not count), on the floor
                    [2.0, 0.0, 0.0],    # swinging 3 cm up: does not count
                    [0.0, 0.0, 0.0]])   # standing still
    height = np.array([0.01, 0.0, 0.03, 0.0])
    assert still_feet_reward(vel, height, 0.02, 5.0) == pytest.approx(math.exp(-5.0 * 0.7))
    assert still_feet_reward(np.zeros((4, 3)), height, 0.02, 5.0) == 1.0
    assert np.allclose(still_feet_reward(np.stack([vel, np.zeros((4, 3))]), np.stack([height] * 2), 0.02, 5.0),
                       [math.exp(-3.5), 1.0])
    # weighted into the total inside e_discount's bracket
    pos, quat, axes = _pose()
    faces = cube_face_points(pos - pos[0], axes)
    face_vel = cube_face_velocities(np.ones((3, 3)), np.zeros((3, 3)), axes)
    local = rot.relative_to_parent(quat, np.array([-1, 0, 1]))
    terms = mimic_reward(local, local, faces, faces, face_vel, face_vel, pos[2], pos[2] + [0, 0.5, 0],
                         r_still=0.25, still_weight=2.0)
    assert terms.r_still == 0.25 and terms.total == pytest.approx(0.6 * (3.0 + 2.0 * 0.25))


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


def test_heading_rotation_by_hand():
    # a pelvis facing +y (x axis along world y, tilted down a little): a 90° yaw back to +x
    r = heading_rotation(np.array([0.0, 0.8, -0.6]))
    assert np.allclose(r @ [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]) and np.allclose(r @ [1.0, 0.0, 0.0], [0.0, -1.0, 0.0])
    assert np.allclose(r @ [0.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    assert np.array_equal(heading_rotation(np.array([0.0, 0.0, 1.0])), np.eye(3))  # no heading: identity


def test_heading_frame_observation_is_the_same_whichever_way_the_character_faces():
    slices = observation_slices(20, 20, com_offset=True)
    assert observation_size(20, 20, com_offset=True) == 276 == slices["prev_action"].stop
    assert slices["dp_com"] == slice(13, 16)
    rng = np.random.default_rng(2)
    pos, vel, ref_rel, ref_vel = (rng.standard_normal((20, 3)) for _ in range(4))
    com, com_vel, ref_com, ref_com_vel = (rng.standard_normal(3) for _ in range(4))
    action = np.arange(20.0)
    root_x = np.array([1.0, 0.0, 0.2])  # facing +x: the heading frame is the world frame
    facing_x = mimic_observation(pos, vel, com, com_vel, ref_rel, ref_vel, ref_com_vel, action,
                                 heading_rotation(root_x), ref_com)
    world = mimic_observation(pos, vel, com, com_vel, ref_rel, ref_vel, ref_com_vel, action)
    assert np.allclose(np.delete(facing_x, slices["dp_com"]), world, atol=1e-6)
    assert np.allclose(facing_x[slices["dp_com"]], com - ref_com, atol=1e-6)
    # the whole scene (character and reference) yawed by 40° about the world origin: same observation
    c, s = np.cos(0.7), np.sin(0.7)
    yaw = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    turned = mimic_observation(pos @ yaw.T, vel @ yaw.T, yaw @ com, yaw @ com_vel, ref_rel @ yaw.T, ref_vel @ yaw.T,
                               yaw @ ref_com_vel, action, heading_rotation(yaw @ root_x), yaw @ ref_com)
    assert np.allclose(turned, facing_x, atol=1e-5)
    # a turn without dp_com (the "reference" frame): ADAPT's layout, every vector turned
    r = heading_rotation(yaw @ root_x)
    no_offset = mimic_observation(pos, vel, com, com_vel, ref_rel, ref_vel, ref_com_vel, action, r)
    assert no_offset.shape == (273,) and np.allclose(no_offset[:3], r @ com_vel, atol=1e-6)


def test_world_frame_observation_with_the_com_offset_is_adapts_plus_dp_com():
    """ref_com without heading: ADAPT's world-frame vector with dp_com = com − ref_com inserted at 13:16."""
    slices = observation_slices(20, 20, com_offset=True)
    rng = np.random.default_rng(3)
    pos, vel, ref_rel, ref_vel = (rng.standard_normal((20, 3)) for _ in range(4))
    com, com_vel, ref_com_vel = (rng.standard_normal(3) for _ in range(3))
    action = np.arange(20.0)
    ref_com = com - np.array([0.3, -0.4, 0.05])  # the character 0.3 m ahead in x, 0.4 m behind in y, 5 cm high
    world = mimic_observation(pos, vel, com, com_vel, ref_rel, ref_vel, ref_com_vel, action)
    offset = mimic_observation(pos, vel, com, com_vel, ref_rel, ref_vel, ref_com_vel, action, ref_com=ref_com)
    assert offset.shape == (276,) and np.allclose(offset[slices["dp_com"]], [0.3, -0.4, 0.05], atol=1e-6)
    assert np.array_equal(np.delete(offset, slices["dp_com"]), world)


def test_lookahead_by_hand():
    """Two future frames of a 2-body reference, in world axes and in axes turned 90° (x ← world y)."""
    slices = observation_slices(20, 20, lookahead_steps=3)
    assert slices["lookahead"] == slice(273, 273 + 3 * 66) and observation_size(20, 20, lookahead_steps=3) == 471
    ref_com = np.array([1.0, 2.0, 0.9])
    ahead_com = np.array([[1.1, 2.0, 0.9], [1.5, 2.2, 0.8]])  # 0.1 m then 0.5 m ahead in x
    ahead_com_vel = np.array([[1.0, 0.0, 0.0], [1.2, 0.4, -0.1]])
    ahead_pos_rel = np.array([[[0.0, 0.0, 0.1], [0.2, 0.0, -0.8]], [[0.0, 0.1, 0.0], [0.0, -0.2, -0.8]]])
    world = lookahead_observation(ref_com, ahead_com, ahead_com_vel, ahead_pos_rel)
    assert world.dtype == np.float32 and world.shape == (2 * 12,)
    assert np.allclose(world[:12], [0.1, 0, 0, 1.0, 0, 0, 0, 0, 0.1, 0.2, 0, -0.8], atol=1e-6)
    assert np.allclose(world[12:], [0.5, 0.2, -0.1, 1.2, 0.4, -0.1, 0, 0.1, 0, 0, -0.2, -0.8], atol=1e-6)
    turn = heading_rotation(np.array([0.0, 1.0, 0.0]))  # facing +y: world y becomes x, world x becomes −y
    turned = lookahead_observation(ref_com, ahead_com, ahead_com_vel, ahead_pos_rel, turn)
    assert np.allclose(turned[12:], [0.2, -0.5, -0.1, 0.4, -1.2, -0.1, 0.1, 0, 0, -0.2, 0, -0.8], atol=1e-6)
    batch = lookahead_observation(np.stack([ref_com] * 3), np.stack([ahead_com] * 3), np.stack([ahead_com_vel] * 3),
                                  np.stack([ahead_pos_rel] * 3), np.stack([turn] * 3))
    assert batch.shape == (3, 24) and np.allclose(batch, turned)


# ----------------------------------------------------------------------------- MimicGait-v0 terms
def test_joint_pose_reward_by_hand():
    # errors 0.1 and -0.2 rad on two of three hinges: 0.01 + 0.04 = 0.05 rad²; alpha 2 -> exp(-0.1)
    assert joint_pose_reward(np.array([0.1, -0.2, 0.3]), np.array([0.0, 0.0, 0.3]), 2.0) == pytest.approx(math.exp(-0.1))
    assert joint_pose_reward(np.zeros(45), np.zeros(45), 2.0) == 1.0


def test_joint_velocity_reward_by_hand():
    # rate errors 1 and 2 rad/s: 1 + 4 = 5 (rad/s)²; alpha 0.025 -> exp(-0.125) = 0.8825
    assert joint_velocity_reward(np.array([1.0, -2.0]), np.zeros(2), 0.025) == pytest.approx(math.exp(-0.125))


def test_end_effector_reward_is_pelvis_relative():
    # character: pelvis at z 1, hands 0.1 m in front and 0.2 m to the left of it; reference: the
    # same 1 m higher, but its first hand on the pelvis. Only that hand's 0.1 m counts: 0.01 m²,
    # alpha 40 -> exp(-0.4) = 0.670
    pelvis, effectors = np.array([0.0, 0.0, 1.0]), np.array([[0.1, 0, 1.0], [0, 0.2, 1.0]])
    ref_pelvis, ref_effectors = np.array([0.0, 0.0, 2.0]), np.array([[0.0, 0, 2.0], [0, 0.2, 2.0]])
    assert end_effector_reward(effectors, pelvis, ref_effectors, ref_pelvis, 40.0) == pytest.approx(math.exp(-0.4))
    # moving the whole character changes nothing
    assert end_effector_reward(effectors + 5, pelvis + 5, ref_effectors, ref_pelvis, 40.0) == pytest.approx(math.exp(-0.4))


def test_contact_reward_counts_xor_channels():
    target = np.array([True, False, True, False])        # LT, RT, LH, RH
    assert contact_mismatches(target, target) == 0 and contact_reward(target, target, 1.0) == 1.0
    # simulated (LT, RT on; heels off): RT and LH disagree -> xor sum 2 -> exp(-2) = 0.1353
    sim = np.array([1, 1, 0, 0])
    assert contact_mismatches(target, sim) == 2
    assert contact_reward(target, sim, 1.0) == pytest.approx(math.exp(-2.0))
    assert contact_reward(target, ~target, 0.5) == pytest.approx(math.exp(-2.0))   # all 4 wrong, alpha 0.5


def test_upper_body_tilt_and_reward_by_hand():
    pelvis = np.array([1.0, 2.0, 1.0])
    assert upper_body_tilt(pelvis, pelvis + [0, 0, 0.6]) == 0.0
    assert upper_body_tilt(pelvis, pelvis + [0.3, 0, 0.3]) == pytest.approx(math.pi / 4)   # leaning 45° forward
    assert upper_body_tilt(pelvis, pelvis + [0, -0.3, -0.3]) == pytest.approx(3 * math.pi / 4)
    # 45° against the reference's 30°: (π/12)² = 0.06854 rad²; alpha 10 -> exp(-0.6854) = 0.5039
    assert upper_body_reward(math.pi / 4, math.pi / 6, 10.0) == pytest.approx(0.5039, abs=1e-4)


def test_root_orientation_reward_by_hand():
    assert root_orientation_reward(np.array([0.0, 0.0, 1.0]), 50.0) == 1.0
    # pelvis z axis tilted 60°: 1 - cos 60° = 0.5, squared 0.25; alpha 4 -> exp(-1)
    tilted = np.array([math.sin(math.pi / 3), 0.0, math.cos(math.pi / 3)])
    assert root_orientation_reward(tilted, 4.0) == pytest.approx(math.exp(-1.0))
    # upside down: (1 - (-1))² = 4 -> exp(-4 alpha)
    assert root_orientation_reward(np.array([0.0, 0.0, -1.0]), 0.25) == pytest.approx(math.exp(-1.0))


def test_torque_reward_by_hand():
    # two joints at half their limit: 0.25 + 0.25 = 0.5; alpha 2 -> exp(-1)
    assert torque_reward(np.array([0.5, -0.5, 0.0]), 2.0) == pytest.approx(math.exp(-1.0))
    assert torque_reward(np.zeros(45), 1.0) == 1.0


def test_gait_reward_is_the_weighted_sum_of_contactvision_eq_6():
    weights = GaitConfig().weights
    assert weights == {"r_q": 0.3, "r_v": 0.05, "r_e": 0.05, "r_fc": 0.3, "r_up": 0.1, "r_root_ori": 0.15,
                       "r_torque": 0.05}
    assert tuple(weights) == GAIT_TERMS and sum(weights.values()) == pytest.approx(1.0)
    perfect = gait_reward(dict.fromkeys(GAIT_TERMS, 1.0), weights)
    assert perfect.total == pytest.approx(1.0)
    # everything perfect but two contact channels wrong (r_fc = exp(-2) = 0.1353):
    # R = 1 - 0.3 (1 - 0.1353) = 0.7406
    terms = {**dict.fromkeys(GAIT_TERMS, 1.0), "r_fc": math.exp(-2.0)}
    assert gait_reward(terms, weights).total == pytest.approx(0.7406, abs=1e-4)
    # hand-picked values: 0.3·0.5 + 0.05·0.2 + 0.05·0.4 + 0.3·1 + 0.1·0.8 + 0.15·0.9 + 0.05·0.6
    #                   = 0.15 + 0.01 + 0.02 + 0.3 + 0.08 + 0.135 + 0.03 = 0.725
    values = dict(zip(GAIT_TERMS, (0.5, 0.2, 0.4, 1.0, 0.8, 0.9, 0.6)))
    result = gait_reward(values, weights)
    assert result.total == pytest.approx(0.725) and result.as_dict()["r_e"] == 0.4
    with pytest.raises(KeyError, match="r_torque"):
        gait_reward({k: 1.0 for k in GAIT_TERMS[:-1]}, weights)


def test_gait_config_scales_mean_what_they_say():
    g = GaitConfig()
    assert upper_body_reward(math.radians(15.0), 0.0, g.alpha_up) == pytest.approx(0.5)
    tilt28 = np.array([math.sin(math.radians(28.0)), 0.0, math.cos(math.radians(28.0))])
    assert root_orientation_reward(tilt28, g.alpha_root_ori) == pytest.approx(0.5)
    assert joint_velocity_reward(np.array([math.sqrt(28.0)]), np.zeros(1), g.alpha_v) == pytest.approx(0.5, abs=0.01)
    assert torque_reward(np.array([math.sqrt(0.69)]), g.alpha_torque) == pytest.approx(0.5, abs=0.01)
    with pytest.raises(ValueError, match="finite and >= 0"):
        GaitConfig(w_fc=-0.3)
    with pytest.raises(ValueError, match="preview_frames"):
        GaitConfig(preview_frames=0)


def test_gait_observation_appends_targets_and_contacts():
    slices = gait_observation_slices(22, 22, preview_frames=3)
    assert list(slices)[-3:] == ["ref_contacts", "ref_toe", "contacts"]
    assert slices["ref_contacts"].start == observation_size(22, 22) == 13 + 12 * 22 + 22
    assert slices["contacts"].stop == observation_size(22, 22) + 12 + 6 + 4
    base = np.arange(observation_size(22, 22), dtype=np.float32)
    ref_contacts = np.array([[1, 0, 0, 1], [1, 1, 0, 1], [0, 1, 0, 1]], bool)
    ref_toe = np.array([[0.0, 0.1], [0.0, 0.2], [0.0, 0.3]])
    obs = gait_observation(base, ref_contacts, ref_toe, np.array([True, False, False, True]))
    assert obs.dtype == np.float32 and obs.shape == (slices["contacts"].stop,)
    assert np.array_equal(obs[: base.size], base)
    assert np.array_equal(obs[slices["ref_contacts"]], [1, 0, 0, 1, 1, 1, 0, 1, 0, 1, 0, 1])   # frame by frame
    assert np.allclose(obs[slices["ref_toe"]], [0, 0.1, 0, 0.2, 0, 0.3])
    assert np.array_equal(obs[slices["contacts"]], [1, 0, 0, 1])


def test_a_batch_of_states_gets_the_rewards_and_observations_of_each_state_alone():
    rng = np.random.default_rng(5)
    poses = [_pose(n_bodies=4, seed=s) for s in range(3)]
    refs = [_pose(n_bodies=4, seed=10 + s) for s in range(3)]
    quat, ref_quat = np.stack([p[1] for p in poses]), np.stack([r[1] for r in refs])
    faces = np.stack([cube_face_points(p[0] - p[0][0], p[2]) for p in poses])
    ref_faces = np.stack([cube_face_points(r[0] - r[0][0], r[2]) for r in refs])
    vel, ref_vel = rng.standard_normal(faces.shape), rng.standard_normal(faces.shape)
    head, ref_head = rng.standard_normal((3, 3)), rng.standard_normal((3, 3)) * 0.3
    feet_vel, feet_height = rng.standard_normal((3, 4, 3)) * 0.2, rng.uniform(-0.01, 0.04, (3, 4))
    still = still_feet_reward(feet_vel, feet_height, 0.02, 5.0)
    com_vel, target = rng.standard_normal((3, 3)), rng.standard_normal((3, 2))
    moving = com_velocity_reward(com_vel, target, 2.0)
    batch = mimic_reward(quat, ref_quat, faces, ref_faces, vel, ref_vel, head, ref_head, still, still_weight=1.5,
                         r_com=moving, com_weight=0.5)
    assert batch.total.shape == (3,)
    for i in range(3):
        assert still[i] == pytest.approx(still_feet_reward(feet_vel[i], feet_height[i], 0.02, 5.0), rel=1e-12)
        assert moving[i] == pytest.approx(com_velocity_reward(com_vel[i], target[i], 2.0), rel=1e-12)
        alone = mimic_reward(quat[i], ref_quat[i], faces[i], ref_faces[i], vel[i], ref_vel[i], head[i], ref_head[i],
                             still[i], still_weight=1.5, r_com=moving[i], com_weight=0.5)
        for name, value in alone.as_dict().items():
            assert getattr(batch, name)[i] == pytest.approx(value, rel=1e-12), name

    pos, linvel = rng.standard_normal((3, 5, 3)), rng.standard_normal((3, 5, 3))
    com, com_vel, ref_com_vel, ref_com = (rng.standard_normal((3, 3)) for _ in range(4))
    ref_rel, ref_linvel, action = rng.standard_normal((3, 5, 3)), rng.standard_normal((3, 5, 3)), rng.standard_normal((3, 2))
    heading = heading_rotation(rng.standard_normal((3, 3)))
    assert heading.shape == (3, 3, 3)
    for frame, offset in ((None, None), (heading, ref_com)):
        observed = mimic_observation(pos, linvel, com, com_vel, ref_rel, ref_linvel, ref_com_vel, action, frame, offset)
        for i in range(3):
            alone = mimic_observation(pos[i], linvel[i], com[i], com_vel[i], ref_rel[i], ref_linvel[i], ref_com_vel[i],
                                      action[i], None if frame is None else frame[i], None if offset is None else offset[i])
            np.testing.assert_allclose(observed[i], alone, rtol=1e-6, atol=1e-6)
    level = heading_rotation(np.array([[0.0, 0.0, 1.0], [0.0, 2.0, 0.0]]))  # no heading, then facing +y
    np.testing.assert_array_equal(level[0], np.eye(3))
    np.testing.assert_allclose(level[1] @ [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], atol=1e-12)


def test_instability_is_judged_per_simulation_in_a_batch():
    qvel = np.zeros((3, 49))
    qvel[1, 5], qvel[2, 0] = 1e4, np.nan
    np.testing.assert_array_equal(unstable(qvel, 200.0), [False, True, True])
