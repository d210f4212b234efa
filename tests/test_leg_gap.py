"""Legs parted (reference_motion/leg_gap.py): the IMU suit's hip adduction on DeepMimic's walk is
read back from the feet's gap and undone, a take with its feet apart is left as it is, and
evaluation tracks the parted take and judges the take as given."""

import numpy as np
import pytest

from agents.evaluate import tracked_and_judged, tracked_label
from envs.preparation import prepared
from reference_motion.artefacts import ArtefactRecipe, ArtefactScales, corrupt
from reference_motion.cli import CliParser, UsageError
from reference_motion.grounding import Grounding
from reference_motion.humanoid.model import load_model
from reference_motion.leg_gap import (LegGap, abducted, add_leg_gap_option, lateral_foot_gap, leg_abduction,
                                      leg_gap_of, median_foot_gap, part_legs)


def _median_gap(motion):
    return median_foot_gap(motion.model, motion.qpos)


def _turned(qpos, yaw):
    """``qpos`` with the whole body turned by ``yaw`` (rad) about world z through the origin."""
    c, s = np.cos(yaw), np.sin(yaw)
    out = qpos.copy()
    out[:, :2] = qpos[:, :2] @ np.array([[c, s], [-s, c]])
    w, x, y, z = qpos[:, 3:7].T
    hw, hz = np.cos(yaw / 2), np.sin(yaw / 2)  # (hw, 0, 0, hz) * q
    out[:, 3:7] = np.stack([hw * w - hz * z, hw * x - hz * y, hw * y + hz * x, hw * z + hz * w], axis=1)
    return out


def test_the_gap_is_the_feet_apart_along_the_pelvis_left_axis(walk):
    rest = load_model(walk.model).rest_qpos()[None]
    np.testing.assert_allclose(lateral_foot_gap(walk.model, rest), [0.18], atol=0.005)  # standing, facing +x
    gap = lateral_foot_gap(walk.model, walk.qpos)
    np.testing.assert_allclose(lateral_foot_gap(walk.model, _turned(walk.qpos, 1.2)), gap, atol=1e-6)
    assert 0.12 < np.median(gap) < 0.16
    wider = lateral_foot_gap(walk.model, abducted(walk, 0.1))
    assert np.all(wider > gap)  # abducting both hips moves every frame's feet apart
    assert 0.15 < np.median(wider - gap) < 0.19  # about 2 × 0.9 m × sin(0.1 rad)


def test_the_suit_adduction_is_read_back_from_the_feet_and_undone(walk):
    adduction = ArtefactScales().adduction_rad
    crossed = corrupt(walk, ArtefactRecipe.named("adduction", 1.0), 0)
    assert _median_gap(crossed) < 0.0 < _median_gap(walk)  # 8° on both hips cross the legs
    angle = leg_abduction(crossed, LegGap(min_gap_m=_median_gap(walk)))
    assert angle == pytest.approx(adduction, abs=0.002)
    parted = part_legs(crossed, LegGap(min_gap_m=_median_gap(walk)))
    assert np.abs(parted.qpos - walk.qpos).max() < 0.002  # back to the clean walk
    assert parted.source["hip_abduction_rad"] == pytest.approx(angle)
    # the default gap parts the legs to it, not to the clean walk's own
    assert _median_gap(part_legs(crossed)) == pytest.approx(LegGap().min_gap_m, abs=0.002)


def test_feet_already_apart_are_left_as_they_are(walk):
    assert leg_abduction(walk, LegGap(min_gap_m=0.10)) == 0.0
    assert part_legs(walk, LegGap(min_gap_m=0.10)) is walk
    capped = LegGap(min_gap_m=2.0, max_abduction_rad=0.05)  # out of reach: bent no further than the cap
    assert leg_abduction(walk, capped) == pytest.approx(0.05)
    for bad in ({"min_gap_m": 0.0}, {"max_abduction_rad": float("nan")}, {"iterations": 0}):
        with pytest.raises(ValueError, match="LegGap"):
            LegGap(**bad)


def test_evaluation_tracks_the_parted_take_before_the_floor_and_judges_the_take_as_given(walk):
    crossed = corrupt(walk, ArtefactRecipe.named("adduction", 1.0), 0)
    tracked, judged = tracked_and_judged([crossed], None, legs=LegGap(), grounding=Grounding())
    assert judged == [crossed]
    assert {"leg_gap", "hip_abduction_rad", "grounding"} <= set(tracked[0].source)
    np.testing.assert_array_equal(tracked[0].qpos, prepared(crossed, legs=LegGap(), grounding=Grounding()).qpos)
    assert tracked_label("models/x", legs=LegGap(), grounding=Grounding()) == \
        "models/x + legs parted to 15 cm + grounded"
    assert LegGap(min_gap_m=0.2, iterations=5).label == "legs parted to 20 cm (iterations=5)"


def test_the_command_line_option_builds_the_leg_gap():
    parser = CliParser()
    add_leg_gap_option(parser, "for a test")
    assert leg_gap_of(parser.parse_args([])) is None
    assert leg_gap_of(parser.parse_args(["--part-legs"])) == LegGap()
    assert leg_gap_of(parser.parse_args(["--part-legs", "0.2"])) == LegGap(min_gap_m=0.2)
    with pytest.raises(UsageError, match="--part-legs: expected a positive number"):
        parser.parse_args(["--part-legs", "-0.1"])


def test_the_search_keeps_the_closest_angle_it_tried_within_its_bounds(walk):
    crossed = corrupt(walk, ArtefactRecipe.named("adduction", 1.0), 0)
    short = LegGap(min_gap_m=0.5, max_abduction_rad=0.05)  # the cap is reached and the gap is still short
    assert leg_abduction(crossed, short) == pytest.approx(0.05)
    assert _median_gap(part_legs(crossed, short)) < 0.05
    one_try = LegGap(iterations=1)  # only the first guess: 2 × 0.9 m × sin(a) = the lack
    lack = LegGap().min_gap_m - _median_gap(crossed)
    assert leg_abduction(crossed, one_try) == pytest.approx(np.arcsin(lack / 1.8))
    model = load_model(walk.model)
    limited, ranges = model.hinge_ranges
    low, high = model.hinge_range("l_thigh_x")
    assert [low, high] == ranges[list(limited).index(model.qpos_index("l_thigh_x"))].tolist()
    assert abducted(walk, 2.0)[:, model.qpos_index("l_thigh_x")].max() == pytest.approx(high)  # within range
    np.testing.assert_array_equal(abducted(walk, 0.0), walk.qpos)


def test_an_angle_that_only_narrows_the_gap_is_not_taken(walk, monkeypatch):
    import reference_motion.leg_gap as leg_gap
    monkeypatch.setattr(leg_gap, "HIP_ABDUCTION", (("l_thigh_x", -1.0), ("r_thigh_x", 1.0)))  # signs turned over
    assert leg_abduction(walk) == 0.0 and part_legs(walk) is walk
