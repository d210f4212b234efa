"""reference_motion/stance.py: the weight's share between the feet, the pendulum's answer to a
moved centre of pressure, and a walk made wider."""

import numpy as np
import pytest

from reference_motion.footskate import foot_channels, planted_points
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion
from reference_motion.stance import GRAVITY, pelvis_drop, pendulum_com_shift, support_share, wider_stance


def test_support_share_follows_the_planted_feet_and_fills_flight():
    left = np.array([1, 1, 1, 0, 0, 0, 0, 1], bool)
    right = np.array([0, 1, 0, 0, 1, 1, 0, 0], bool)
    share = support_share(left, right, fps=10.0, smoothing_s=0.0)
    # left alone 1, both 1/2, flight between the last left and first right contact interpolated
    assert share.tolist() == [1.0, 0.5, 1.0, 0.5, 0.0, 0.0, 0.5, 1.0]
    assert np.all(support_share(np.zeros(5, bool), np.zeros(5, bool), 10.0) == 0.5)
    smooth = support_share(left, right, fps=10.0, smoothing_s=0.3)  # a 3-frame running mean
    assert smooth[1] == pytest.approx((1.0 + 0.5 + 1.0) / 3)
    with pytest.raises(ValueError, match=r"must be \(T,\) alike"):
        support_share(left, right[:-1], 10.0)


def test_the_pendulum_com_shift_solves_the_linear_inverted_pendulum():
    fps, height = 200.0, 0.9
    t = np.arange(800) / fps
    cop = 0.1 * np.sign(np.sin(2 * np.pi * 0.9 * t))  # the weight stepping from foot to foot
    com = pendulum_com_shift(cop, fps, height)
    assert pendulum_com_shift(np.full(50, 0.2), fps, height) == pytest.approx(np.full(50, 0.2))  # still: over it
    inner = slice(300, 500)  # away from the padded ends: x'' = g / h (x - p) where p is constant
    accel = np.gradient(np.gradient(com, 1 / fps), 1 / fps)
    steps = np.convolve(np.abs(np.diff(cop, prepend=cop[0])) > 0, np.ones(7), mode="same") > 0
    steady = ~steps[inner]  # 3 frames either side of a step left out: the kink in x is not differentiable
    residual = (accel - GRAVITY / height * (com - cop))[inner][steady]
    assert np.abs(residual).max() < 0.05 * GRAVITY / height * 0.1
    assert 0.02 < np.abs(com[inner]).max() < 0.06  # it sways a fraction of the feet's 0.1 m
    two = pendulum_com_shift(np.stack([cop, -cop], axis=1), fps, height)  # (T, 2) column by column
    assert np.allclose(two[:, 0], com) and np.allclose(two[:, 1], -com)
    with pytest.raises(ValueError, match="com_height_m must be > 0"):
        pendulum_com_shift(cop, fps, 0.0)


def test_a_wider_stance_sways_over_the_stance_foot_keeps_its_feet_planted_and_refuses_bad_input():
    walk = load_motion("deepmimic:walk", min_frames=606)  # looped to a training episode's length
    wide = wider_stance(walk, 0.35)
    assert wide.n_frames == walk.n_frames and wide.name == "deepmimic:walk (stance +0.35 m)"
    hm = load_model(walk.model)
    narrow_kin, wide_kin = hm.forward_kinematics(walk.qpos), hm.forward_kinematics(wide.qpos)
    hips = (narrow_kin.body_pos[:, hm.body_names.index("l_thigh"), :2]
            - narrow_kin.body_pos[:, hm.body_names.index("r_thigh"), :2])
    leftward = np.sum((wide_kin.com[:, :2] - narrow_kin.com[:, :2]) * hips, axis=1) / np.linalg.norm(hips, axis=1)
    planted = planted_points(narrow_kin, walk.fps)
    on_left, on_right = planted[:, foot_channels("left")].any(1), planted[:, foot_channels("right")].any(1)
    assert np.median(leftward[on_left & ~on_right]) > 0.02  # over the left foot while it bears the weight
    assert np.median(leftward[on_right & ~on_left]) < -0.02
    ends = np.r_[leftward[:15], leftward[-15:]]  # half a second at either end: no lean onto the first or last foot
    assert np.abs(ends).max() < 1.5 * np.abs(leftward[15:-15]).max()
    # the feet: as many sole points planted, at the same height (the pelvis lowered where a leg lacked reach)
    wide_planted = planted_points(wide_kin, walk.fps)
    assert abs(int(wide_planted.sum()) - int(planted.sum())) <= 0.02 * planted.sum()
    both = planted & wide_planted
    assert np.abs(wide_kin.foot_points[..., 2][both] - narrow_kin.foot_points[..., 2][both]).max() < 0.01
    assert wider_stance(walk, 0.2, label="wide").name == "wide"
    with pytest.raises(ValueError, match="extra_m must be finite"):
        wider_stance(walk, float("nan"))


def test_the_pelvis_drops_by_what_a_leg_lacks_and_no_more():
    hip = np.zeros((21, 2, 3))
    target = np.zeros((21, 2, 3))
    target[:, :, 2] = -0.8
    target[10, 0, 0] = 0.6  # one frame, one leg: 0.6 m sideways with 0.8 m of reach
    reach = np.full((21, 2), 0.8)
    drop = pelvis_drop(hip, target, reach, fps=10.0)
    lack = 0.8 - np.sqrt(0.8**2 - 0.6**2)  # 0.8 m below, where the leg reaches only 0.53 m below
    assert drop[10] >= lack - 1e-9 and drop.max() == pytest.approx(lack) and drop[0] == 0.0 and drop[-1] == 0.0
    assert np.all(np.diff(drop[:11]) >= 0) and np.all(np.diff(drop[10:]) <= 0)  # comes and goes
    assert np.all(pelvis_drop(hip, np.where(target[..., :1] > 0, 0.0, target), reach, 10.0) == 0.0)
