import itertools

import numpy as np
import pytest

from reference_motion import rotations as rot

ORDERS = ["".join(p) for p in itertools.permutations("xyz")]


def random_quats(n, seed=0):
    return rot.normalize(np.random.default_rng(seed).standard_normal((n, 4)))


def same_rotation(a, b, atol=1e-9):
    return np.allclose(np.abs(np.sum(a * b, -1)), 1.0, atol=atol)


def test_matrix_round_trip():
    q = random_quats(500)
    assert same_rotation(rot.from_matrix(rot.to_matrix(q)), q)
    m = rot.to_matrix(q)
    assert np.allclose(m @ np.swapaxes(m, -1, -2), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(m), 1.0)


def test_matrix_matches_rotate():
    q = random_quats(50, seed=1)
    v = np.random.default_rng(2).standard_normal((50, 3))
    assert np.allclose(rot.rotate(q, v), np.einsum("nij,nj->ni", rot.to_matrix(q), v))


@pytest.mark.parametrize("axes", ORDERS)
def test_hinge_round_trip(axes):
    q = random_quats(500, seed=3)
    angles = rot.to_hinges(q, axes)
    assert same_rotation(rot.from_hinges(angles, axes), q, atol=1e-8)
    assert np.all(np.abs(angles[:, 1]) <= np.pi / 2 + 1e-12)
    # angles -> quaternion -> angles reproduces angles inside the principal range
    a = np.random.default_rng(4).uniform([-3, -1.5, -3], [3, 1.5, 3], (200, 3))
    assert np.allclose(rot.to_hinges(rot.from_hinges(a, axes), axes), a, atol=1e-8)


@pytest.mark.parametrize("axes", ORDERS)
def test_hinge_gimbal_lock(axes):
    a = np.array([[0.3, np.pi / 2, 0.4], [-0.7, -np.pi / 2, 0.2]])
    q = rot.from_hinges(a, axes)
    assert same_rotation(rot.from_hinges(rot.to_hinges(q, axes), axes), q, atol=1e-7)


def test_hinge_order_matches_mujoco():
    """Three hinges declared x, y, z in one MuJoCo body compose as R_x R_y R_z."""
    import mujoco

    xml = """<mujoco><worldbody><body name="b"><joint type="hinge" axis="1 0 0"/>
      <joint type="hinge" axis="0 1 0"/><joint type="hinge" axis="0 0 1"/>
      <geom size="0.1"/></body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    d.qpos[:] = [0.4, -0.9, 1.3]
    mujoco.mj_kinematics(m, d)
    assert same_rotation(d.xquat[1], rot.from_hinges(d.qpos, "xyz"))


def test_twist_slerp_power_between():
    axis = np.array([0.0, 1.0, 0.0])
    q = rot.from_axis_angle(axis, 0.8)
    assert np.isclose(rot.twist_angle(q, axis), 0.8)
    assert np.isclose(rot.twist_angle(q, -axis), -0.8)
    assert same_rotation(rot.slerp(q, rot.from_axis_angle(axis, 1.6), 0.5), rot.from_axis_angle(axis, 1.2))
    assert same_rotation(rot.multiply(rot.power(q, 0.5), rot.power(q, 0.5)), q)
    a, b = np.array([1.0, 0, 0]), np.array([0.0, 0.6, 0.8])
    assert np.allclose(rot.rotate(rot.between_vectors(a, b), a), b)
    assert np.allclose(rot.rotate(rot.between_vectors(a, -a), a), -a)
    assert np.isclose(rot.yaw(rot.from_axis_angle(np.array([0, 0, 1.0]), 0.5)), 0.5)
