"""Legs evened (reference_motion/leg_symmetry.py): one leg's offset is read from the difference of
the two legs' mean angles and taken out half from each leg, an offset both legs share stays, the
suit's per-hinge offsets on DeepMimic's walk are brought nearer the clean walk, and evaluation tracks
the evened take before it parts the legs."""

import json
from dataclasses import asdict

import numpy as np
import pytest

from agents.evaluate import tracked_and_judged, tracked_label
from envs.preparation import prepared
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.cli import CliParser
from reference_motion.humanoid.model import load_model
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import (LEG_HINGES, LIBRARY_ASYMMETRY, LegSymmetry, add_leg_symmetry_option,
                                           even_legs, leg_asymmetry, leg_corrections, leg_symmetry_of)
from reference_motion.transforms import mirror


def _own_prior(walk, spread_deg):
    """A prior centred on ``walk``'s own asymmetry (so the walk reads as evened already), each
    hinge with the clean spread ``spread_deg``."""
    return LegSymmetry(clean=tuple((h, float(np.degrees(d)), spread_deg) for h, d in zip(LEG_HINGES, leg_asymmetry(walk))))


def _offset(walk, offsets):
    qpos = walk.qpos.copy()
    model = load_model(walk.model)
    for hinge, angle in offsets.items():
        qpos[:, model.qpos_index(hinge)] += angle
    return walk.with_qpos(qpos)


def test_a_take_and_its_mirror_image_have_opposite_asymmetries_and_corrections(walk):
    asymmetry = leg_asymmetry(walk)
    assert asymmetry.shape == (len(LEG_HINGES),)
    np.testing.assert_allclose(leg_asymmetry(mirror(walk)), -asymmetry, atol=1e-12)
    assert np.degrees(np.abs(asymmetry)).max() < 8.0  # a walk: each leg hinge's means within a few degrees
    # the library's prior has means far from 0 (the feet's x and z −4.3° and −5.7°): a mirrored take
    # is read against the mirrored mean, so its corrections are the take's, mirrored
    take = corrupt(walk, ArtefactRecipe(bias=1.0, drift=1.0), 2)
    corrections, mirrored = leg_corrections(take), leg_corrections(mirror(take))
    assert max(abs(c) for c in corrections.values()) > np.radians(1.0)
    for hinge in LEG_HINGES:
        assert mirrored[hinge] == pytest.approx(-corrections[hinge], abs=1e-12)
    with pytest.raises(ValueError, match="not left leg hinges"):
        leg_asymmetry(walk, ("spine_lower_x",))


def test_one_legs_offset_is_taken_out_half_from_each_leg(walk):
    # the clean spread √2 × 3.1° equals the suit's for a difference: k = 1/2
    symmetry = _own_prior(walk, np.sqrt(2) * 3.1)
    assert symmetry.shrinkage(np.sqrt(2) * 3.1) == pytest.approx(0.5)
    offset = _offset(walk, {"l_shin_y": 0.04, "l_foot_x": 0.04})  # a y hinge and an x hinge (mirror flips x)
    corrections = leg_corrections(offset, symmetry)
    assert corrections["l_shin_y"] == pytest.approx(0.02) and corrections["l_foot_x"] == pytest.approx(0.02)
    assert abs(corrections["l_thigh_y"]) < 1e-12
    evened = even_legs(offset, symmetry)
    model = load_model(walk.model)
    moved = evened.qpos - offset.qpos
    expected = {"l_shin_y": -0.01, "r_shin_y": 0.01, "l_foot_x": -0.01, "r_foot_x": -0.01}  # r_foot_x: mirrored
    for hinge, change in expected.items():
        np.testing.assert_allclose(moved[:, model.qpos_index(hinge)], change, atol=1e-12)
    others = np.setdiff1d(np.arange(model.nq), [model.qpos_index(h) for h in expected])
    assert np.abs(moved[:, others]).max() < 1e-12
    assert evened.source["leg_corrections_rad"]["l_shin_y"] == pytest.approx(0.02)


def test_an_offset_both_legs_share_stays(walk):
    symmetry = _own_prior(walk, 3.0)
    shared = _offset(walk, {"l_shin_y": 0.05, "r_shin_y": 0.05, "l_foot_x": 0.03, "r_foot_x": -0.03})
    np.testing.assert_allclose(even_legs(shared, symmetry).qpos, shared.qpos, atol=1e-12)


def test_the_suits_offsets_on_the_walk_come_nearer_the_clean_walk(walk):
    model = load_model(walk.model)
    columns = [model.qpos_index(h) for h in LEG_HINGES] + [model.qpos_index("r" + h[1:]) for h in LEG_HINGES]
    given, evened = [], []
    for seed in range(8):
        take = corrupt(walk, ArtefactRecipe(bias=1.0, drift=1.0), seed)  # the offsets the prior is set for
        for out, motion in ((given, take), (evened, even_legs(take))):
            out.append(np.sqrt(np.mean((motion.qpos[:, columns] - walk.qpos[:, columns]) ** 2)))
    # ≈ 3.1° per hinge (LegSymmetry.suit_offset_deg), brought 11% nearer (3.24° → 2.89°) with the
    # library's prior, whose feet's means are the Bandai Namco rig's, not DeepMimic's
    assert np.degrees(np.mean(given)) == pytest.approx(3.2, abs=0.3)
    assert np.mean(evened) < 0.92 * np.mean(given)


def test_the_settings_come_back_from_a_sidecars_lists_and_hash():
    symmetry = LegSymmetry(suit_offset_deg=2.5)
    again = LegSymmetry(**json.loads(json.dumps(asdict(symmetry))))
    assert again == symmetry and hash(again) == hash(symmetry)


def test_bad_settings_are_refused_by_name():
    for bad, match in (({"suit_offset_deg": 0.0}, "suit_offset_deg"), ({"suit_offset_deg": "x"}, "suit_offset_deg"),
                       ({"clean": (("l_upper_arm_x", 0.0, 1.0),)}, "'l_upper_arm_x' is not a left leg hinge"),
                       ({"clean": (("l_shin_y", 0.0, float("nan")),)}, r"clean\['l_shin_y'\]"),
                       ({"clean": (("l_shin_y", 0.0),)}, r"each entry must be \(hinge, mean_deg, spread_deg\)"),
                       ({"clean": (("l_shin_y", 0.0, 1.0), ("l_shin_y", 1.0, 1.0))}, "'l_shin_y' is given twice")):
        with pytest.raises(ValueError, match=match):
            LegSymmetry(**bad)
    assert LegSymmetry(suit_offset_deg=4).label == "legs evened (suit_offset_deg=4)"
    assert LegSymmetry(clean=LIBRARY_ASYMMETRY[:2]).label == "legs evened (clean=custom)"


def test_evened_hinges_stay_within_their_ranges_and_nothing_else_moves(walk):
    model = load_model(walk.model)
    low, high = model.hinge_range("l_shin_y")
    qpos = walk.qpos.copy()
    column, right = model.qpos_index("l_shin_y"), model.qpos_index("r_shin_y")
    qpos[0, column] = low - 0.05  # the take itself beyond the range at one frame
    qpos[1, column] = low + 0.001  # and just inside it at another
    qpos[:, model.qpos_index("l_upper_arm_x")] = 10.0  # a hinge not evened, far beyond its range
    take = walk.with_qpos(qpos)
    symmetry = LegSymmetry(clean=(("l_shin_y", float(np.degrees(leg_asymmetry(take, ("l_shin_y",))[0])) - 4.0, 3.1),))
    correction = leg_corrections(take, symmetry)["l_shin_y"]
    assert correction > 0.01  # the left knee is moved down, toward and beyond its low end
    evened = even_legs(take, symmetry)
    assert evened.qpos[0, column] == low and evened.qpos[1, column] == low  # both stop at the range's end
    np.testing.assert_allclose(evened.qpos[2:, column], np.maximum(qpos[2:, column] - correction / 2, low))
    np.testing.assert_allclose(evened.qpos[:, right], qpos[:, right] + correction / 2)
    others = np.setdiff1d(np.arange(model.nq), [column, right])
    np.testing.assert_array_equal(evened.qpos[:, others], qpos[:, others])  # other hinges untouched, even out of range


def test_evaluation_tracks_the_evened_take_before_parting_the_legs(walk):
    take = corrupt(walk, ArtefactRecipe.imu(1.0), 3)
    tracked, judged = tracked_and_judged([take], None, symmetry=LegSymmetry(), legs=LegGap())
    assert judged == [take]
    assert {"leg_symmetry", "leg_corrections_rad", "hip_abduction_rad"} <= set(tracked[0].source)
    np.testing.assert_array_equal(tracked[0].qpos, prepared(take, symmetry=LegSymmetry(), legs=LegGap()).qpos)
    assert tracked_label("models/x", symmetry=LegSymmetry(), legs=LegGap()) == \
        "models/x + legs evened + legs parted to 15 cm"


def test_the_command_line_option_builds_the_leg_symmetry():
    parser = CliParser()
    add_leg_symmetry_option(parser, "for a test")
    assert leg_symmetry_of(parser.parse_args([])) is None
    assert leg_symmetry_of(parser.parse_args(["--even-legs"])) == LegSymmetry()
