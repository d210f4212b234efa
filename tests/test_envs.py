"""The registered mimic environments on real clips: API, layout, determinism, endings, errors."""

import math
import warnings
from dataclasses import replace

import gymnasium as gym
import mujoco
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import envs
from envs import ArtefactMix
from envs.bodies import read_body_state
from envs.config import MimicConfig, Pushes
from envs.preparation import prepared, preparation_of, preparation_record, prepares_any
from envs.reference import pd_targets
from reference_motion import rotations as rot
from perception.imu_denoiser import DEFAULT_DENOISER, denoise
from perception.weights import shared_network
from reference_motion.artefacts import HINGE_KINDS, ArtefactRecipe, corrupt
from reference_motion.cli import CliParser
from reference_motion.grounding import Grounding, add_grounding_option
from reference_motion.leg_gap import LegGap, add_leg_gap_option, lateral_foot_gap
from reference_motion.leg_symmetry import LegSymmetry, add_leg_symmetry_option, even_legs
from reference_motion.humanoid.model import load_model
from reference_motion.library import load_motion
from reference_motion.motion import Motion
from reference_motion.swing_lift import SwingLift, add_swing_lift_options

WALK = ["deepmimic:walk"]


@pytest.mark.parametrize("env_id, obs_dim, act_dim", [("MimicIMU-v0", 273, 20), ("MimicDReCon-v0", 105, 20),
                                                      ("MimicFullAction-v0", 296, 43)])
def test_env_checker_passes(env_id, obs_dim, act_dim):
    env = gym.make(env_id, clips=["deepmimic:walk", "deepmimic:walker/turn_left0"], render_mode="rgb_array",
                   width=160, height=120)
    assert env.observation_space.shape == (obs_dim,) and env.action_space.shape == (act_dim,)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*infinity.*")  # unbounded observations are intended
        check_env(env.unwrapped)
    env.close()


def test_two_segment_foot_observes_22_bodies():
    env = gym.make("MimicIMU-v0", clips=WALK, foot="two")
    assert env.observation_space.shape == (13 + 12 * 22 + 20,)
    obs, _ = env.reset(seed=0)
    _, _, _, _, info = env.step(np.zeros(20, np.float32))
    assert np.isfinite(obs).all() and 0.0 < info["reward"] <= 3.0


def test_observation_slices_at_reference_state_initialisation():
    env = gym.make("MimicIMU-v0", clips=WALK, artefacts=None)
    base = env.unwrapped
    obs, info = env.reset(seed=3, options={"start_frame": 40})
    s = base.obs_slices
    track = base.track(0)
    assert info["frame"] == 40 and not info["corrupted"]
    # the character starts in the reference state: differences vanish, reference terms are the track's
    assert np.abs(obs[s["dp"]]).max() < 1e-5 and np.abs(obs[s["dv"]]).max() < 1e-4
    assert np.allclose(obs[s["ref_v_com"]], track.com_vel[40], atol=1e-6)
    assert np.allclose(obs[s["dv_com"]], 0.0, atol=1e-4)
    assert np.allclose(obs[s["p"]].reshape(20, 3), base.data.xpos[1:] - base.data.subtree_com[1], atol=1e-6)
    assert np.array_equal(obs[s["prev_action"]], np.zeros(20))
    # the smoothed action shows up in the next observation: a_t = 0.2 a_raw
    action = np.linspace(-1, 1, 20).astype(np.float32)
    obs, *_ = env.step(action)
    assert np.allclose(obs[s["prev_action"]], 0.2 * action, atol=1e-6)


def test_the_lookahead_shows_the_reference_steps_ahead_clamped_to_the_last_frame():
    """kick (92 frames), reference axes, lookahead 1 and 30 control steps: at frame 10 the
    observation shows frames 12 and 70; at frame 40, 42 and the last frame (91, not 100)."""
    config = MimicConfig(obs_frame="reference", lookahead=[1, 30])  # a sidecar's list is accepted
    env = gym.make("MimicIMU-v0", clips=["deepmimic:kick"], artefacts=None, config=config)
    base, plain = env.unwrapped, gym.make("MimicIMU-v0", clips=["deepmimic:kick"], artefacts=None,
                                          config=MimicConfig(obs_frame="reference"))
    assert config.lookahead == (1, 30) and env.observation_space.shape == (273 + 2 * 66,)
    track = base.track(0)
    com = track.pos[:, 0] - track.pos_rel_com[:, 0]
    for start, ahead in ((10, (12, 70)), (40, (42, 91))):
        obs, _ = env.reset(seed=0, options={"start_frame": start})
        assert np.array_equal(obs[:273], plain.reset(seed=0, options={"start_frame": start})[0])
        turn = track.to_heading[start]
        for k, frame in enumerate(ahead):
            part = obs[base.obs_slices["lookahead"]].reshape(2, 66)[k]
            assert np.allclose(part[:3], turn @ (com[frame] - com[start]), atol=1e-5)
            assert np.allclose(part[3:6], turn @ track.com_vel[frame], atol=1e-5)
            assert np.allclose(part[6:].reshape(20, 3), track.pos_rel_com[frame] @ turn.T, atol=1e-5)
    for bad in ((0,), (4, 1), (2, 2), (True,)):
        with pytest.raises(ValueError, match="lookahead must be strictly increasing positive"):
            MimicConfig(lookahead=bad)
    with pytest.raises(ValueError, match=r"MimicGait-v0 previews .*MimicConfig.lookahead and lookbehind must be"):
        gym.make("MimicGait-v0", clips=WALK, config=MimicConfig(lookahead=(1,)))


def test_the_lookbehind_shows_the_reference_steps_back_clamped_to_the_first_frame():
    """kick, reference axes, lookahead 1 and lookbehind 1 and 10 control steps (2 frames each): at
    frame 30 the window shows frames 32, then 28 and 10; at frame 6, 8, then 4 and the first frame
    (0, not -14). The lookbehind follows the lookahead, laid out as it is."""
    config = MimicConfig(obs_frame="reference", lookahead=(1,), lookbehind=[1, 10])
    env = gym.make("MimicIMU-v0", clips=["deepmimic:kick"], artefacts=None, config=config)
    base = env.unwrapped
    assert config.window_steps == (1, -1, -10) and env.observation_space.shape == (273 + 3 * 66,)
    assert base.obs_slices["lookbehind"] == slice(273 + 66, 273 + 3 * 66)
    track = base.track(0)
    com = track.pos[:, 0] - track.pos_rel_com[:, 0]
    for start, window in ((30, (32, 28, 10)), (6, (8, 4, 0))):
        obs, _ = env.reset(seed=0, options={"start_frame": start})
        turn = track.to_heading[start]
        parts = obs[273:].reshape(3, 66)
        for part, frame in zip(parts, window):
            assert np.allclose(part[:3], turn @ (com[frame] - com[start]), atol=1e-5)
            assert np.allclose(part[3:6], turn @ track.com_vel[frame], atol=1e-5)
            assert np.allclose(part[6:].reshape(20, 3), track.pos_rel_com[frame] @ turn.T, atol=1e-5)
    for bad in ((0,), (3, 1), (-1,)):
        with pytest.raises(ValueError, match="lookbehind must be strictly increasing positive"):
            MimicConfig(lookbehind=bad)
    with pytest.raises(ValueError, match=r"MimicGait-v0 previews .*got \(\) and \(2,\)"):
        gym.make("MimicGait-v0", clips=WALK, config=MimicConfig(lookbehind=(2,)))


def test_first_step_tracks_the_reference_closely_and_reports_everything():
    env = gym.make("MimicIMU-v0", clips=WALK, artefacts=None)
    env.reset(seed=0, options={"start_frame": 0})
    _, reward, term, trunc, info = env.step(np.zeros(20, np.float32))
    for key in ("r_local", "r_p", "r_v", "e_discount", "reward", "contacts", "frame", "episode_frame", "clip",
                "corrupted", "unstable", "ended_by"):
        assert key in info, key
    assert info["frame"] == 2 and info["episode_frame"] == 2 and info["clip"] == "deepmimic:walk"
    assert info["e_discount"] > 0.99 and info["r_local"] > 0.9 and reward > 2.0
    assert not term and not trunc and info["ended_by"] == ""
    assert info["contacts"].shape == (4,) and info["contacts"].dtype == bool
    later = [env.step(np.zeros(20, np.float32))[4]["contacts"] for _ in range(3)]
    assert np.any(later)  # the heel strikes at frame 3–4


@pytest.mark.parametrize("foot", ["one", "two"])
def test_still_feet_term_is_the_skate_of_the_simulated_foot_points(foot):
    """r_still from the env's body states equals the one from MuJoCo's own site kinematics, and
    w_still weighs it into the reward and its maximum; with w_still = 0 the reward is ADAPT's."""
    config = MimicConfig(still_feet_weight=2.0)
    env = gym.make("MimicIMU-v0", clips=WALK, artefacts=None, foot=foot, config=config).unwrapped
    plain = gym.make("MimicIMU-v0", clips=WALK, artefacts=None, foot=foot).unwrapped
    assert env.max_step_reward == 5.0 and plain.max_step_reward == 3.0
    n_act = env.action_space.shape[0]
    for e in (env, plain):
        e.reset(seed=0, options={"start_frame": 0})
    rng = np.random.default_rng(0)
    sliding = []
    for _ in range(12):
        action = rng.uniform(-0.3, 0.3, n_act).astype(np.float32)
        _, reward, term, _, info = env.step(action)
        _, plain_reward, _, _, plain_info = plain.step(action)
        m, d = env.model, env.data
        speed = []
        for site in env.humanoid.foot_point_sites:
            vel = np.zeros(6)
            mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_SITE, site, vel, 0)
            near = d.site_xpos[site, 2] < config.still_feet_height_m
            speed.append(np.linalg.norm(vel[3:5]) if near else 0.0)
        sliding.append(sum(speed))
        assert info["r_still"] == pytest.approx(np.exp(-config.still_feet_alpha * sum(speed)), rel=1e-6, abs=1e-9)
        assert reward == pytest.approx(info["e_discount"] * (info["r_local"] + info["r_p"] + info["r_v"]
                                                              + 2.0 * info["r_still"]))
        assert plain_reward == pytest.approx(plain_info["e_discount"] * (plain_info["r_local"] + plain_info["r_p"]
                                                                          + plain_info["r_v"]))
        assert term is False
    assert max(sliding) > 0.05  # the random actions did move feet on the floor


def test_still_feet_settings_are_checked_and_the_gait_task_refuses_the_term():
    for bad in (dict(still_feet_weight=-1.0), dict(still_feet_weight=math.inf), dict(still_feet_alpha=0.0),
                dict(still_feet_alpha=math.nan), dict(still_feet_height_m=0.0)):
        with pytest.raises(ValueError, match="still_feet_weight must be finite and >= 0"):
            MimicConfig(**bad)
    with pytest.raises(ValueError, match="MimicGait-v0 has ContactVision's own reward.*still_feet_weight and com_velocity_weight must be 0"):
        gym.make("MimicGait-v0", clips=WALK, config=MimicConfig(still_feet_weight=1.0))


def test_same_seed_same_trajectory_and_corrupted_variants():
    def rollout():
        env = gym.make("MimicIMU-v0", clips=["deepmimic:walk", "deepmimic:run"],
                       artefacts=ArtefactMix(fraction=0.5, variants_per_clip=2))
        env.action_space.seed(5)
        obs, info = env.reset(seed=11)
        out, seeds = [obs], [info["artefact_seed"]]
        for _ in range(60):
            obs, r, term, trunc, info = env.step(env.action_space.sample())
            out.append(np.append(obs, r))
            if term or trunc:
                obs, info = env.reset()
                seeds.append(info["artefact_seed"])
        return np.concatenate(out), seeds

    a, seeds_a = rollout()
    b, seeds_b = rollout()
    assert np.array_equal(a, b) and seeds_a == seeds_b
    assert len(seeds_a) > 2 and any(s is not None for s in seeds_a)  # episodes ended and some were corrupted


def test_episode_is_truncated_at_episode_frames():
    env = gym.make("MimicIMU-v0", clips=WALK, episode_frames=6)
    env.reset(seed=0, options={"start_frame": 10})
    results = [env.step(np.zeros(20, np.float32)) for _ in range(3)]
    assert [r[3] for r in results] == [False, False, True]
    assert results[-1][4]["ended_by"] == "time_limit" and results[-1][4]["frame"] == 16


def test_open_loop_walk_falls_behind_and_ends_by_lagging():
    env = gym.make("MimicIMU-v0", clips=WALK)
    env.reset(seed=0, options={"start_frame": 0})
    for steps in range(1, 151):
        _, _, term, trunc, info = env.step(np.zeros(20, np.float32))
        if term or trunc:
            break
    assert term and info["ended_by"] == "lagging" and info["e_discount"] < 0.025
    assert 10 <= steps < 150  # the PD controllers alone keep it up a while, not a whole episode


def test_random_pushes_shove_the_pelvis_for_their_duration_and_change_its_velocity():
    pushes = Pushes(force_n=(200.0, 200.0), duration_s=0.1, rate_hz=30.0)  # one push right away, 3 steps long
    env = gym.make("MimicIMU-v0", clips=WALK, pushes=pushes, artefacts=None).unwrapped
    still = gym.make("MimicIMU-v0", clips=WALK, artefacts=None).unwrapped
    for e in (env, still):
        e.reset(seed=0, options={"start_frame": 0})
    forces = []
    for _ in range(3):
        env.step(np.zeros(20, np.float32))
        still.step(np.zeros(20, np.float32))
        forces.append(env.data.xfrc_applied[env._pelvis].copy())
    np.testing.assert_allclose([np.linalg.norm(f) for f in forces], 200.0)  # held 0.1 s = 3 control steps
    assert all(f[2] == 0.0 and not f[3:].any() and np.array_equal(f, forces[0]) for f in forces)  # horizontal, one way
    # 200 N on 70 kg for 0.1 s: ~0.29 m/s along the push (the feet's friction takes some of it)
    gained = (env.data.subtree_linvel[1] - still.data.subtree_linvel[1]) @ (forces[0][:3] / 200.0)
    assert 0.1 < gained < 0.35
    env.step(np.zeros(20, np.float32))  # the next push (rate 30 Hz: at once), another way
    assert np.linalg.norm(env.data.xfrc_applied[env._pelvis]) == pytest.approx(200.0)
    assert not np.array_equal(env.data.xfrc_applied[env._pelvis], forces[0])
    env.reset(seed=0, options={"start_frame": 0})
    assert not env.data.xfrc_applied.any()  # a reset ends any push
    with pytest.raises(ValueError, match=r"Pushes.force_n must be \(low, high\)"):
        Pushes(force_n=(100.0, 50.0))
    with pytest.raises(TypeError, match="pushes must be an envs.config.Pushes"):
        gym.make("MimicIMU-v0", clips=WALK, pushes={"force_n": (1, 2)})


def test_pd_targets_lead_a_moving_reference_by_kv_over_kp():
    angles, rates = np.array([0.5, -0.2, 0.0]), np.array([2.0, 0.0, -1.0])
    assert pd_targets(angles, rates, None) is angles
    lead = np.array([0.1, 0.1, 0.05])
    np.testing.assert_allclose(pd_targets(angles, rates, lead), [0.7, -0.2, -0.05])
    # the MuJoCo position actuator's force kp·(ctrl − q) − kv·q̇ is then PD on angle and velocity
    kp, kv, q, qdot = 300.0, 30.0, 0.4, 1.5
    ctrl = pd_targets(np.array([0.5]), np.array([2.0]), np.array([kv / kp]))[0]
    assert kp * (ctrl - q) - kv * qdot == pytest.approx(kp * (0.5 - q) + kv * (2.0 - qdot))


def test_velocity_feedforward_cuts_the_open_loop_tracking_error():
    errors = {}
    for feedforward in (False, True):
        env = gym.make("MimicIMU-v0", clips=WALK, config=MimicConfig(velocity_feedforward=feedforward))
        u = env.unwrapped
        assert (u.pd_lead_s is not None) == feedforward
        per_start = []
        for start in range(0, 60, 12):
            env.reset(seed=0, options={"start_frame": start})
            for _ in range(15):  # 0.5 s with zero actions: the PD controllers alone
                env.step(np.zeros(20, np.float32))
                per_start.append(np.sqrt(np.mean((u.data.qpos[u.actuator_qpos] - u.current_track.ctrl[u._frame]) ** 2)))
        errors[feedforward] = np.degrees(np.mean(per_start))
    # measured: 5.6 deg with ADAPT's PD (the body trails the reference), 3.1 deg with the lead
    assert errors[True] < 0.65 * errors[False]
    assert 4.0 < errors[False] < 8.0


def test_three_spinal_contacts_end_the_episode():
    hm = load_model("humanoid_1seg")
    q = hm.rest_qpos()
    q[3:7] = rot.from_axis_angle(np.array([0.0, 1.0, 0.0]), np.pi / 2)  # face down
    q[2] = 0.12
    q[[hm.qpos_index("neck_y"), hm.qpos_index("head_y")]] = 0.3
    q[[hm.qpos_index(j) for j in ("spine_lower_y", "spine_mid_y", "chest_y")]] = -0.2
    lying = Motion("lying", 60.0, np.tile(q, (320, 1)), "humanoid_1seg")
    env = gym.make("MimicIMU-v0", clips=[lying])
    env.reset(seed=0)
    for _ in range(20):
        _, _, term, _, info = env.step(np.zeros(20, np.float32))
        if term:
            break
    assert term and info["ended_by"] == "fallen" and info["e_discount"] > 0.5  # not lagging: it mimics well


def test_blown_up_simulation_ends_cleanly():
    env = gym.make("MimicIMU-v0", clips=WALK)
    obs0, _ = env.reset(seed=0)
    env.unwrapped.data.qvel[20] = 1e7
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        obs, reward, term, trunc, info = env.step(np.zeros(20, np.float32))
    assert term and not trunc and info["unstable"] and info["ended_by"] == "unstable" and reward == 0.0
    assert np.isfinite(obs).all()
    obs, info = env.reset()
    assert np.isfinite(obs).all() and not info["unstable"]


def test_reference_tracks_are_precomputed_once():
    env = gym.make("MimicIMU-v0", clips=WALK).unwrapped
    env.reset(seed=0)
    assert env.track(0) is env.track(0)
    track = env.track(0)
    assert track.faces_rel_root.shape == (track.n_frames, 20, 6, 3)
    assert track.face_vel.shape == track.faces_rel_root.shape and track.local.shape[1:] == (18, 4)


def test_environments_with_a_fixed_variant_seed_share_their_tracks():
    """ArtefactMix(seed=...): every env makes the same corrupted variants, and the envs of one
    process build each track once (one copy); without it each env has its own variants."""
    mix = ArtefactMix(fraction=1.0, variants_per_clip=2, seed=7)
    a, b = (gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=mix).unwrapped for _ in range(2))
    a.reset(seed=0)
    b.reset(seed=1)
    assert a.track(0, 1) is b.track(0, 1) and a.track(0, -1) is b.track(0, -1)
    assert not np.allclose(a.track(0, 0).motion.qpos, a.track(0, 1).motion.qpos)
    own = ArtefactMix(fraction=1.0, variants_per_clip=2)
    c, d = (gym.make("MimicIMU-v0", clips=["deepmimic:walk"], artefacts=own).unwrapped for _ in range(2))
    c.reset(seed=0)
    d.reset(seed=1)
    assert not np.allclose(c.track(0, 1).motion.qpos, d.track(0, 1).motion.qpos)


def test_render_shows_the_reference_beside_the_character():
    env = gym.make("MimicIMU-v0", clips=WALK, render_mode="rgb_array", width=200, height=150)
    env.reset(seed=0)
    env.step(np.zeros(20, np.float32))
    img = env.render()
    assert img.shape == (150, 200, 3) and img.dtype == np.uint8
    orange = (img[..., 0] > 150) & (img[..., 0] > img[..., 2] + 60)  # the translucent reference
    grey = (np.abs(img[..., 0].astype(int) - img[..., 2]) < 20) & (img[..., 1] > 90)
    assert orange.sum() > 200 and grey.sum() > 200
    env.close()


def test_bad_arguments_raise_clear_errors():
    with pytest.raises(ValueError, match="foot must be one of"):
        gym.make("MimicIMU-v0", clips=WALK, foot="three")
    with pytest.raises(ValueError, match="obs_mode"):
        gym.make("MimicIMU-v0", clips=WALK, obs_mode="pixels")
    with pytest.raises(ValueError, match="action_mode"):
        gym.make("MimicIMU-v0", clips=WALK, action_mode="all")
    with pytest.raises(ValueError, match="clips is empty"):
        gym.make("MimicIMU-v0", clips=[])
    with pytest.raises(KeyError, match="unknown clip set"):
        gym.make("MimicIMU-v0", clips="walking")
    walk = load_motion("deepmimic:walk")
    with pytest.raises(ValueError, match=r"has 20 frames at 60 Hz, fewer than 31 \(min_clip_frames 30 \+ 1\)"):
        gym.make("MimicIMU-v0", clips=[walk.with_qpos(walk.qpos[:20], loop=False)])
    two = load_motion("deepmimic:walk", "humanoid_2seg")
    with pytest.raises(ValueError, match="Motion for humanoid_2seg"):
        gym.make("MimicIMU-v0", clips=[two])
    with pytest.raises(TypeError, match="ArtefactMix"):
        gym.make("MimicIMU-v0", clips=WALK, artefacts="imu")
    with pytest.raises(ValueError, match="fraction"):
        ArtefactMix(fraction=1.5)
    env = gym.make("MimicIMU-v0", clips=WALK, artefacts=None)
    with pytest.raises(ValueError, match="unknown clip 'deepmimic:run'"):
        env.reset(options={"clip": "deepmimic:run"})
    with pytest.raises(ValueError, match="unknown reset option"):
        env.reset(options={"speed": 2})
    with pytest.raises(ValueError, match="needs an env made with artefacts"):
        env.reset(options={"corrupted": True})
    with pytest.raises(ValueError, match="start_frame 9999 out of range"):
        env.reset(options={"start_frame": 9999})


def test_all_ids_registered():
    assert set(envs.ENV_IDS) <= set(gym.registry)


def test_a_clip_shorter_than_an_episode_plays_to_its_end():
    """kick is 92 frames, shorter than an episode (300): episodes start in its first half and are
    truncated at the last frame whole control steps reach, whatever the start's parity."""
    env = gym.make("MimicIMU-v0", clips=["deepmimic:kick"])
    base = env.unwrapped
    assert base.clips[0].n_frames == 92 and base.last_start(0) == 45
    for start in (0, 1, 45):
        env.reset(options={"start_frame": start})
        assert base.episode_end == start + 2 * ((91 - start) // 2)
        while True:
            _, _, term, trunc, info = env.step(np.zeros(env.action_space.shape, np.float32))
            if term or trunc:
                break
        assert info["frame"] <= 91 and (term or info["frame"] == base.episode_end)
    with pytest.raises(ValueError, match=r"start_frame 46 out of range .*0\.\.45"):
        env.reset(options={"start_frame": 46})


def test_floor_contacts_of_several_simulations_at_once_match_each_alone():
    """envs.bodies' contact helpers on a hand-made case: geom 0 is the floor; geoms 1-2 are sole
    spheres of channels 0 and 3, geom 3 belongs to spinal body 7, geom 4 to body 8, geom 5 to none."""
    from envs.bodies import bodies_touching, geoms_touching, region_contacts
    channel = np.array([-1, 0, 3, -1, -1, -1])
    body = np.array([-1, -1, -1, 7, 8, -1])
    sims = [np.array([[0, 1], [2, 0], [3, 4]]),  # two soles down; 3-4 touch each other, not the floor
            np.array([[3, 0], [0, 4], [0, 3], [0, 5]]),  # two spinal bodies (3 twice), one geom of none
            np.empty((0, 2), int)]  # no contact at all
    touching = [geoms_touching(p, 0) for p in sims]
    np.testing.assert_array_equal(touching[0], [1, 2])
    np.testing.assert_array_equal(touching[1], [3, 4, 3, 5])
    owner = np.repeat(np.arange(3), [len(p) for p in sims])
    all_touching, all_owner = geoms_touching(np.concatenate(sims), 0, owner)
    np.testing.assert_array_equal(all_owner, [0, 0, 1, 1, 1, 1])
    expected_regions = [[True, False, False, True], [False] * 4, [False] * 4]
    np.testing.assert_array_equal(region_contacts(all_touching, channel, all_owner, 3), expected_regions)
    for i in range(3):
        np.testing.assert_array_equal(region_contacts(touching[i], channel), expected_regions[i])
    np.testing.assert_array_equal(bodies_touching(all_touching, body, all_owner, 3), [0, 2, 0])
    assert [bodies_touching(t, body) for t in touching] == [0, 2, 0]


def test_a_corrupted_episode_can_be_judged_against_the_clean_clip(walk):
    """ArtefactMix.judge="clean": the policy observes the corrupted reference and its PD targets follow
    it, but the reward (and so the lag termination) compares the simulation with the clean clip."""
    mix = ArtefactMix(strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5, judge="clean")
    judged = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    adapt = gym.make("MimicIMU-v0", clips=[walk], artefacts=ArtefactMix(strength=(1.0, 1.0), fraction=1.0,
                                                                        variants_per_clip=1, seed=5)).unwrapped
    obs_j, info_j = judged.reset(options={"clip": 0, "start_frame": 0})
    obs_a, info_a = adapt.reset(options={"clip": 0, "start_frame": 0})
    assert info_j["corrupted"] and info_a["corrupted"]
    np.testing.assert_array_equal(obs_j, obs_a)  # the same corrupted reference is observed ...
    assert judged.judging_track is judged.track(0, -1) and judged.current_track is judged.track(0, 0)
    assert sorted(judged._plans) == [(0, -1, False, ()), (0, 0, False, ())]  # nothing prepared: one slot each
    assert adapt.judging_track is adapt.current_track
    action = np.zeros(adapt.action_space.shape)
    for _ in range(10):
        obs_j, r_j, *_ = judged.step(action)
        obs_a, r_a, *_ = adapt.step(action)
    np.testing.assert_array_equal(obs_j, obs_a)  # ... and followed, so the simulations are the same
    clean_terms = judged._tracking_terms(read_body_state(judged.model, judged.data), walk_frame(judged))
    assert r_j == pytest.approx(clean_terms.total) and abs(r_j - r_a) > 1e-3  # only the reward differs
    with pytest.raises(ValueError, match="judge must be one of"):
        ArtefactMix(judge="oracle")


def test_corrupted_variants_can_pass_through_the_imu_denoiser(walk):
    """ArtefactMix.denoiser: each corrupted variant is the denoised corruption, built once."""
    mix = ArtefactMix(strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5)
    plain = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    denoised = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, denoiser=str(DEFAULT_DENOISER))).unwrapped
    for env in (plain, denoised):
        env.reset(options={"clip": 0, "start_frame": 0})
    corrupted = plain.current_track.motion
    expected = denoise(shared_network(str(DEFAULT_DENOISER), "denoiser"), corrupted)
    np.testing.assert_allclose(denoised.current_track.motion.qpos, expected.qpos)
    assert not np.allclose(expected.qpos, corrupted.qpos)
    assert denoised.track(0, 0) is denoised.current_track  # cached, not denoised again


def test_training_references_can_be_prepared_as_evaluation_prepares_takes(walk):
    """ArtefactMix.grounding/lift with judge="given": every episode tracks its reference as
    envs.preparation.prepared makes it (a corrupted variant set on the floor; a clean clip too) and is
    judged against the reference as made, as evaluate.py --ground judges a take."""
    grounding = Grounding()
    mix = ArtefactMix(strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5, grounding=grounding,
                      judge="given")
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    plain = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, grounding=None, judge="corrupted")).unwrapped
    for corrupted in (True, False):
        for e in (env, plain):
            e.reset(options={"clip": 0, "start_frame": 0, "corrupted": corrupted})
        as_made = plain.current_track.motion
        np.testing.assert_array_equal(env.judging_track.motion.qpos, as_made.qpos)
        np.testing.assert_allclose(env.current_track.motion.qpos, prepared(as_made, grounding=grounding).qpos)
        lowered = as_made.qpos[:, 2] - env.current_track.motion.qpos[:, 2]
        assert np.abs(lowered).max() > (0.01 if corrupted else 1e-4)  # the variant's height offset is taken out
        np.testing.assert_array_equal(env.current_track.motion.qpos[:, 3:], as_made.qpos[:, 3:])
    clean_judge = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, judge="clean")).unwrapped
    clean_judge.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    np.testing.assert_array_equal(clean_judge.judging_track.motion.qpos, walk.qpos[:clean_judge.judging_track.n_frames])
    tracking = replace(mix, judge="corrupted")
    same = gym.make("MimicIMU-v0", clips=[walk], artefacts=tracking).unwrapped
    same.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    assert same.judging_track is same.current_track  # "corrupted": judged against what it tracks
    assert ArtefactMix(lift=SwingLift()).prepares(False) and not ArtefactMix(denoiser="d").prepares(False)


def test_the_command_line_asks_for_the_preparation_steps_that_a_mix_and_a_record_carry():
    """preparation_of reads --even-legs, --part-legs, --ground and --swing-lift into the keyword
    arguments of prepared() and ArtefactMix; preparation_record writes them as the --json outputs do."""
    parser = CliParser()
    for add in (add_leg_symmetry_option, add_leg_gap_option, add_grounding_option, add_swing_lift_options):
        add(parser, "for a test")
    none = preparation_of(parser.parse_args([]))
    assert none == {"symmetry": None, "legs": None, "grounding": None, "lift": None} and not prepares_any(none)
    assert preparation_record(none) == {"leg_symmetry": None, "legs": None, "grounding": None, "swing_lift": None}
    some = preparation_of(parser.parse_args(["--part-legs", "0.2", "--swing-lift"]))
    assert some == {"symmetry": None, "legs": LegGap(min_gap_m=0.2), "grounding": None, "lift": SwingLift()}
    assert prepares_any(some) and ArtefactMix(**some).steps == some and ArtefactMix(**some).prepares(False)
    record = preparation_record(some, lift_key="lift")
    assert record["legs"]["min_gap_m"] == 0.2 and record["lift"]["knee_deg"] == SwingLift.knee_deg
    assert record["leg_symmetry"] is None and record["grounding"] is None and "swing_lift" not in record


def test_training_references_can_have_their_legs_parted(walk):
    """ArtefactMix.legs: a corrupted variant whose feet cross (the suit's hip adduction) is tracked
    with its legs parted to the gap, before it is set on the floor, and judged as given."""
    mix = ArtefactMix(recipe=ArtefactRecipe.named("adduction"), strength=(1.0, 1.0), fraction=1.0,
                      variants_per_clip=1, seed=5, legs=LegGap(), grounding=Grounding(), judge="given")
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    env.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    as_made, tracked = env.judging_track.motion, env.current_track.motion
    assert np.median(lateral_foot_gap(walk.model, as_made.qpos)) < 0.0  # crossed as made
    assert np.median(lateral_foot_gap(walk.model, tracked.qpos)) == pytest.approx(LegGap().min_gap_m, abs=0.003)
    np.testing.assert_allclose(tracked.qpos, prepared(as_made, legs=LegGap(), grounding=Grounding()).qpos)
    assert replace(mix, grounding=None, judge="corrupted").prepares(True)  # the legs alone prepare it


def test_training_references_can_pass_behind_the_denoisers_slow_corrections(walk):
    """ArtefactMix.denoise_slow_s: a corrupted variant is tracked behind the denoiser's slowed
    corrections (perception.imu_denoiser.SlowCorrections), another track than behind its whole ones."""
    from perception.imu_denoiser import DEFAULT_DENOISER, SlowCorrections
    from perception.weights import shared_network
    mix = ArtefactMix(recipe=ArtefactRecipe.imu(), strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5,
                      denoiser=str(DEFAULT_DENOISER), denoise_slow_s=0.5, judge="given")
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    env.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    as_made, tracked = env.judging_track.motion, env.current_track.motion
    slow = SlowCorrections(shared_network(str(DEFAULT_DENOISER), "denoiser"), 0.5)
    np.testing.assert_allclose(tracked.qpos, prepared(as_made, slow).qpos)
    np.testing.assert_array_equal(tracked.qpos[:, :7], as_made.qpos[:, :7])  # the height correction dropped
    whole = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, denoise_slow_s=None)).unwrapped
    whole.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    assert not np.allclose(whole.current_track.motion.qpos, tracked.qpos)


def test_training_references_can_have_their_legs_evened(walk):
    """ArtefactMix.symmetry: a corrupted variant is tracked with its legs evened, then parted, and
    the track is built once per preparation (the settings are part of the shared track's key)."""
    mix = ArtefactMix(recipe=ArtefactRecipe.imu(), strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5,
                      symmetry=LegSymmetry(), legs=LegGap(), judge="given")
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    env.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    as_made, tracked = env.judging_track.motion, env.current_track.motion
    np.testing.assert_allclose(tracked.qpos, prepared(as_made, symmetry=LegSymmetry(), legs=LegGap()).qpos)
    assert tracked.source["leg_corrections_rad"] == even_legs(as_made).source["leg_corrections_rad"]
    assert replace(mix, legs=None, judge="corrupted").prepares(True)  # the evening alone prepares it
    weaker = replace(mix, symmetry=LegSymmetry(suit_offset_deg=1.0))
    other = gym.make("MimicIMU-v0", clips=[walk], artefacts=weaker).unwrapped
    other.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    assert not np.allclose(other.current_track.motion.qpos, tracked.qpos)  # another setting: another track


def test_clean_pose_judges_a_corrupted_episode_against_its_root_path_with_the_clean_hinge_angles(walk):
    """ArtefactMix.judge="clean_pose": a corrupted episode tracks its variant (set on the floor here)
    but is judged against the variant as made without its hinge errors: the same root path (heading,
    root drift, skate and height), the clean clip's hinge angles (no adduction crossing the legs); a
    clean episode against the clip as given."""
    mix = ArtefactMix(strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5, grounding=Grounding(),
                      judge="clean_pose")
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    as_made = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, grounding=None, judge="corrupted")).unwrapped
    for e in (env, as_made):
        e.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    variant, judged = as_made.current_track.motion.qpos, env.judging_track.motion.qpos
    np.testing.assert_array_equal(judged[:, :7], variant[:, :7])
    np.testing.assert_array_equal(judged[:, 7:], walk.qpos[:len(judged), 7:])
    assert np.abs(variant[:, 7:] - walk.qpos[:len(variant), 7:]).max() > 0.1  # the hinge errors it is spared
    assert env.judging_track is env.track(0, 0, as_given=True, without=HINGE_KINDS)
    assert env.judging_track is env.track(0, 0, as_given=True, without=HINGE_KINDS[::-1])  # one slot, any order
    assert env.current_track is env.track(0, 0)  # it tracks the variant, set on the floor
    env.reset(options={"clip": 0, "start_frame": 0, "corrupted": False})
    np.testing.assert_array_equal(env.judging_track.motion.qpos, walk.qpos[:env.judging_track.n_frames])
    unprepared = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, grounding=None, seed=None)).unwrapped
    unprepared.reset(seed=3, options={"clip": 0, "start_frame": 0, "corrupted": True})
    assert unprepared.judging_track is not unprepared.current_track  # nothing prepared, yet another track
    assert sorted(unprepared._plans) == [(0, 0, False, ()), (0, 0, False, tuple(sorted(HINGE_KINDS)))]
    np.testing.assert_array_equal(unprepared.judging_track.motion.qpos[:, 7:], walk.qpos[:len(judged), 7:])
    unprepared.reset(seed=11, options={"clip": 0, "start_frame": 0, "corrupted": False})
    assert sorted(unprepared._plans) == [(0, -1, False, ())]  # a new seed forgets every variant drawn with the old one


def test_unslid_pose_judges_a_corrupted_episode_against_its_root_path_without_the_stance_skate(walk):
    """ArtefactMix.judge="unslid_pose": as "clean_pose", and the judged root path is the variant's without
    its stance skate: its heading, root drift and height drawn from the same streams, the clean hinge angles."""
    mix = ArtefactMix(strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=5, judge="unslid_pose")
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=mix).unwrapped
    env.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    unslid = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(
        mix, recipe=mix.recipe.without(("skate",)), judge="corrupted")).unwrapped
    unslid.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    variant, judged = env.current_track.motion.qpos, env.judging_track.motion.qpos
    np.testing.assert_array_equal(judged[:, :7], unslid.current_track.motion.qpos[:len(judged), :7])
    np.testing.assert_array_equal(judged[:, 7:], walk.qpos[:len(judged), 7:])
    slide = np.linalg.norm(variant[:, :2] - judged[:, :2], axis=1)
    assert 0.005 < slide.max() < 0.2  # the skate it is spared: centimetres, not the path
    assert env.judging_track is env.track(0, 0, as_given=True, without=(*HINGE_KINDS, "skate"))
    action = np.zeros(env.action_space.shape)
    reward = env.step(action)[1]
    followed = gym.make("MimicIMU-v0", clips=[walk], artefacts=replace(mix, judge="clean_pose")).unwrapped
    followed.reset(options={"clip": 0, "start_frame": 0, "corrupted": True})
    np.testing.assert_array_equal(followed.current_track.motion.qpos, variant)  # the same reference tracked ...
    assert followed.step(action)[1] != reward  # ... and paid against another path
    env.reset(options={"clip": 0, "start_frame": 0, "corrupted": False})
    np.testing.assert_array_equal(env.judging_track.motion.qpos, walk.qpos[:env.judging_track.n_frames])
    with pytest.raises(TypeError, match="not a string"):
        env.track(0, 0, without="skate")


def test_a_clip_can_be_judged_against_another_motion(walk):
    """judged_clips: the policy observes and follows the clip (a denoised take) while the reward
    compares the simulation with the motion it is judged against (the take as given)."""
    given = corrupt(walk, ArtefactRecipe.imu(1.0), 5)
    judged = gym.make("MimicIMU-v0", clips=[walk], artefacts=None, judged_clips=[given]).unwrapped
    plain = gym.make("MimicIMU-v0", clips=[walk], artefacts=None).unwrapped
    assert plain.reset(options={"clip": 0, "start_frame": 0})[1]["corrupted"] is False
    judged.reset(options={"clip": 0, "start_frame": 0})
    np.testing.assert_array_equal(judged.judging_track.motion.qpos, given.qpos)
    np.testing.assert_array_equal(judged.current_track.motion.qpos, walk.qpos)
    action = np.zeros(plain.action_space.shape)
    for _ in range(10):
        obs_j, r_j, *_ = judged.step(action)
        obs_p, r_p, *_ = plain.step(action)
    np.testing.assert_array_equal(obs_j, obs_p)  # same reference followed: the same simulation
    terms = judged._tracking_terms(read_body_state(judged.model, judged.data),
                                   judged.judging_track.frame(judged._frame))
    assert r_j == pytest.approx(terms.total) and abs(r_j - r_p) > 1e-3
    with pytest.raises(ValueError, match="judged_clips has 2 clips, clips has 1"):
        gym.make("MimicIMU-v0", clips=[walk], artefacts=None, judged_clips=[given, given])
    with pytest.raises(ValueError, match="judged clip .* has 60 frames, its clip"):
        gym.make("MimicIMU-v0", clips=[walk], artefacts=None, judged_clips=[given.with_qpos(given.qpos[:60])])
    with pytest.raises(ValueError, match="judged_clips and artefacts cannot be combined"):
        gym.make("MimicIMU-v0", clips=[walk], judged_clips=[given], artefacts=ArtefactMix())
    with pytest.raises(ValueError, match="on an env made with judged_clips"):
        plain.track(0, envs.mimic.JUDGED)
    with pytest.raises(ValueError, match="MimicGait-v0 takes no judged_clips"):
        gym.make("MimicGait-v0", clips=[walk], judged_clips=[given])


def walk_frame(env):
    """The clean clip's reference frame at the env's current frame."""
    return env.track(0, -1).frame(env._frame)
