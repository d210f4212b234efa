"""reference_motion/touch_up.py: a simulated clip lifted out of the floor and its planted feet
pinned, stretch by stretch, with what moved reported; clean.py --touch-up."""

import json

import numpy as np
import pytest

from agents import clean
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.cli import UsageError
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion
from reference_motion.motion import Motion
from reference_motion.quality import motion_quality
from reference_motion.footskate import PinningConfig
from reference_motion.touch_up import floor_lift, touch_up


def test_floor_lift_is_the_depth_or_a_smooth_bound_above_it():
    lowest = np.array([0.01, -0.02, -0.01, 0.005])
    np.testing.assert_allclose(floor_lift(lowest, window=0), [0.0, 0.02, 0.01, 0.0])
    # running max over 3 frames [0.02, 0.02, 0.02, 0.01], then their mean over 3 frames
    np.testing.assert_allclose(floor_lift(lowest, window=1), [0.02, 0.02, 0.05 / 3, 0.04 / 3])
    assert np.all(floor_lift(lowest, 1) >= floor_lift(lowest, 0))
    with pytest.raises(ValueError, match="window must be >= 0 frames, got -1"):
        floor_lift(lowest, -1)


def test_a_sunk_skating_clip_comes_out_on_the_floor_with_planted_feet(walk):
    """DeepMimic's walk sunk 2 cm into the floor with IMU-like stance skate: after the touch-up
    nothing is below the floor, foot skate falls by more than half, and the bodies moved about
    the sinking plus a few millimetres."""
    sunk = corrupt(walk, ArtefactRecipe.named("skate", 1.0), seed=3)
    qpos = sunk.qpos.copy()
    qpos[:, 2] -= 0.02
    sunk = sunk.with_qpos(qpos)
    before = motion_quality(sunk)
    touched, report = touch_up(sunk)
    after = motion_quality(touched)
    assert before.penetration_max_m > 0.015 and after.penetration_max_m < 1e-9
    assert after.foot_skate_mps < 0.5 * before.foot_skate_mps
    assert 0.015 < report.lift_max_m < 0.05 and report.lift_mean_m > 0.01
    assert report.lift_mean_m <= report.body_shift_mean_m < 0.04
    assert touched.source["touch_up"] == report.as_dict() and touched.n_frames == sunk.n_frames


def test_no_contact_window_spans_a_break(walk):
    """A clip that jumps 0.5 m sideways at frame 150 (a re-anchor): touched up with the break, no
    body moves more than a few centimetres; without it, the feet planted across the jump are
    pinned half-way between, tens of centimetres off."""
    qpos = walk.qpos.copy()
    qpos[150:, 1] += 0.5
    jumped = walk.with_qpos(qpos)
    unlimited = PinningConfig(max_correction_m=None)  # no limit on how far a foot is moved
    _, split = touch_up(jumped, breaks=[150], pinning=unlimited)
    _, whole = touch_up(jumped, pinning=unlimited)
    assert split.body_shift_max_m < 0.1 < whole.body_shift_max_m
    # the touch-up's own limit leaves a window that would move a foot more than 10 cm alone
    _, limited = touch_up(jumped)
    assert limited.body_shift_max_m < 0.1


def test_a_performance_is_touched_up_between_its_reanchors(walk):
    """clean.touched_up reads the breaks from the performance's re-anchors."""
    qpos = walk.qpos.copy()
    qpos[150:, 1] += 0.5
    performed = walk.with_qpos(qpos, source={"reanchors": [{"frame": 150}]})
    touched, _ = clean.touched_up(performed)
    np.testing.assert_array_equal(touched.qpos, touch_up(performed, breaks=[150])[0].qpos)
    assert not np.allclose(touched.qpos, touch_up(performed)[0].qpos)


def test_a_smoothed_lift_stays_above_the_floor_and_bad_settings_are_refused(walk):
    qpos = walk.qpos.copy()
    qpos[:, 2] -= 0.02
    sunk = walk.with_qpos(qpos)
    touched, smooth = touch_up(sunk, smooth_s=0.1)
    _, exact = touch_up(sunk, smooth_s=0)
    lowest = load_model(walk.model).forward_kinematics(touched.qpos).lowest
    assert lowest.min() > -1e-9 and smooth.lift_mean_m >= exact.lift_mean_m
    # a stretch shorter than MIN_PINNED_FRAMES is lifted, not pinned
    short, _ = touch_up(sunk, breaks=[2])
    np.testing.assert_allclose(short.qpos[:2, 3:], sunk.qpos[:2, 3:])
    assert np.all(short.qpos[:2, 2] >= sunk.qpos[:2, 2])
    with pytest.raises(ValueError, match="smooth_s must be a finite number of seconds >= 0, got -1"):
        touch_up(sunk, smooth_s=-1)
    with pytest.raises(ValueError, match="smooth_s must be a finite number of seconds >= 0, got inf"):
        touch_up(sunk, smooth_s=float("inf"))
    with pytest.raises(ValueError, match=r"breaks must be whole frame indices in 0\.\.302, got \[400, 2\.5\]"):
        touch_up(sunk, breaks=[10, 400, 2.5])


def test_clean_cli_touches_up_on_request(tmp_path):
    common = ["deepmimic:walk", "--policy", "models/mimic_walk", "--min-frames", "200", "--no-adapt"]
    result = clean.main([*common, "--touch-up", "--out", str(tmp_path / "t.npz"), "--json", str(tmp_path / "t.json")])
    record = json.loads((tmp_path / "t.json").read_text())
    assert record["touch_up"]["body_shift_mean_m"] > 0 and "foot_skate_mps" in record["touch_up"]["simulated"]
    touched = Motion.load(tmp_path / "t.npz")
    assert result["cleaned"]["penetration_max_m"] < 1e-9 < record["touch_up"]["simulated"]["penetration_max_m"]
    kin = load_model(touched.model).forward_kinematics(touched.qpos)
    assert kin.lowest.min() > -1e-9
    plain = clean.main([*common, "--out", str(tmp_path / "p.npz")])
    assert plain["touch_up"] is None and plain["cleaned"]["penetration_max_m"] > 0.005
    from agents import reconstruct_gait  # it reports the simulation itself: no touch-up there
    with pytest.raises(UsageError, match="unrecognized arguments: --touch-up"):
        reconstruct_gait.build_parser().parse_args(["deepmimic:walk", "--policy", "p", "--out", "o.npz", "--touch-up"])
