import numpy as np
import pytest

from reference_motion import deepmimic
from reference_motion import rotations as rot
from reference_motion.humanoid.model import load_model
from reference_motion.leg_gap import median_foot_gap
from reference_motion.library import STYLE_SHIFT_NAMES, StyleShifts, augmented, load_motion, named_set, style_shifted
from reference_motion.motion import Motion
from reference_motion.quality import motion_quality
from reference_motion.retarget import bone_direction_error, retarget
from reference_motion.transforms import (PostureRanges, loop, mirror, posture_offsets, random_posture, resample,
                                        reversed_in_time, time_warp, with_posture)

CLIPS = deepmimic.clip_names()


def test_twenty_clips_totalling_39_7_seconds():
    assert len(CLIPS) == 20
    total = sum(deepmimic.load(n).n_frames / deepmimic.load(n).fps for n in CLIPS)
    assert 38.0 < total < 41.0


@pytest.mark.parametrize("model", ["humanoid_1seg", "humanoid_2seg"])
def test_all_clips_retarget_with_matching_bone_directions(model):
    hm = load_model(model)
    for name in CLIPS:
        clip = deepmimic.load(name)
        motion = retarget(clip, model)
        assert motion.qpos.shape == (clip.n_frames, hm.nq)
        err = bone_direction_error(clip, motion)
        assert err.mean() < 5.0, f"{name}: mean bone direction error {err.mean():.2f} deg"


def test_retargeted_clip_starts_at_origin_facing_plus_x():
    m = load_motion("deepmimic:walker/turn_left0")
    assert np.allclose(m.qpos[0, :2], 0.0, atol=1e-9)
    assert abs(rot.yaw(m.qpos[0, 3:7])) < 1e-6
    assert np.ptp(m.qpos[:, 0]) > 0.5  # and it walks forward


LOCOMOTION = named_set("locomotion")


@pytest.mark.parametrize("source", LOCOMOTION)
def test_locomotion_replay_quality(source):
    for model in ("humanoid_1seg", "humanoid_2seg"):
        q = motion_quality(load_motion(source, model))
        assert q.penetration_max_m <= 0.02, f"{source}/{model}: penetration {q.penetration_max_m:.3f} m"
        assert q.floating_m <= 0.02
        assert min(q.contact_frac) > 0.0
        assert q.foot_skate_mps <= 0.15, f"{source}/{model}: skate {q.foot_skate_mps:.3f} m/s"


def test_resample_to_60hz_keeps_duration_and_endpoints():
    m30 = retarget(deepmimic.load("walk"))
    assert m30.fps == pytest.approx(30.0, rel=1e-3)
    m60 = resample(m30, 60.0)
    assert m60.fps == 60.0
    assert m60.duration == pytest.approx(m30.duration, abs=1 / 60)
    assert np.allclose(m60.qpos[0], m30.qpos[0])
    # the source rate is 1/0.033332 s = 30.0012 Hz, so 60 Hz frame 2 sits a hair before source frame 1
    assert np.allclose(m60.qpos[2], m30.qpos[1], atol=1e-4)
    mid = m60.qpos[1, 7:]
    assert np.allclose(mid, 0.5 * (m30.qpos[0, 7:] + m30.qpos[1, 7:]), atol=1e-4)


def test_loop_carries_root_offset_over_cycles():
    m = retarget(deepmimic.load("walk"))
    cycle = np.linalg.norm(m.qpos[-1, :2] - m.qpos[0, :2])
    n = m.n_frames - 1
    long = loop(m, 3 * n + 1)
    assert long.n_frames == 3 * n + 1
    # each cycle moves the root as far as the first did (turned by the cycle's small heading change)
    assert np.linalg.norm(long.qpos[2 * n, :2] - long.qpos[n, :2]) == pytest.approx(cycle, abs=1e-6)
    assert long.qpos[3 * n, 0] > 3 * 0.9 * cycle
    assert np.allclose(long.qpos[n + 5, 7:], long.qpos[5, 7:])
    seams = np.abs(np.diff(long.hinges[n - 2:n + 3], axis=0)).max()
    raw_seam = np.abs(m.hinges[0] - m.hinges[-1]).max()  # what a plain wrap would jump by (0.46 rad)
    assert seams < 0.5 * raw_seam, "the seam blend removes the pose jump between cycles"
    with pytest.raises(ValueError, match="not cyclic"):
        loop(retarget(deepmimic.load("kick")), 500)


def test_mirror_swaps_sides():
    m = load_motion("deepmimic:walker/turn_left0")
    mm = mirror(m)
    hm = load_model(m.model)
    k, km = hm.forward_kinematics(m.qpos), hm.forward_kinematics(mm.qpos)
    left_foot, right_foot = hm.body_names.index("l_foot"), hm.body_names.index("r_foot")
    expected = k.body_pos[:, right_foot] * [1, -1, 1]
    assert np.allclose(km.body_pos[:, left_foot], expected, atol=1e-9)
    assert np.allclose(mirror(mm).qpos, m.qpos)
    assert rot.yaw(mm.qpos[-1, 3:7]) == pytest.approx(-rot.yaw(m.qpos[-1, 3:7]))  # turns right


def test_time_warp_scales_duration_and_speed(walk):
    fast, slow = time_warp(walk, 1.2), time_warp(walk, 0.8)
    assert fast.n_frames == pytest.approx(walk.n_frames / 1.2, abs=2)
    assert slow.n_frames == pytest.approx(walk.n_frames / 0.8, abs=2)
    speed = lambda m: np.linalg.norm(m.qpos[-1, :2] - m.qpos[0, :2]) / m.duration  # noqa: E731
    assert speed(fast) == pytest.approx(1.2 * speed(walk), rel=0.01)
    assert np.allclose(fast.qpos[-1, :2], walk.qpos[-1, :2], atol=0.02)  # same path, walked faster
    with pytest.raises(ValueError, match="speed must be a finite number > 0"):
        time_warp(walk, 0.0)


def test_reversed_in_time_walks_backwards_with_the_same_torques_and_ground_forces(walk):
    """Played backwards, walk moves the other way with every velocity negated; rigid-body inverse
    dynamics (contacts off, so the root's row is the wrench the ground must supply) is the same at
    every pose, as M(q)q̈ + C(q, q̇)q̇ + g(q) is even in q̇; twice reversed is the walk again."""
    import copy

    import mujoco

    back = reversed_in_time(walk)
    assert back.name == "deepmimic:walk (reversed)" and back.source["reversed"] and back.fps == walk.fps
    np.testing.assert_array_equal(back.qpos, walk.qpos[::-1])
    heading = rot.yaw(walk.root_quat[0])
    assert np.median(walk.qvel[:, 0] * np.cos(heading)) > 0.5 > -0.5 > np.median(back.qvel[:, 0] * np.cos(heading))
    np.testing.assert_allclose(back.qvel[::-1], -walk.qvel, atol=1e-9)
    again = reversed_in_time(back)
    assert again.name == walk.name and not again.source["reversed"]
    np.testing.assert_array_equal(again.qpos, walk.qpos)

    model = copy.copy(load_model(walk.model).model)
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    assert not model.dof_damping.any()  # no velocity-linear passive force to flip sign
    data = mujoco.MjData(model)

    def inverse_dynamics(motion, t):
        data.qpos[:], data.qvel[:] = motion.qpos[t], motion.qvel[t]
        data.qacc[:] = np.gradient(motion.qvel, 1.0 / motion.fps, axis=0)[t]
        mujoco.mj_inverse(model, data)
        return data.qfrc_inverse.copy()

    for t in (40, 150, 260):
        forward, backward = inverse_dynamics(walk, t), inverse_dynamics(back, walk.n_frames - 1 - t)
        assert np.abs(forward[2]) > 400  # the ground carries the body's weight (N)
        np.testing.assert_allclose(backward, forward, rtol=1e-6, atol=1e-6)


def test_posture_offsets_by_hand():
    hm = load_model("humanoid_1seg")
    off = posture_offsets("humanoid_1seg", trunk_flexion=0.3, neck_flexion=0.1, crouch=0.2, stance_width=0.05,
                          elbow_flexion=0.4)
    at = {name: off[hm.qpos_index(name)] for name in hm.hinge_names}
    assert at["spine_lower_y"] == at["spine_mid_y"] == at["chest_y"] == pytest.approx(0.1) and at["neck_y"] == 0.1
    for side, out in (("l", 1), ("r", -1)):  # knee 2a, hip and ankle -a: the sole keeps its pitch
        assert (at[f"{side}_thigh_y"], at[f"{side}_shin_y"], at[f"{side}_foot_y"]) == pytest.approx((-0.2, 0.4, -0.2))
        assert (at[f"{side}_thigh_x"], at[f"{side}_foot_x"]) == pytest.approx((0.05 * out, -0.05 * out))
        assert at[f"{side}_forearm_y"] == 0.4
    assert np.count_nonzero(off) == 4 + 2 * 6 and not off[:7].any()
    draws = np.array([random_posture("humanoid_1seg", np.random.default_rng(s))[hm.qpos_index("l_shin_y")]
                      for s in range(50)])
    assert 0 <= draws.min() and draws.max() <= 2 * np.radians(12) and draws.std() > 0.05
    with pytest.raises(ValueError, match=r"PostureRanges.crouch_deg must be \(low, high\)"):
        PostureRanges(crouch_deg=(10.0, 0.0))


def test_a_posture_keeps_the_centre_of_mass_path_and_the_floor_contact(walk):
    """walk with a 30° stoop and a 10° crouch: the centre of mass walks the same path (the hips go
    back, the pelvis lower), the lowest point of the body is as high as before in every frame,
    and the stance feet still hold their ground within a few cm/s."""
    import mujoco

    hm = load_model(walk.model)
    off = posture_offsets(walk.model, trunk_flexion=np.radians(30), crouch=np.radians(10))
    stooped = with_posture(walk, off, "stoop")
    assert stooped.name == "deepmimic:walk (stoop)" and len(stooped.source["posture_rad"]) == hm.nq - 7
    data = mujoco.MjData(hm.model)

    def com(qpos):
        out = []
        for q in qpos:
            data.qpos[:] = q
            mujoco.mj_kinematics(hm.model, data)
            out.append(hm.model.body_mass @ data.xipos / hm.model.body_mass.sum())
        return np.array(out)

    np.testing.assert_allclose(com(stooped.qpos)[:, :2], com(walk.qpos)[:, :2], atol=1e-9)
    before, after = hm.forward_kinematics(walk.qpos), hm.forward_kinematics(stooped.qpos)
    np.testing.assert_allclose(after.lowest, before.lowest, atol=1e-9)
    shift = stooped.qpos[:, :3] - walk.qpos[:, :3]
    assert np.median(shift[:, 0] * np.cos(rot.yaw(walk.root_quat[0]))) < -0.02 and np.median(shift[:, 2]) < -0.01
    moved = stooped.qpos[:, 7:] - walk.qpos[:, 7:]
    np.testing.assert_allclose(moved, np.broadcast_to(off[7:], moved.shape), atol=1e-12)  # all within their ranges
    planted = after.foot_points[1:, :, 2] < 0.03
    slide = np.linalg.norm(np.diff(after.foot_points[..., :2], axis=0), axis=-1)[planted] * walk.fps
    assert np.median(slide) < 0.08
    with pytest.raises(ValueError, match=r"posture offsets must be finite, shape \(50,\) .* zero on the root"):
        with_posture(walk, np.ones(hm.nq))


def test_augmented_set_mirrors_and_warps(walk):
    clips = augmented([walk], mirrored=True, speeds=(0.8, 1.0))
    assert [c.name for c in clips] == ["deepmimic:walk (x0.8 speed)", "deepmimic:walk",
                                       "deepmimic:walk (x0.8 speed) (mirrored)", "deepmimic:walk (mirrored)"]
    assert clips[1] is walk
    assert motion_quality(clips[0]).foot_skate_mps < 0.08  # re-pinned after warping
    with pytest.raises(ValueError, match="speeds is empty"):
        augmented([walk], speeds=())


def test_style_shifted_takes_are_wider_slower_faster_and_carried_otherwise(walk):
    """Five versions per take, the draws fixed by the seed: the wider copy's feet further apart by
    its drawn distance, the warped ones as long as their pace says, the postured one another carriage."""
    clips = style_shifted([walk], seed=3)
    assert len(clips) == len(STYLE_SHIFT_NAMES) == 5
    given, wider, slower, faster, postured = clips
    assert given is walk
    extra = float(wider.name.split("(stance +")[1].split(" m)")[0])
    assert 0.1 <= extra <= 0.35
    gap = median_foot_gap(walk.model, wider.qpos) - median_foot_gap(walk.model, walk.qpos)
    assert gap == pytest.approx(extra, abs=0.05)
    assert slower.n_frames == pytest.approx(walk.n_frames / 0.8, abs=2)
    assert faster.n_frames == pytest.approx(walk.n_frames / 1.25, abs=2)
    assert np.abs(postured.qpos[:, 7:] - walk.qpos[:, 7:]).max() > np.radians(1)
    again = style_shifted([walk], seed=3)
    assert [c.name for c in again] == [c.name for c in clips]
    assert np.array_equal(again[4].qpos, postured.qpos)
    assert style_shifted([walk], seed=4)[1].name != wider.name
    with pytest.raises(ValueError, match="expected 0 < slower < 1 < faster"):
        StyleShifts(slower=1.2)
    with pytest.raises(ValueError, match="StyleShifts.stance_extra_m"):
        StyleShifts(stance_extra_m=(0.3, 0.1))


def test_motion_npz_round_trip(tmp_path, walk):
    path = walk.save(tmp_path / "walk.npz")
    back = Motion.load(path)
    assert np.array_equal(back.qpos, walk.qpos) and back.fps == walk.fps and back.model == walk.model
    assert back.source == walk.source and back.loop
    assert back.qvel.shape == (walk.n_frames, walk.qpos.shape[1] - 1)


def test_qvel_matches_mujoco_differentiation(walk):
    import mujoco

    hm = load_model(walk.model)
    v = np.zeros(hm.nv)
    mujoco.mj_differentiatePos(hm.model, v, 2 / walk.fps, walk.qpos[9], walk.qpos[11])
    assert np.allclose(walk.qvel[10], v, atol=1e-6)


def test_held_repeats_the_last_frame_and_is_not_cyclic(walk):
    held = walk.held(5)
    assert held.n_frames == walk.n_frames + 5 and not held.loop
    np.testing.assert_array_equal(held.qpos[:walk.n_frames], walk.qpos)
    np.testing.assert_array_equal(held.qpos[-5:], np.repeat(walk.qpos[-1:], 5, axis=0))
    with pytest.raises(ValueError, match="frames to hold must be >= 0"):
        walk.held(-1)
