"""reference_motion/stance.py: the weight's share between the feet, the pendulum's answer to a
moved centre of pressure, and a walk made wider."""

import numpy as np
import pytest

from reference_motion.library import load_motion
from reference_motion.stance import GRAVITY, pendulum_com_shift, support_share, wider_stance


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


def test_a_wider_stance_keeps_the_take_on_the_floor_and_refuses_bad_input():
    walk = load_motion("deepmimic:walk")
    wide = wider_stance(walk, 0.2)
    assert wide.n_frames == walk.n_frames and wide.name == "deepmimic:walk (stance +0.2 m)"
    assert np.allclose(wide.qpos[:, 2], walk.qpos[:, 2])  # the pelvis' height: the feet are reached by the legs
    assert wider_stance(walk, 0.2, label="wide").name == "wide"
    with pytest.raises(ValueError, match="extra_m must be finite"):
        wider_stance(walk, float("nan"))
