"""agents/policy_set.py: the backward-walking, dash, fast, sideways and turn rules by hand and on real clips, the set file,
routing."""

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from agents import evaluate
from agents.policy import PolicyError
from agents.policy_set import (THRESHOLD_FIELDS, PolicySet, heading_frame_velocity, heading_speeds, load_policy_set,
                               median_ground_speed, route_clips, source_name, turn_rate, turns, walks_backward,
                               walks_sideways)
from reference_motion.library import load_motion
from reference_motion.library import posture_copies, stance_copies
from reference_motion import rotations as rot
from reference_motion.transforms import mirror, reversed_in_time, time_warp, turned

MODELS = Path(__file__).parents[1] / "models"


def _quat_yaw(yaw: float) -> np.ndarray:
    return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


def test_heading_speed_by_hand():
    """A root facing +y (yaw 90°) moving at 0.5 m/s along −y: −0.5 m/s along its heading; moving
    sideways (+x) it is 0."""
    fps = 60.0
    t = np.arange(30) / fps
    qpos = np.zeros((30, 7))
    qpos[:, 3:7] = _quat_yaw(math.pi / 2)
    qpos[:, 1] = -0.5 * t
    assert np.allclose(heading_speeds(qpos, fps), -0.5)
    qpos[:, 1], qpos[:, 0] = 0.0, 0.5 * t
    assert np.allclose(heading_speeds(qpos, fps), 0.0, atol=1e-12)
    with pytest.raises(ValueError, match="at least 2 frames"):
        heading_speeds(qpos[:1], fps)


def test_a_walk_is_forward_and_the_same_walk_played_backwards_is_not():
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    backwards = walk.with_qpos(walk.qpos[::-1].copy(), loop=False)
    assert np.median(heading_speeds(walk.qpos, walk.fps)) > 0.5  # DeepMimic's walk: ~1 m/s
    assert not walks_backward(walk, 0.2) and walks_backward(backwards, 0.2)


def test_policy_set_file_round_trip_and_errors(tmp_path):
    saved = PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", 0.3).save()
    spec = json.loads(saved.read_text())
    assert not Path(spec["default"]).is_absolute() and spec["format"] == "physmimic.policy_set/1"
    loaded = load_policy_set(tmp_path / "set")
    assert loaded.default.resolve() == (MODELS / "mimic_walk").resolve() and loaded.backward_speed_mps == 0.3
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "policy_set.json").write_text(json.dumps({"format": "physmimic.policy_set/1", "default": "x"}))
    with pytest.raises(PolicyError, match="backward missing"):
        load_policy_set(bad)
    (bad / "policy_set.json").write_text("[1, 2]")
    with pytest.raises(PolicyError, match="holds a JSON list, expected an object"):
        load_policy_set(bad)
    (bad / "policy_set.json").write_text("{not json")
    with pytest.raises(PolicyError, match="cannot read the policy set"):
        load_policy_set(bad)


def test_a_policy_set_routes_each_clip_and_evaluate_scores_them_all(tmp_path):
    """The walk goes to the default policy, the walk played backwards to the backward one; the
    evaluation command runs each group with its own policy and reports every rollout, naming a
    member given as its ``model.zip`` by its directory (a run's checkpoint by its file:
    tests/test_policy_files.py)."""
    PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu").save()
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    backwards = walk.with_qpos(walk.qpos[::-1].copy(), loop=False)
    groups = route_clips(tmp_path / "set", lambda foot: [walk, backwards, walk])
    assert [(g.path.name, len(clips)) for g, clips in groups] == [("mimic_walk", 2), ("mimic_imu", 1)]
    assert groups[1][1][0] is backwards
    (plain,) = route_clips(MODELS / "mimic_walk", lambda foot: [walk, backwards])
    assert plain[0].path.name == "mimic_walk" and len(plain[1]) == 2
    result = evaluate.main(["--policy", str(tmp_path / "set"), "--clips", "deepmimic:walk", "--episodes", "2"])
    assert result["rollouts"] == 2 and result["ELR_mean"] == 1.0  # mimic_walk walks its own clip whole
    assert {name: Path(policy).name for name, policy in result["routed_to"].items()} == {"deepmimic:walk": "mimic_walk"}
    PolicySet(tmp_path / "by_file", MODELS / "mimic_walk" / "model.zip", MODELS / "mimic_imu").save()
    result = evaluate.main(["--policy", str(tmp_path / "by_file"), "--clips", "deepmimic:walk", "--episodes", "1"])
    assert Path(result["routed_to"]["deepmimic:walk"]).relative_to(MODELS.resolve()) == Path("mimic_walk")


def test_clip_globs_route_before_the_backward_rule_and_round_trip(tmp_path):
    """A ``clips`` route sends the walk played backwards (whose name matches) to the walk policy,
    ahead of the backward rule; a clip no glob matches is routed as before."""
    set_dir = tmp_path / "set"
    PolicySet(set_dir, MODELS / "mimic_walk", MODELS / "mimic_imu", clips=(("*reversed*", MODELS / "mimic_walk"),)).save()
    spec = json.loads((set_dir / "policy_set.json").read_text())
    assert list(spec["clips"]) == ["*reversed*"] and not Path(spec["clips"]["*reversed*"]).is_absolute()
    loaded = load_policy_set(set_dir)
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    backwards = walk.with_qpos(walk.qpos[::-1].copy(), loop=False)
    reversed_ = backwards.with_qpos(backwards.qpos, name="walk reversed")
    assert loaded.route(reversed_).resolve() == (MODELS / "mimic_walk").resolve()
    assert loaded.route(backwards).resolve() == (MODELS / "mimic_imu").resolve()
    assert len(loaded.policies) == 2  # the route's policy is the default one, counted once
    spec["clips"] = {"*": 3}
    (set_dir / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="clips must be an object of clip-name globs"):
        load_policy_set(set_dir)


def test_a_glob_naming_a_take_exactly_routes_its_copies_with_it(tmp_path):
    """Mirrored, time-warped and reversed copies carry the take's name with suffixes; an exact-name
    glob routes them with the take, and a glob naming a suffix, listed first, routes copies apart."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    copies = [mirror(walk), time_warp(mirror(walk), 1.5), reversed_in_time(walk)]
    assert [c.name for c in copies] == ["deepmimic:walk (mirrored)", "deepmimic:walk (mirrored) (x1.5 speed)",
                                        "deepmimic:walk (reversed)"]
    assert [source_name(c.name) for c in copies] == ["deepmimic:walk"] * 3 and source_name("amc:02_03") == "amc:02_03"
    posture, turn = posture_copies([walk], 1, seed=0)[0], turned(mirror(walk), np.pi / 2)
    assert [source_name(m.name) for m in (posture, turn)] == ["deepmimic:walk"] * 2, (posture.name, turn.name)
    assert source_name("deepmimic:walk (mirrored) (cleaned)") == "deepmimic:walk (mirrored) (cleaned)"  # not a copy
    wide = stance_copies([mirror(walk)], 1, seed=0, extra_m=(-0.05, -0.05))[0]
    assert wide.name == "deepmimic:walk (mirrored) (stance -0.05 m)" and source_name(wide.name) == "deepmimic:walk"
    assert source_name("deepmimic:walk (stance 0.3 m)") == "deepmimic:walk (stance 0.3 m)"  # no sign: not a copy
    exact = PolicySet(tmp_path / "a", MODELS / "mimic_imu", MODELS / "mimic_imu",
                      clips=(("deepmimic:walk", MODELS / "mimic_walk"),))
    assert all(exact.route(m) == MODELS / "mimic_walk" for m in (walk, *copies))
    apart = PolicySet(tmp_path / "b", MODELS / "mimic_walk", MODELS / "mimic_imu",
                      clips=(("*(reversed)*", MODELS / "mimic_imu"), ("deepmimic:walk", MODELS / "mimic_walk")))
    assert [apart.route(m).name for m in (walk, *copies)] == ["mimic_walk", "mimic_walk", "mimic_walk", "mimic_imu"]
    other = walk.with_qpos(walk.qpos, name="deepmimic:walking (mirrored)")
    assert exact.route(other) == MODELS / "mimic_imu"  # "walking" is not "walk"


def test_median_ground_speed_by_hand():
    """A root going 3 m/s along x and 4 along y, bobbing up and down: 5 m/s on the ground."""
    fps = 60.0
    t = np.arange(40) / fps
    qpos = np.zeros((40, 7))
    qpos[:, 0], qpos[:, 1], qpos[:, 2] = 3 * t, 4 * t, 0.9 + 0.1 * np.sin(20 * t)
    assert median_ground_speed(qpos, fps) == pytest.approx(5.0)
    with pytest.raises(ValueError, match="at least 2 frames"):
        median_ground_speed(qpos[:1], fps)


def test_the_fast_rule_routes_a_run_after_the_backward_rule_and_round_trips(tmp_path):
    """DeepMimic's run (median 3.9 m/s on the ground) goes to the fast policy, its walk (1.0 m/s) to the
    default; the run played backwards walks backwards, so the backward rule takes it first. Without a
    fast policy the run stays with the default; the file keeps the rule, and a bad speed is refused."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    run = load_motion("deepmimic:run", "humanoid_1seg")
    assert median_ground_speed(walk.qpos, walk.fps) < 1.5 < 2.5 < median_ground_speed(run.qpos, run.fps)
    backwards = run.with_qpos(run.qpos[::-1].copy(), loop=False)
    fast = PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", fast=MODELS / "mimic_general",
                     fast_speed_mps=2.0)
    assert [fast.route(m).name for m in (walk, run, backwards)] == ["mimic_walk", "mimic_general", "mimic_imu"]
    assert [p.name for p in fast.policies] == ["mimic_walk", "mimic_imu", "mimic_general"]
    assert PolicySet(tmp_path / "plain", MODELS / "mimic_walk", MODELS / "mimic_imu").route(run).name == "mimic_walk"
    spec = json.loads(fast.save().read_text())
    assert spec["fast_speed_mps"] == 2.0 and not Path(spec["fast"]).is_absolute()
    loaded = load_policy_set(tmp_path / "set")
    assert loaded.fast.resolve() == (MODELS / "mimic_general").resolve() and loaded.route(run).name == "mimic_general"
    assert "fast" not in json.loads(PolicySet(tmp_path / "plain", MODELS / "mimic_walk", MODELS / "mimic_imu")
                                    .save().read_text())
    spec["fast_speed_mps"] = -1
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="fast_speed_mps must be a finite number >= 0"):
        load_policy_set(tmp_path / "set")
    for bad in (float("nan"), float("inf"), "2", True):
        with pytest.raises(PolicyError, match="fast_speed_mps must be a finite number >= 0"):
            PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", fast_speed_mps=bad)
    with pytest.raises(PolicyError, match="backward_speed_mps must be a finite number >= 0"):
        PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", backward_speed_mps=-0.1)
    spec["fast_speed_mps"], spec["fast"] = 2.0, 7
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="fast must be a policy directory"):
        load_policy_set(tmp_path / "set")
    del spec["fast"]
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="fast_speed_mps is given without fast"):
        load_policy_set(tmp_path / "set")
    spec["fast_speed"] = 2.0
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="unknown field.s. fast_speed;"):
        load_policy_set(tmp_path / "set")


def test_the_dash_rule_routes_a_sprint_before_the_fast_rule_and_round_trips(tmp_path):
    """DeepMimic's run (median 3.9 m/s) is above the dash rule's 3.0 m/s and goes to the dash policy; played at
    0.7× its pace (2.7 m/s) it is under it and goes to the fast policy; its walk goes to the default and the run
    played backwards to the backward policy. The file keeps the rule and its speed; a lone speed is refused."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    run = load_motion("deepmimic:run", "humanoid_1seg")
    jog = time_warp(run, 0.7)
    assert 2.0 < median_ground_speed(jog.qpos, jog.fps) < 3.0 < median_ground_speed(run.qpos, run.fps)
    backwards = run.with_qpos(run.qpos[::-1].copy(), loop=False)
    dash = PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", dash=MODELS / "mimic_walk_back",
                     fast=MODELS / "mimic_general")
    assert dash.dash_speed_mps == 3.0
    assert [dash.route(m).name for m in (walk, run, jog, backwards)] == ["mimic_walk", "mimic_walk_back",
                                                                          "mimic_general", "mimic_imu"]
    assert [p.name for p in dash.policies] == ["mimic_walk", "mimic_imu", "mimic_walk_back", "mimic_general"]
    spec = json.loads(replace(dash, dash_speed_mps=4.0).save().read_text())
    assert spec["dash_speed_mps"] == 4.0 and not Path(spec["dash"]).is_absolute()
    loaded = load_policy_set(tmp_path / "set")
    assert loaded.dash.resolve() == (MODELS / "mimic_walk_back").resolve() and loaded.route(run).name == "mimic_general"
    with pytest.raises(PolicyError, match=r"dash_speed_mps \(2 m/s\) must be above fast_speed_mps \(2 m/s\)"):
        replace(dash, dash_speed_mps=2.0)
    del spec["dash"]
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="dash_speed_mps is given without dash"):
        load_policy_set(tmp_path / "set")


def test_turn_rate_by_hand():
    """A heading turning 90° left over 2 s, through the ±180° seam, turns at π/4 rad/s; the same turned back
    halfway, or swaying ±20° from step to step, nets less; a heading turning right counts the same."""
    fps = 60.0
    yaw = np.radians(150.0) + np.linspace(0.0, math.pi / 2, 121)  # 150° -> 240° (= -120°): across the seam
    qpos = np.zeros((121, 7))
    qpos[:, 3:7] = np.stack([_quat_yaw(a) for a in yaw])
    assert turn_rate(qpos, fps) == pytest.approx(math.pi / 4)
    qpos[:, 3:7] = np.stack([_quat_yaw(-a) for a in yaw])
    assert turn_rate(qpos, fps) == pytest.approx(math.pi / 4)
    there_and_back = np.concatenate([yaw[:61], yaw[60::-1][1:]])
    qpos[:, 3:7] = np.stack([_quat_yaw(a) for a in there_and_back])
    assert turn_rate(qpos, fps) == pytest.approx(0.0, abs=1e-9)
    sway = np.radians(20.0) * np.sin(np.linspace(0.0, 8 * math.pi, 121))
    qpos[:, 3:7] = np.stack([_quat_yaw(a) for a in sway])
    assert turn_rate(qpos, fps) == pytest.approx(0.0, abs=1e-9)
    off_phase = np.radians(20.0) * np.sin(np.linspace(0.0, 8.5 * math.pi, 121))  # ends a quarter period on: +20°
    qpos[:, 3:7] = np.stack([_quat_yaw(a) for a in off_phase])
    assert turn_rate(qpos, fps) == pytest.approx(np.radians(20.0) / 2.0)
    with pytest.raises(ValueError, match="at least 2 frames"):
        turn_rate(qpos[:1], fps)


def test_the_turn_rule_routes_deepmimics_turn_after_the_other_rules_and_round_trips(tmp_path):
    """DeepMimic's walker/turn_right0 turns 99° at 1.4 rad/s and goes to the turn policy (0.3 rad/s); its walk
    (0.1 rad/s) stays with the default, and its run, turning as little, goes to the fast policy first. The
    file keeps the rule and its rate; a lone rate and a bad rate are refused, the message in rad/s."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    run = load_motion("deepmimic:run", "humanoid_1seg")
    turn = load_motion("deepmimic:walker/turn_right0", "humanoid_1seg")
    assert turn_rate(walk.qpos, walk.fps) < 0.2 < 1.0 < turn_rate(turn.qpos, turn.fps)
    assert turns(turn, 0.3) and not turns(walk, 0.3)
    turning = PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", fast=MODELS / "mimic_general",
                        turn=MODELS / "mimic_walk_back")
    assert turning.turn_rate_rad_s == 0.3
    assert [turning.route(m).name for m in (walk, run, turn)] == ["mimic_walk", "mimic_general", "mimic_walk_back"]
    assert [p.name for p in turning.policies] == ["mimic_walk", "mimic_imu", "mimic_general", "mimic_walk_back"]
    spec = json.loads(replace(turning, turn_rate_rad_s=2.0).save().read_text())
    assert spec["turn_rate_rad_s"] == 2.0 and not Path(spec["turn"]).is_absolute()
    loaded = load_policy_set(tmp_path / "set")
    assert loaded.turn.resolve() == (MODELS / "mimic_walk_back").resolve() and loaded.route(turn).name == "mimic_walk"
    assert replace(turning, turn_rate_rad_s=0.05).route(run).name == "mimic_general"  # over 0.05: the fast rule first
    whole = PolicySet(tmp_path / "ints", MODELS / "mimic_walk", MODELS / "mimic_imu", backward_speed_mps=0,
                      turn_rate_rad_s=1)
    assert [type(getattr(whole, name)) for name in THRESHOLD_FIELDS] == [float] * len(THRESHOLD_FIELDS)  # ints kept as floats
    with pytest.raises(PolicyError, match=r"turn_rate_rad_s must be a finite number >= 0 \(rad/s\)"):
        PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", turn_rate_rad_s=-1.0)
    del spec["turn"]
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="turn_rate_rad_s is given without turn"):
        load_policy_set(tmp_path / "set")


def test_heading_frame_velocity_by_hand():
    """A root facing +y (yaw 90°) moving at 0.5 m/s along +x moves 0.5 m/s to its right (−0.5 across its
    heading), none along it; along −x, to its left."""
    fps = 60.0
    t = np.arange(30) / fps
    qpos = np.zeros((30, 7))
    qpos[:, 3:7] = _quat_yaw(math.pi / 2)
    qpos[:, 0] = 0.5 * t
    assert np.allclose(heading_frame_velocity(qpos, fps), [0.0, -0.5])
    qpos[:, 0] = -0.5 * t
    assert np.allclose(heading_frame_velocity(qpos, fps), [0.0, 0.5])
    qpos[:, 3:7] = _quat_yaw(math.radians(30))  # facing 30° left of +x, moving (0.3, 0.4) m/s
    qpos[:, 0], qpos[:, 1] = 0.3 * t, 0.4 * t
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert np.allclose(heading_frame_velocity(qpos, fps), [0.3 * c + 0.4 * s, 0.4 * c - 0.3 * s])
    with pytest.raises(ValueError, match="at least 2 frames"):
        heading_frame_velocity(qpos[:1], fps)


def _facing_turned(motion, yaw: float):
    """``motion`` with its pelvis turned by ``yaw`` (rad) about the vertical, its path unchanged."""
    qpos = motion.qpos.copy()
    qpos[:, 3:7] = rot.multiply(np.broadcast_to(_quat_yaw(yaw), qpos[:, 3:7].shape), qpos[:, 3:7])
    return motion.with_qpos(qpos, name=f"{motion.name} facing {yaw:.2f}")


def test_the_sideways_rule_routes_a_walk_facing_across_its_path_after_the_fast_rule_and_round_trips(tmp_path):
    """DeepMimic's walk with its pelvis turned 90° either way (its path unchanged) goes at about 1 m/s across its
    heading and to the sideways policy; as given, or turned 5°, it stays with the default. Its run turned 90° is
    fast, and the fast rule takes it first; the walk played backwards and turned 60° walks backwards and
    sideways, and the backward rule takes it first. The file keeps the rule and its speed; a bad speed, a
    lone speed or a policy that is not a directory name is refused."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg")
    run = load_motion("deepmimic:run", "humanoid_1seg")
    left, right, slightly = (_facing_turned(walk, yaw) for yaw in (-math.pi / 2, math.pi / 2, math.radians(5)))
    assert np.median(heading_frame_velocity(left.qpos, left.fps)[:, 1]) > 0.8
    assert np.median(heading_frame_velocity(right.qpos, right.fps)[:, 1]) < -0.8
    assert abs(np.median(heading_frame_velocity(walk.qpos, walk.fps)[:, 1])) < 0.05
    assert abs(np.median(heading_frame_velocity(slightly.qpos, slightly.fps)[:, 1])) < 0.2
    back_and_aside = _facing_turned(walk.with_qpos(walk.qpos[::-1].copy(), loop=False), math.radians(60))
    assert walks_backward(back_and_aside, 0.2) and walks_sideways(back_and_aside, 0.2)
    assert [walks_sideways(m, 0.2) for m in (walk, left, right, slightly)] == [False, True, True, False]
    sideways = PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", fast=MODELS / "mimic_general",
                         sideways=MODELS / "mimic_walk_back")
    routed = [sideways.route(m).name for m in (walk, left, right, slightly, _facing_turned(run, math.pi / 2),
                                               back_and_aside)]
    assert routed == ["mimic_walk", "mimic_walk_back", "mimic_walk_back", "mimic_walk", "mimic_general", "mimic_imu"]
    assert [p.name for p in sideways.policies] == ["mimic_walk", "mimic_imu", "mimic_general", "mimic_walk_back"]
    spec = json.loads(replace(sideways, sideways_speed_mps=1.5).save().read_text())
    assert spec["sideways_speed_mps"] == 1.5 and not Path(spec["sideways"]).is_absolute()
    loaded = load_policy_set(tmp_path / "set")
    assert loaded.sideways.resolve() == (MODELS / "mimic_walk_back").resolve() and loaded.sideways_speed_mps == 1.5
    assert loaded.route(left).name == "mimic_walk" and loaded.fast.resolve() == (MODELS / "mimic_general").resolve()
    with pytest.raises(PolicyError, match="sideways_speed_mps must be a finite number >= 0"):
        PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu", sideways_speed_mps=float("nan"))
    del spec["sideways"]
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="sideways_speed_mps is given without sideways"):
        load_policy_set(tmp_path / "set")
    for bad in (["../x"], None):
        spec["sideways"] = bad
        (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
        with pytest.raises(PolicyError, match="sideways must be a policy directory"):
            load_policy_set(tmp_path / "set")


def test_a_set_can_slow_one_members_denoiser_corrections(tmp_path):
    """``denoise_slow_s`` round-trips; the member it names tracks behind the denoiser's corrections slowed to its
    seconds, replacing the command line's slowing, every other member behind the denoiser as given, no denoiser
    stays none; a role the set has no policy for, bad seconds, or one member slowed two ways is a clear error."""
    from agents.policy import load_policy
    from agents.policy_set import member_denoiser, slowed_members
    from perception.imu_denoiser import SlowCorrections
    from perception.weights import load_network

    PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_walk", fast=MODELS / "mimic_imu",
              denoise_slow_s=(("fast", 0.5),)).save()
    assert json.loads((tmp_path / "set" / "policy_set.json").read_text())["denoise_slow_s"] == {"fast": 0.5}
    loaded = load_policy_set(tmp_path / "set")
    assert loaded.denoise_slow_s == (("fast", 0.5),)
    assert loaded.slowing(loaded.fast) == 0.5 and loaded.slowing(loaded.default) is None
    net = load_network(MODELS / "imu_denoiser_dm", "denoiser")
    fast, walker = (load_policy(p) for p in (loaded.fast, loaded.default))
    behind = member_denoiser(tmp_path / "set", fast, net)
    assert isinstance(behind, SlowCorrections) and behind.smooth_s == 0.5 and behind.denoiser is net
    assert member_denoiser(tmp_path / "set", fast, SlowCorrections(net, 2.0)).smooth_s == 0.5  # the set's wins
    assert member_denoiser(tmp_path / "set", walker, net) is net
    assert member_denoiser(tmp_path / "set", fast, None) is None
    assert member_denoiser(MODELS / "mimic_imu", fast, net) is net  # a plain policy: as the command line says
    assert slowed_members({"fast": behind, "walker": net}, net) == {"fast": 0.5}  # what results record
    assert slowed_members({"walker": net}, net) == {} and slowed_members({"fast": None}, None) == {}
    with pytest.raises(PolicyError, match="denoise_slow_s names 'dash', expected a role the set has a policy for: "
                                          "default, backward, fast"):
        PolicySet(tmp_path / "bad", MODELS / "mimic_walk", MODELS / "mimic_imu", fast=MODELS / "mimic_imu",
                  denoise_slow_s=(("dash", 0.5),))
    with pytest.raises(PolicyError, match="denoise_slow_s of fast must be a finite number of seconds > 0, got 0"):
        PolicySet(tmp_path / "bad", MODELS / "mimic_walk", MODELS / "mimic_imu", fast=MODELS / "mimic_imu",
                  denoise_slow_s=(("fast", 0),))
    with pytest.raises(PolicyError, match="plays several roles with different denoise_slow_s"):
        PolicySet(tmp_path / "bad", MODELS / "mimic_walk", MODELS / "mimic_imu", fast=MODELS / "mimic_imu",
                  denoise_slow_s=(("fast", 0.5),))  # mimic_imu is the backward policy too, unslowed
    denoiser = ["--denoise", str(MODELS / "imu_denoiser_dm")]
    as_set = evaluate.main(["--policy", str(tmp_path / "set"), "--clips", "deepmimic:run", "--episodes", "1", *denoiser])
    alone = evaluate.main(["--policy", str(MODELS / "mimic_imu"), "--clips", "deepmimic:run", "--episodes", "1",
                           *denoiser, "--denoise-slow", "0.5"])
    assert Path(as_set["routed_to"]["deepmimic:run"]).name == "mimic_imu"
    assert {Path(k).name: v for k, v in as_set["denoise_slow_s_of_members"].items()} == {"mimic_imu": 0.5}
    assert as_set["per_clip"] == alone["per_clip"]  # the set's fast member tracked the run as it does slowed alone
    whole = evaluate.main(["--policy", str(MODELS / "mimic_imu"), "--clips", "deepmimic:run", "--episodes", "1",
                           *denoiser])
    assert whole["per_clip"] != alone["per_clip"]  # ELR 0.093 behind the whole corrections, 0.100 slowed
    from agents import clean
    cleaned = clean.main(["deepmimic:run", "--policy", str(tmp_path / "set"), *denoiser, "--no-adapt", "--search", "off",
                          "--out", str(tmp_path / "run.npz")])
    assert {Path(k).name: v for k, v in cleaned["denoise_slow_s_of_members"].items()} == {"mimic_imu": 0.5}
    assert cleaned["denoise_slow_s"] is None  # the command line's, as evaluate.py records it
    from agents.distill import check_teacher_set
    with pytest.raises(PolicyError, match="slows some members' denoiser corrections its own way"):
        check_teacher_set(tmp_path / "set", MODELS / "imu_denoiser_dm")
    check_teacher_set(tmp_path / "set", None)  # without a denoiser the slowing changes nothing
    assert as_set["policy"].startswith(f"{tmp_path / 'set'} + its fast policy's denoiser corrections slowed to 0.5 s")
    spec = json.loads((tmp_path / "set" / "policy_set.json").read_text()) | {"denoise_slow_s": [0.5]}
    (tmp_path / "set" / "policy_set.json").write_text(json.dumps(spec))
    with pytest.raises(PolicyError, match="denoise_slow_s must be an object of roles to seconds"):
        load_policy_set(tmp_path / "set")
