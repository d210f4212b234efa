import numpy as np
import pytest

from reference_motion import rotations as rot
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.footskate import (LegIK, PinningConfig, contact_windows, drop_fast_windows, fade_between_windows,
                                        knee_flexion_for_reach, pin_contacts, pin_corrections, smoothstep)
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion
from reference_motion.quality import motion_quality


def test_contact_windows_are_half_open_runs():
    assert contact_windows(np.array([1, 1, 0, 0, 1, 0, 1], bool)) == [(0, 2), (4, 5), (6, 7)]
    assert contact_windows(np.zeros(4, bool)) == []


def test_pin_corrections_cancel_a_steady_slide_and_follow_a_heel_to_toe_roll():
    T = 5
    heel = np.stack([np.arange(T) * 0.01, np.zeros(T)], -1)  # slides 1 cm per frame
    toe = heel + [0.2, 0.0]
    points = np.stack([heel, toe], axis=1)
    planted = np.array([[1, 0], [1, 0], [1, 1], [0, 1], [0, 1]], bool)  # heel strike → roll → toe off
    delta = pin_corrections(points, planted)
    pinned = points + delta[:, None, :]
    for p in range(2):
        held = planted[1:, p] & planted[:-1, p]
        assert np.allclose(np.diff(pinned[:, p], axis=0)[held], 0.0)
    # the correction is the centred cumulative slide: -(0, 1, 2, 3, 4) cm + 2 cm
    assert np.allclose(delta[:, 0], [0.02, 0.01, 0.0, -0.01, -0.02])
    assert np.allclose(delta[:, 1], 0.0)
    # a window whose correction would exceed the limit (2 cm here) is left alone; at the limit it is pinned
    assert np.allclose(pin_corrections(points, planted, max_correction=0.019), 0.0)
    assert np.allclose(pin_corrections(points, planted, max_correction=0.0201), delta)


def test_fast_low_windows_are_swing_not_contact():
    low = np.array([[1], [1], [1], [0], [1], [1]], bool)
    speed = np.array([[0.1], [0.2], [0.1], [3.0], [3.0], [2.5]])
    assert drop_fast_windows(low, speed, 1.0)[:, 0].tolist() == [True, True, True, False, False, False]


def test_fades_bridge_short_gaps_and_decay_long_ones():
    assert smoothstep(np.array([-1.0, 0.0, 0.5, 1.0, 2.0])).tolist() == [0.0, 0.0, 0.5, 1.0, 1.0]
    values = np.zeros((12, 1))
    values[0], values[3] = 1.0, 3.0
    values[11] = 2.0
    defined = np.zeros(12, bool)
    defined[[0, 3, 11]] = True
    out = fade_between_windows(values, defined, fade_frames=2)[:, 0]
    # gap 1–2 (2 frames ≤ 2·2): smoothstep bridge from 1 to 3 at t = 1/3, 2/3
    assert out[1] == pytest.approx(1 + 2 * smoothstep(np.array(1 / 3))) and out[2] == pytest.approx(1 + 2 * smoothstep(np.array(2 / 3)))
    # gap 4–10 (7 frames): 3 fades out over 2 frames, 2 fades in over 2 frames, zero between
    assert out[4] == pytest.approx(3 * smoothstep(np.array(2 / 3))) and out[5] == pytest.approx(3 * smoothstep(np.array(1 / 3)))
    assert out[6:9].tolist() == [0.0, 0.0, 0.0]
    assert out[10] == pytest.approx(2 * smoothstep(np.array(2 / 3)))
    assert out[[0, 3, 11]].tolist() == [1.0, 3.0, 2.0]


def test_knee_flexion_from_the_law_of_cosines():
    # thigh 0.43, shin 0.43: a reach of 0.43·√2 needs a 90° knee; full length is straight
    flex = knee_flexion_for_reach(np.array([0.43 * np.sqrt(2), 0.86, 1.5]), 0.43, 0.43)
    assert np.allclose(flex, [np.pi / 2, 0.0, 0.0])


@pytest.mark.parametrize("model", ["humanoid_1seg", "humanoid_2seg"])
def test_leg_ik_reaches_the_target_and_keeps_the_foot_orientation(model):
    hm = load_model(model)
    qpos = load_motion("deepmimic:walk", model).qpos
    kin = hm.forward_kinematics(qpos)
    for side in "lr":
        leg = LegIK(hm, side)
        target = kin.body_pos[:, leg.foot] + [0.04, -0.03, 0.02]
        q = qpos.copy()
        leg.reach(q, kin.body_pos, kin.body_quat, target)
        after = hm.forward_kinematics(q)
        reach = np.linalg.norm(target - kin.body_pos[:, leg.thigh], axis=-1)
        reachable = reach < leg.thigh_len + leg.shin_len
        assert reachable.mean() > 0.8
        assert np.abs(after.body_pos[reachable, leg.foot] - target[reachable]).max() < 1e-9
        # out of reach: the nearest reachable pose, a straight knee
        assert np.allclose(q[~reachable, leg.knee_joint.qpos_index[0]], 0.0)
        assert rot.angle(rot.multiply(rot.conjugate(kin.body_quat[:, leg.foot]), after.body_quat[:, leg.foot])).max() < 1e-6
        untouched = [i for i, n in enumerate(hm.body_names) if not n.startswith(f"{side}_")]
        assert np.allclose(after.body_pos[:, untouched], kin.body_pos[:, untouched])


def test_pinning_removes_synthetic_foot_skate_without_moving_the_body():
    clean = load_motion("deepmimic:walker/turn_left1", min_frames=300)
    skating = corrupt(clean, ArtefactRecipe.only("skate", 1.0), seed=3)
    pinned = pin_contacts(skating)
    before, after = motion_quality(skating).foot_skate_mps, motion_quality(pinned).foot_skate_mps
    assert before > 0.2 and after < 0.35 * before, (before, after)   # measured: 0.26 -> 0.08 m/s
    hm = load_model(clean.model)
    moved = np.linalg.norm(hm.forward_kinematics(pinned.qpos).body_pos - hm.forward_kinematics(skating.qpos).body_pos, axis=-1)
    assert moved.mean() < 0.02
    assert np.array_equal(pinned.qpos[:, :7], skating.qpos[:, :7])  # only the legs move


def test_a_shuffling_foot_is_not_dragged_across_its_steps():
    """A foot point that never rises above the contact height while it walks 1.2 m in 2 s (0.6 m/s,
    a shuffle: slower than a swing skimming the floor) is one window by height alone; pinning it
    would hold it 0.6 m away at each end, so by default the window is left alone. A planted foot
    sliding 10 cm is still pinned."""
    t = np.arange(121) / 60.0
    shuffle = np.stack([np.stack([0.6 * t, np.zeros_like(t)], -1)] * 2, axis=1)  # (T, 2 points, xy)
    planted = np.ones((121, 2), bool)
    assert np.abs(pin_corrections(shuffle, planted, None)).max() == pytest.approx(0.6)
    assert not pin_corrections(shuffle, planted, PinningConfig().max_correction_m).any()
    slide = shuffle / 12  # 10 cm over the same 2 s
    np.testing.assert_allclose(pin_corrections(slide, planted, PinningConfig().max_correction_m)[:, 0],
                               0.05 - slide[:, 0, 0], atol=1e-9)


def test_pinning_fixes_the_sliding_in_deepmimic_run():
    raw = motion_quality(load_motion("deepmimic:run", pin_feet=False)).foot_skate_mps
    pinned = motion_quality(load_motion("deepmimic:run")).foot_skate_mps
    assert raw > 0.25 and pinned < 0.05, (raw, pinned)


def test_masked_mean_averages_the_marked_points_and_gives_zero_where_none_is():
    from reference_motion.footskate import masked_mean

    values = np.array([[[1.0, 2.0], [3.0, 6.0]], [[5.0, 0.0], [7.0, 1.0]], [[9.0, 9.0], [9.0, 9.0]]])
    mask = np.array([[True, True], [False, True], [False, False]])
    np.testing.assert_allclose(masked_mean(values, mask), [[2.0, 4.0], [7.0, 1.0], [0.0, 0.0]])
