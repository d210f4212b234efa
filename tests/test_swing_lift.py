"""Knees lifted in the swing of backward steps (reference_motion/swing_lift.py): the weights on
hand-made signals, the lift on DeepMimic's walk and on the same walk played backwards, the checks,
and evaluation's tracked and judged clips."""

import math

import numpy as np
import pytest

from agents.evaluate import tracked_label, tracked_and_judged
from reference_motion.humanoid.model import load_model
from reference_motion.cli import CliParser
from reference_motion.swing_lift import (KNEES, SwingLift, add_swing_lift_options, backward_weights, lift_swing,
                                         speed_swing_weights, swing_lift_of, swing_weights)
from reference_motion.transforms import reversed_in_time


def test_swing_weights_follow_the_foot_off_its_low():
    height = np.r_[np.zeros(30), np.full(30, 0.08), np.zeros(30)]  # stance, swing 8 cm up, stance
    w = swing_weights(height, clearance_m=0.01, smoothing_frames=3.0)
    assert w.shape == (90,) and w.min() >= 0 and w.max() <= 1
    assert np.all(w[:20] < 0.01) and np.all(w[38:52] > 0.99) and np.all(w[70:] < 0.01)
    assert 0.3 < w[30] < 0.7  # the step smoothed, centred on the lift-off
    # the same take floating 3 cm above the floor reads alike (the foot's own low, not z = 0)
    np.testing.assert_allclose(swing_weights(height + 0.03, 0.01, 3.0), w)
    with pytest.raises(ValueError, match="finite"):
        swing_weights(np.array([0.0, np.nan]), 0.01, 3.0)


def test_speed_swing_weights_need_every_point_of_the_foot_moving():
    fps = 60.0
    x = np.r_[np.zeros(30), np.linspace(0.0, 0.6, 30), np.full(30, 0.6)]  # still, 1.2 m/s, still
    heel = np.stack([x, np.zeros(90)], axis=1)
    toe = heel + [0.15, 0.0]
    w = speed_swing_weights(np.stack([heel, toe], axis=1), fps, swing_speed_mps=1.0, smoothing_frames=3.0)
    assert w.shape == (90,) and w.min() >= 0 and w.max() <= 1
    assert np.all(w[:20] < 0.01) and np.all(w[38:52] > 0.99) and np.all(w[70:] < 0.01)
    # the heel still on the floor while the toe swings round it: stance
    rolled = np.stack([np.zeros((90, 2)), toe], axis=1)
    np.testing.assert_allclose(speed_swing_weights(rolled, fps, 1.0, 3.0), 0.0)
    # a slower swing (0.6 m/s) is not read as swing at 1 m/s
    assert speed_swing_weights(np.stack([heel, toe], axis=1) * 0.5, fps, 1.0, 3.0).max() < 0.01
    with pytest.raises(ValueError, match=r"\(T, P, 2\)"):
        speed_swing_weights(np.zeros((10, 2)), fps, 1.0, 3.0)


def test_backward_weights_read_the_root_against_the_heading():
    t = np.arange(120) / 60.0
    heading = np.full(120, math.pi / 2)  # facing +y
    backward = np.stack([np.zeros(120), -1.0 * t], axis=1)  # moving to -y at 1 m/s: backward
    np.testing.assert_allclose(backward_weights(backward, heading, 60.0, 0.5, 0.5)[10:-10], 1.0)
    np.testing.assert_allclose(backward_weights(-backward, heading, 60.0, 0.5, 0.5), 0.0)  # forward
    sideways = np.stack([1.0 * t, np.zeros(120)], axis=1)
    np.testing.assert_allclose(backward_weights(sideways, heading, 60.0, 0.5, 0.5), 0.0, atol=1e-12)
    slow = backward * 0.25  # 0.25 m/s backward: half the lift at full_speed 0.5 m/s
    np.testing.assert_allclose(backward_weights(slow, heading, 60.0, 0.5, 0.5)[30:-30], 0.5)


def test_a_forward_walk_is_left_alone_and_a_backward_one_lifted_in_swing(walk):
    model = load_model(walk.model)
    knees = [model.qpos_index(k) for k in KNEES]
    forward = lift_swing(walk, SwingLift(knee_deg=15.0))
    np.testing.assert_allclose(forward.qpos, walk.qpos, atol=1e-9)
    back = reversed_in_time(walk)
    lifted = lift_swing(back, SwingLift(knee_deg=15.0))
    added = np.degrees(lifted.qpos[:, knees] - back.qpos[:, knees])
    others = np.setdiff1d(np.arange(walk.qpos.shape[1]), knees)
    np.testing.assert_array_equal(lifted.qpos[:, others], back.qpos[:, others])
    assert added.min() >= 0 and added.max() == pytest.approx(15.0, abs=0.05)
    # lifted in swing (the foot well off the floor), not in stance
    heights = model.forward_kinematics(back.qpos).foot_points[..., 2]
    for side, columns in enumerate(((0, 2), (1, 3))):
        low = heights[:, list(columns)].min(axis=1)
        stance, swing = low < np.percentile(low, 5) + 0.003, low > np.percentile(low, 5) + 0.05
        assert added[swing, side].mean() > 12.0 and added[stance, side].mean() < 3.0
    assert lifted.source["swing_lift"]["knee_deg"] == 15.0


def test_swing_read_from_speed_lifts_the_same_swings_and_spares_the_stance(walk):
    model = load_model(walk.model)
    knees = [model.qpos_index(k) for k in KNEES]
    back = reversed_in_time(walk)
    by_speed = np.degrees(lift_swing(back, SwingLift(swing_from="speed")).qpos[:, knees] - back.qpos[:, knees])
    heights = model.forward_kinematics(back.qpos).foot_points[..., 2]
    for side, columns in enumerate(((0, 2), (1, 3))):
        low = heights[:, list(columns)].min(axis=1)
        stance, swing = low < np.percentile(low, 5) + 0.003, low > np.percentile(low, 5) + 0.05
        assert by_speed[swing, side].mean() > 10.0 and by_speed[stance, side].mean() < 1.0


@pytest.mark.parametrize("bad", [dict(knee_deg=0.0), dict(clearance_m=-0.01), dict(smoothing_frames=math.nan),
                                 dict(backward_speed_mps=math.inf), dict(backward_window_s=0.0),
                                 dict(swing_speed_mps=-1.0)])
def test_bad_settings_are_refused(bad):
    with pytest.raises(ValueError, match="SwingLift.* must be finite and > 0"):
        SwingLift(**bad)


def test_evaluation_tracks_the_lifted_take_and_judges_the_take_as_given(walk):
    back = reversed_in_time(walk)
    tracked, judged = tracked_and_judged([back], None, lift=SwingLift())
    assert judged == [back] and tracked[0].source["swing_lift"]["knee_deg"] == SwingLift.knee_deg
    assert tracked_and_judged([back], None) == ([back], None)
    assert tracked_label("models/x (mirror-averaged)", lift=SwingLift(knee_deg=15.0)) == \
        "models/x (mirror-averaged) + swing lift 15 deg above 3 cm"
    assert tracked_label("models/x", lift=SwingLift(swing_from="speed")) == "models/x + swing lift 15 deg faster than 1 m/s"


def test_the_command_line_options_build_the_lift():
    parser = CliParser()
    add_swing_lift_options(parser, "for a test")
    assert swing_lift_of(parser.parse_args([])) is None
    assert swing_lift_of(parser.parse_args(["--swing-lift"])) == SwingLift()
    assert swing_lift_of(parser.parse_args(["--swing-lift", "10", "--swing-from", "speed"])) == \
        SwingLift(knee_deg=10.0, swing_from="speed")
    with pytest.raises(ValueError, match="swing-from"):
        parser.parse_args(["--swing-lift", "--swing-from", "toes"])
    with pytest.raises(ValueError, match="--swing-from goes with --swing-lift"):
        swing_lift_of(parser.parse_args(["--swing-from", "speed"]))
    with pytest.raises(ValueError, match="swing_from must be one of"):
        SwingLift(swing_from="toes")

