"""MimicGait-v0 (ContactVision's reconstruction task) on real clips: registration, API, reward sum,
contact and toe targets, observation layout, errors."""

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import envs
from envs import GaitConfig, MimicGaitEnv
from envs.rewards import GAIT_TERMS
from perception.gait import toe_reference_angles
from reference_motion.library import load_motion

ZERO = np.zeros(22, np.float32)


@pytest.fixture(scope="module")
def walk2():
    """DeepMimic walk on humanoid_2seg at 60 Hz as it is (76 frames)."""
    return load_motion("deepmimic:walk", "humanoid_2seg")


@pytest.fixture(scope="module")
def vgrf_env():
    """MimicGait-v0 on deepmimic:walk with the default contacts (VGRFNet + Γ), built once."""
    return gym.make("MimicGait-v0", clips=["deepmimic:walk"], render_mode="rgb_array", width=160, height=120)


def _make(motion, contacts, **kwargs):
    return gym.make("MimicGait-v0", clips=[motion], contacts=contacts, **kwargs)


def test_registered_and_env_checker_passes(vgrf_env):
    assert "MimicGait-v0" in envs.ENV_IDS and set(envs.ENV_IDS) <= set(gym.registry)
    base = vgrf_env.unwrapped
    assert isinstance(base, MimicGaitEnv) and base.humanoid.name == "humanoid_2seg"
    # 22 bodies: 13 + 12·22 + 22 (adapt layout) + 4·4 + 2·4 (4 frames of targets) + 4 (contacts)
    assert vgrf_env.observation_space.shape == (13 + 12 * 22 + 22 + 24 + 4,) == (327,)
    assert vgrf_env.action_space.shape == (22,)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*infinity.*")  # unbounded observations are intended
        check_env(base)
    vgrf_env.reset(seed=0)
    assert vgrf_env.render().shape == (120, 160, 3)


def test_action_drives_the_key_joints_and_both_toes(vgrf_env):
    base = vgrf_env.unwrapped
    driven = [base.humanoid.hinge_names[q - 7] for q in base.actuator_qpos[base.driven]]
    assert driven[-2:] == ["l_toe_y", "r_toe_y"] and len(driven) == 22
    assert {j.split("_")[1] for j in driven[:20]} == {"upper", "thigh", "shin", "foot"}


def test_vgrf_contacts_of_walk_have_a_plausible_duty_factor(vgrf_env):
    contacts = vgrf_env.unwrapped.contact_targets[0]
    assert contacts.dtype == bool and contacts.shape == (vgrf_env.unwrapped.clips[0].n_frames, 4)
    left, right = contacts[:, [0, 2]].any(axis=1), contacts[:, [1, 3]].any(axis=1)
    for foot in (left, right):
        assert 0.4 <= foot.mean() <= 0.8   # walking: each foot on the ground ~60% of the cycle
    assert (left | right).all()            # walking, not running: never both feet in the air
    assert all(0.2 < contacts[:, c].mean() < 0.8 for c in range(4))   # every channel switches


def test_toe_targets_follow_the_toe_ref_estimator(vgrf_env):
    base = vgrf_env.unwrapped
    contacts, toe = base.contact_targets[0], base.toe_targets[0]
    assert np.array_equal(toe, toe_reference_angles(contacts))
    assert toe.max() == pytest.approx(math.radians(42.0))   # full push-offs: heel-off ≥ 5 frames before toe-off
    # the gait reference is the clip with the toe targets added to its toe hinges (0 in DeepMimic clips)
    clip = load_motion("deepmimic:walk", "humanoid_2seg", min_frames=602)
    toe_columns = [base.humanoid.qpos_index("l_toe_y"), base.humanoid.qpos_index("r_toe_y")]
    assert np.allclose(base.clips[0].qpos[:, toe_columns], clip.qpos[:, toe_columns] + toe)
    others = np.setdiff1d(np.arange(clip.qpos.shape[1]), toe_columns)
    assert np.array_equal(base.clips[0].qpos[:, others], clip.qpos[:, others])
    # ... so the toe hinges' PD targets are the toe targets, and info reports them
    obs, info = vgrf_env.reset(seed=1, options={"start_frame": 20})
    toe_actuators = [int(np.flatnonzero(base.actuator_qpos == q)[0]) for q in toe_columns]
    for _ in range(10):
        _, _, _, _, info = vgrf_env.step(ZERO)
        f = info["frame"]
        assert np.allclose(base.data.ctrl[toe_actuators], toe[f])   # zero action: the target itself
        assert np.array_equal(info["toe_targets"], toe[f]) and np.array_equal(info["contact_targets"], contacts[f])


def test_reward_is_the_weighted_sum_of_the_terms_in_info(vgrf_env):
    weights = GaitConfig().weights
    vgrf_env.reset(seed=2, options={"start_frame": 0})
    for _ in range(5):
        _, reward, _, _, info = vgrf_env.step(vgrf_env.action_space.sample())
        assert all(0.0 <= info[k] <= 1.0 for k in GAIT_TERMS)
        assert reward == info["reward"] == info["total"] == pytest.approx(sum(weights[k] * info[k] for k in GAIT_TERMS))
        assert info["contacts"].dtype == bool and info["contacts"].shape == (4,) and "e_discount" in info


def test_observation_carries_the_next_targets_and_the_contacts(vgrf_env):
    base = vgrf_env.unwrapped
    s = base.obs_slices
    obs, info = vgrf_env.reset(seed=0, options={"start_frame": 30})
    ahead = [31, 32, 33, 34]
    assert np.array_equal(obs[s["ref_contacts"]], base.contact_targets[0][ahead].ravel())
    assert np.allclose(obs[s["ref_toe"]], base.toe_targets[0][ahead].ravel())
    assert np.array_equal(obs[s["contacts"]], info["contacts"])
    obs, *_, info = vgrf_env.step(ZERO)
    assert np.array_equal(obs[s["ref_contacts"]].reshape(4, 4), base.contact_targets[0][[33, 34, 35, 36]])
    assert np.array_equal(obs[s["contacts"]], info["contacts"])


def test_array_contacts_are_used_as_given_and_r_fc_drops_on_disagreement(walk2):
    """Three target arrays that differ only at frame 2 (the first step's frame, where r_fc is read)
    and have no heel-off, so toe targets (all 0) and hence the simulation are the same."""
    def first_step(contacts):
        env = _make(walk2, contacts)
        env.reset(seed=0, options={"start_frame": 0})
        base = env.unwrapped
        assert np.array_equal(base.contact_targets[0], contacts.astype(bool)) and not base.toe_targets[0].any()
        return env.step(ZERO)

    none = np.zeros((walk2.n_frames, 4), bool)
    _, r_none, _, _, info_none = first_step(none)
    sim = info_none["contacts"]
    assert info_none["frame"] == 2 and sim.sum() == 2   # one foot's toe and the other's heel
    matching, opposite = none.copy(), none.copy()
    matching[2], opposite[2] = sim, ~sim
    _, r_match, _, _, info_match = first_step(matching.astype(int))   # 0/1 ints are accepted too
    _, r_opp, _, _, info_opp = first_step(opposite)
    assert np.array_equal(info_match["contacts"], sim) and np.array_equal(info_opp["contacts"], sim)
    assert info_match["r_fc"] == 1.0
    assert info_none["r_fc"] == pytest.approx(math.exp(-2.0))     # the 2 simulated contacts missed
    assert info_opp["r_fc"] == pytest.approx(math.exp(-4.0))      # all four channels wrong
    assert np.array_equal(info_opp["contact_targets"], ~sim)
    for key in GAIT_TERMS[:3] + GAIT_TERMS[4:]:                  # nothing else changes
        assert info_opp[key] == info_match[key] == info_none[key]
    assert r_match - r_opp == pytest.approx(0.3 * (1.0 - math.exp(-4.0)))


def test_keypoint_contacts_agree_with_vgrf_and_read_keypoint_files(vgrf_env, walk2, tmp_path):
    from perception.keypoints import follow_camera, motion_keypoints, observe
    from reference_motion.transforms import resample
    env = _make(walk2, "keypoints")
    from_vgrf = vgrf_env.unwrapped.contact_targets[0][:walk2.n_frames]   # the looped clip starts as walk2
    from_keypoints = env.unwrapped.contact_targets[0]
    assert (from_keypoints == from_vgrf).mean() > 0.85
    # a keypoint file as the video front end writes it: 30 Hz, pixel noise
    video = resample(walk2, 30.0)
    points = motion_keypoints(video)
    keypoints = observe(points, follow_camera(points[:, 0], math.pi / 2), np.random.default_rng(3), noise_px=1.0)
    np.savez(tmp_path / "walk_kp.npz", keypoints=keypoints, fps=30.0)
    from_file = _make(walk2, tmp_path / "walk_kp.npz").unwrapped.contact_targets[0]
    assert from_file.shape == (walk2.n_frames, 4) and (from_file == from_keypoints).mean() > 0.8
    np.savez(tmp_path / "short_kp.npz", keypoints=keypoints[:10], fps=30.0)
    with pytest.raises(ValueError, match=r"keypoints cover 0\.30 s .* lasts 1\.25 s"):
        _make(walk2, str(tmp_path / "short_kp.npz"))


def test_zero_action_rollout_stays_finite(walk2):
    env = _make(walk2, np.ones((walk2.n_frames, 4), bool), episode_frames=60)
    obs, info = env.reset(seed=4)
    assert np.isfinite(obs).all()
    for _ in range(30):
        obs, reward, term, trunc, info = env.step(ZERO)
        assert np.isfinite(obs).all() and 0.0 <= reward <= 1.0 and not info["unstable"]
        if term or trunc:
            break
    assert info["ended_by"] in ("", "lagging", "fallen", "time_limit")


def test_bad_arguments_raise_clear_errors(walk2):
    contacts = np.zeros((walk2.n_frames, 4), bool)
    with pytest.raises(ValueError, match="unknown contacts mode 'magic'; expected 'vgrf', 'keypoints'"):
        _make(walk2, "magic")
    with pytest.raises(ValueError, match=r"must have shape \(76, 4\).*got \(76, 2\)"):
        _make(walk2, contacts[:, :2])
    with pytest.raises(ValueError, match=r"must have shape \(76, 4\).*got \(75, 4\)"):
        _make(walk2, contacts[1:])
    with pytest.raises(ValueError, match="must be bool or 0/1"):
        _make(walk2, np.full((walk2.n_frames, 4), 0.5))
    with pytest.raises(ValueError, match="foot must be 'two' .* or 'one'"):
        _make(walk2, contacts, foot="three")
    with pytest.raises(ValueError, match="a list of 2, but the env has 1 clips"):
        _make(walk2, [contacts, contacts])
    with pytest.raises(ValueError, match="fits one clip, but the env has 2 clips"):
        gym.make("MimicGait-v0", clips=[walk2, walk2], contacts=contacts)
    with pytest.raises(ValueError, match="no such keypoint file"):
        _make(walk2, "missing_kp.npz")
    with pytest.raises(TypeError, match="GaitConfig"):
        _make(walk2, contacts, gait={"w_fc": 1.0})
    with pytest.raises(ValueError, match="end_effectors"):
        _make(walk2, contacts, gait=GaitConfig(end_effectors=("l_hand", "tail")))
    with pytest.raises(ValueError, match="action_mode 'key_toes' .* only foot='two'"):
        gym.make("MimicIMU-v0", clips=["deepmimic:walk"], action_mode="key_toes")


def test_ablations_one_segment_foot_and_toes_held_straight(walk2):
    """ContactVision Fig. 12's ablations: the one-segment foot (no toe hinges: 20-D key action, toe
    targets 0) and the ToeRefEstimator off (toe targets 0, the toes' reference angle unchanged)."""
    walk1 = load_motion("deepmimic:walk", "humanoid_1seg")
    contacts = np.zeros((walk1.n_frames, 4), bool)
    one = gym.make("MimicGait-v0", clips=[walk1], contacts=contacts, foot="one")
    assert one.action_space.shape == (20,) and one.unwrapped.humanoid.name == "humanoid_1seg"
    _, info = one.reset(seed=0)
    assert np.array_equal(info["toe_targets"], [0.0, 0.0])
    _, _, _, _, info = one.step(np.zeros(20, np.float32))
    assert set(GAIT_TERMS) <= set(info) and 0.0 <= info["reward"] <= 1.0
    contacts2 = np.ones((walk2.n_frames, 4), bool)
    contacts2[30:40, 2] = False  # left heel-off at 30 with the toe down: the ToeRefEstimator bends the left toe
    with_ref = _make(walk2, contacts2)
    straight = _make(walk2, contacts2, gait=GaitConfig(toe_reference=False))
    assert with_ref.unwrapped.toe_targets[0][35, 0] > math.radians(20)
    assert not straight.unwrapped.toe_targets[0].any()
    toe = with_ref.unwrapped.humanoid.body_joints["l_toe"].qpos_index[0]
    assert np.array_equal(straight.unwrapped.clips[0].qpos[:, toe], walk2.qpos[:, toe])


def test_import_envs_stays_light():
    """perception (and torch) load only when a gait env estimates contacts."""
    import subprocess
    import sys
    code = "import sys, envs; assert 'torch' not in sys.modules and 'perception' not in sys.modules, 'heavy import'"
    subprocess.run([sys.executable, "-c", code], check=True)
