"""A take set on the floor (reference_motion/grounding.py): DeepMimic's walk raised, sunk and
wobbling comes back to the floor, the clean walk hardly moves, and evaluation tracks the grounded
take and judges the take as given."""

import numpy as np
import pytest

from agents.evaluate import tracked_label, tracked_and_judged
from reference_motion.cli import CliParser
from reference_motion.grounding import Grounding, add_grounding_option, ground, ground_offset, grounding_of
from reference_motion.quality import replay_on_ground
from reference_motion.swing_lift import SwingLift


def _raised(motion, dz):
    qpos = motion.qpos.copy()
    qpos[:, 2] += dz
    return motion.with_qpos(qpos)


def test_the_clean_walk_stays_on_the_floor(walk):
    _, apparent = replay_on_ground(walk)
    assert np.abs(apparent).max() < 0.01  # DeepMimic's walk stands on z = 0 already
    grounded = ground(walk)
    assert np.abs(grounded.qpos[:, 2] - walk.qpos[:, 2]).max() < 0.01
    np.testing.assert_array_equal(grounded.qpos[:, [0, 1, *range(3, walk.qpos.shape[1])]],
                                  walk.qpos[:, [0, 1, *range(3, walk.qpos.shape[1])]])
    assert grounded.source["grounding"]["smooth_s"] == Grounding.smooth_s


@pytest.mark.parametrize("dz", [0.04, -0.04])
def test_a_walk_floating_or_sunk_comes_back_to_the_floor(walk, dz):
    # sinking or rising steadily through the take, to ±4 cm at its end
    ramp = dz * np.linspace(0.0, 1.0, walk.n_frames)
    back = ground(_raised(walk, ramp))
    off = back.qpos[:, 2] - walk.qpos[:, 2]
    assert np.abs(ramp).mean() > 0.019
    assert np.abs(off).mean() < 0.003 and np.abs(off).max() < 0.006  # taken back to a few mm
    # a slow wobble (1 cm at an 8 s period, as slow as the IMU model's: a Gaussian of 2 s) is taken
    # out too, most of it
    t = np.arange(walk.n_frames) / walk.fps
    wobble = 0.01 * np.sin(2 * np.pi * t / 8.0)
    left = ground(_raised(walk, wobble)).qpos[:, 2] - ground(walk).qpos[:, 2]
    assert np.sqrt(np.mean(left ** 2)) < 0.35 * np.sqrt(np.mean(wobble ** 2))


def test_the_offset_is_the_smoothed_apparent_ground(walk):
    raised = _raised(walk, 0.05)
    _, apparent = replay_on_ground(raised)
    np.testing.assert_allclose(ground_offset(raised, Grounding(smooth_s=0.0)), apparent)
    smooth = ground_offset(raised)
    assert np.abs(np.diff(smooth)).max() < 0.2 * np.abs(np.diff(apparent)).max()  # no step of its own
    assert np.abs(smooth - apparent).max() < 0.005  # yet the same ground
    with pytest.raises(ValueError, match="smooth_s must be a finite number"):
        Grounding(smooth_s=-0.1)


def test_evaluation_tracks_the_grounded_take_and_judges_the_take_as_given(walk):
    sunk = _raised(walk, -0.03)
    tracked, judged = tracked_and_judged([sunk], None, grounding=Grounding())
    assert judged == [sunk] and "grounding" in tracked[0].source
    assert np.abs(tracked[0].qpos[:, 2] - walk.qpos[:, 2]).mean() < 0.004
    assert tracked_label("models/x (mirror-averaged)", lift=SwingLift(), grounding=Grounding()) == \
        "models/x (mirror-averaged) + grounded + swing lift 15 deg above 3 cm"
    assert tracked_label("models/x", grounding=Grounding()) == "models/x + grounded"
    assert tracked_label("models/x") == "models/x"
    assert Grounding(smooth_s=0.5).label == "grounded (smooth_s=0.5)"


def test_the_command_line_option_builds_the_grounding():
    parser = CliParser()
    add_grounding_option(parser, "for a test")
    assert grounding_of(parser.parse_args([])) is None
    assert grounding_of(parser.parse_args(["--ground"])) == Grounding()
