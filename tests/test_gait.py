"""ToeRefEstimator, gait phases and gait parameters on hand-made contact sequences."""

import numpy as np
import pytest

from perception.gait import (PHASES, TOE_PEAK_RAD, gait_cycles, gait_parameters, gait_parameters_per_cycle,
                             gait_phases, gait_report, toe_reference_angles)

LT, RT, LH, RH = range(4)


def _stance(T, foot, heel_on, heel_off, toe_off):
    """Contacts (T, 4) with one stance of ``foot`` (0 left, 1 right): heel from heel_on to heel_off,
    toe from heel_on to toe_off (exclusive ends)."""
    c = np.zeros((T, 4), bool)
    c[heel_on:heel_off, 2 + foot] = True
    c[heel_on:toe_off, foot] = True
    return c


def test_toe_reference_long_push_off():
    theta = toe_reference_angles(_stance(40, 1, 2, 10, 20))  # heel-off at 10, toe-off at 20
    right = np.rad2deg(theta[:, 1])
    assert np.allclose(right[:11], 0.0)
    assert right[12] == pytest.approx(42 * 2 / 5) and right[15] == pytest.approx(42.0)
    assert np.allclose(right[15:21], 42.0)
    assert right[21] == pytest.approx(21.0) and right[22] == pytest.approx(0.0)
    assert np.allclose(theta[:, 0], 0.0)  # the left foot never pushed off


def test_toe_reference_short_interval_scales_the_peak():
    right = np.rad2deg(toe_reference_angles(_stance(30, 1, 2, 10, 13))[:, 1])  # T = 3 < 5
    assert right.max() == pytest.approx(42 * 3 / 5)
    assert right[13] == pytest.approx(42 * 3 / 5) and right[14] == pytest.approx(42 * 3 / 10) and right[15] == 0


def test_toe_reference_missing_toe_off_holds_to_the_end():
    left = toe_reference_angles(_stance(20, 0, 0, 12, 20))[:, 0]  # toe still down at the last frame
    assert left[-1] == pytest.approx(TOE_PEAK_RAD) and left[11] == 0.0


def test_toe_reference_several_steps_both_feet():
    c = _stance(120, 0, 0, 20, 30) | _stance(120, 1, 25, 50, 60) | _stance(120, 0, 55, 80, 92)
    theta = np.rad2deg(toe_reference_angles(c))
    assert theta[25, 0] == pytest.approx(42) and theta[85, 0] == pytest.approx(42)
    assert theta[55, 1] == pytest.approx(42) and theta[40, 1] == 0.0 and theta[40, 0] == 0.0
    assert theta[110].sum() == 0.0


def test_table2_phases_and_parameters():
    rows = [(1, 1, 1, 1), (1, 0, 0, 1), (1, 1, 0, 1), (0, 1, 0, 1), (0, 1, 1, 0), (1, 1, 1, 0), (1, 0, 1, 0),
            (1, 0, 0, 0), (0, 0, 0, 0)]
    phases = gait_phases(np.array(rows, bool))
    assert [PHASES[p] for p in phases] == list(PHASES)
    # one cycle: 2 HS, 4 LR, 6 MS, 3 TS, 2 PS, 5 TO/MW, 3 TW frames (+ a stand and an undefined frame)
    counts = dict(zip(PHASES[1:8], (2, 4, 6, 3, 2, 5, 3)))
    seq = np.concatenate([[0], *[[PHASES.index(k)] * n for k, n in counts.items()], [8]])
    p = gait_parameters(seq)
    assert p.valid_frames == 25
    assert p.stance == pytest.approx(17 / 25) and p.swing == pytest.approx(8 / 25)
    assert p.double_support == pytest.approx(4 / 25) and p.single_support == pytest.approx(21 / 25)
    two = np.concatenate([seq[1:-1], seq[1:-1], [1]])
    assert gait_cycles(two) == [(0, 25), (25, 50)]
    assert [c.stance for c in gait_parameters_per_cycle(two)] == pytest.approx([17 / 25, 17 / 25])
    assert np.isnan(gait_parameters(np.array([0, 8])).stance)


def test_bad_contacts_shape():
    with pytest.raises(ValueError, match=r"shape \(frames, 4\)"):
        toe_reference_angles(np.zeros((10, 2)))


def test_gait_report_of_two_cycles():
    rows = {"heel_strike": (1, 0, 0, 1), "loading_response": (1, 1, 0, 1), "mid_stance": (0, 1, 0, 1),
            "terminal_stance": (0, 1, 1, 0), "pre_swing": (1, 1, 1, 0), "toe_off_mid_swing": (1, 0, 1, 0),
            "terminal_swing": (1, 0, 0, 0)}
    cycle = [rows[k] for k, n in zip(rows, (2, 4, 6, 3, 2, 5, 3)) for _ in range(n)]
    contacts = np.array(cycle + cycle + [rows["heel_strike"]], bool)
    report = gait_report(contacts, fps=50.0)
    assert report["frames"] == 51 and report["phases"][0] == "heel_strike" and report["phases"][-1] == "heel_strike"
    assert [(c["start_s"], c["stop_s"]) for c in report["cycles"]] == [(0.0, 0.5), (0.5, 1.0)]
    assert report["cycles"][0]["stance"] == pytest.approx(17 / 25)
    assert report["parameters"]["valid_frames"] == 51
    toe = np.array(report["toe_reference_deg"])
    assert toe.shape == (51, 2) and toe[:, 1].max() == pytest.approx(42.0)   # the right foot pushes off
