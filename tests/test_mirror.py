"""The mirror-symmetric actor (agents/mirror.py): its maps are what the environment does to a
mirrored clip, exactly, and the actor it makes is mirror symmetric whatever the policy."""

import gymnasium as gym
import numpy as np
import pytest

import envs  # noqa: F401  (registers the ids)
from agents.mirror import MirrorAveraged, MirrorMaps, actor_label
from reference_motion.library import load_motion
from reference_motion.transforms import mirror


@pytest.fixture(scope="module")
def walk():
    return load_motion("deepmimic:walker/turn_left0")


@pytest.mark.parametrize("env_id,obs_frame,window", [("MimicIMU-v0", "reference", {}), ("MimicIMU-v0", "world", {}),
                                                     ("MimicDReCon-v0", "heading", {}),
                                                     ("MimicFullAction-v0", "heading", {}),
                                                     ("MimicIMU-v0", "reference", {"lookahead": (1, 4),
                                                                                   "lookbehind": (2, 8)})])
def test_the_maps_are_what_the_environment_does_to_the_mirrored_clip(walk, env_id, obs_frame, window):
    """A clip and its mirror image in one environment, from the same frame: the mirrored clip's
    observation is the clip's observation mirrored, at the reset and after a step in which the
    mirrored clip gets the mirrored action (the model is left/right symmetric, so to float precision);
    also with the reference ahead and behind in the observation."""
    from envs.config import MimicConfig
    env = gym.make(env_id, clips=[walk, mirror(walk)], config=MimicConfig(obs_frame=obs_frame, **window),
                   artefacts=None)
    maps = MirrorMaps.of(env)
    action = np.random.default_rng(0).normal(0.0, 0.3, env.action_space.shape).astype(np.float32)
    observed = []
    for clip, act in ((0, action), (1, maps.action(action))):
        first, _ = env.reset(seed=0, options={"clip": clip, "start_frame": 30})
        observed.append((first, env.step(act)[0]))
    for (obs, obs_mirrored) in zip(*observed):
        assert np.abs(obs - obs_mirrored).max() > 0.1  # a walk's frame is not its own mirror image
        np.testing.assert_allclose(maps.observation(obs), obs_mirrored, atol=1e-5)
    obs = observed[0][1]
    np.testing.assert_array_equal(maps.observation(maps.observation(obs)), obs)  # each map undoes itself
    np.testing.assert_array_equal(maps.action(maps.action(action)), action)


def test_the_symmetric_actor_is_mirror_symmetric(walk):
    """For any policy (here a random nonlinear one that is not), actor(mirrored o) = mirrored actor(o)."""
    env = gym.make("MimicIMU-v0", clips=[walk], artefacts=None)
    maps = MirrorMaps.of(env)
    rng = np.random.default_rng(1)
    weights = rng.normal(0.0, 0.1, (env.action_space.shape[0], env.observation_space.shape[0]))

    def lopsided(o: np.ndarray) -> np.ndarray:
        return np.tanh(weights @ o)

    obs, _ = env.reset(seed=0, options={"clip": 0, "start_frame": 10})
    actor = MirrorAveraged(lopsided, maps)
    assert np.abs(lopsided(maps.observation(obs)) - maps.action(lopsided(obs))).max() > 0.05
    np.testing.assert_allclose(actor(maps.observation(obs)), maps.action(actor(obs)), atol=1e-6)
    assert actor_label("models/x", True) == "models/x (mirror-averaged)" and actor_label("models/x", False) == "models/x"


def test_an_observation_it_does_not_know_is_refused():
    env = gym.make("MimicGait-v0", clips=["deepmimic:walk"])
    with pytest.raises(ValueError, match="MimicGait-v0: the mirror-symmetric actor knows the mimic observation"):
        MirrorMaps.of(env)


def test_mirror_twins_of_bodies_hinges_and_contact_channels():
    from reference_motion.humanoid.model import CONTACT_CHANNELS
    from reference_motion.transforms import mirror_twin
    assert [mirror_twin(n) for n in ("l_knee", "r_ankle_x", "left_toe", "right_heel", "pelvis", "lower_back")] == \
        ["r_knee", "l_ankle_x", "right_toe", "left_heel", "pelvis", "lower_back"]
    assert sorted(mirror_twin(c) for c in CONTACT_CHANNELS) == sorted(CONTACT_CHANNELS)


def test_the_leading_maps_are_the_prefix_and_a_prefix_the_mirror_leaves_is_refused():
    maps = MirrorMaps(np.array([1, 0, 2, 3]), np.array([1.0, 1.0, -1.0, 1.0]), np.array([0]), np.array([1.0]))
    leading = maps.leading(3)
    assert leading.obs_perm.tolist() == [1, 0, 2] and leading.obs_sign.tolist() == [1.0, 1.0, -1.0]
    with pytest.raises(ValueError, match="first 1 values are not closed under the mirror"):
        maps.leading(1)


def test_maps_that_are_not_a_mirror_are_refused():
    """Each map must be a signed permutation that undoes itself; lists are taken as arrays."""
    good = dict(obs_perm=[1, 0, 2], obs_sign=[1.0, 1.0, -1.0], action_perm=[1, 0], action_sign=[1.0, 1.0])
    maps = MirrorMaps(**good)
    assert maps.obs_perm.dtype.kind == "i" and maps.obs_sign.dtype == np.float32
    np.testing.assert_array_equal(maps.observation(np.array([1.0, 2.0, 3.0])), [2.0, 1.0, -3.0])
    with pytest.raises(ValueError, match="the action map is not its own inverse"):
        MirrorMaps(**{**good, "action_sign": [1.0, -1.0]})  # applied twice: minus the identity
    with pytest.raises(ValueError, match="the observation map's perm is not a permutation of the integers 0..2"):
        MirrorMaps(**{**good, "obs_perm": [1, 1, 2]})
    with pytest.raises(ValueError, match="not a permutation of the integers"):
        MirrorMaps(**{**good, "action_perm": [1.0, 0.0]})
    with pytest.raises(ValueError, match=r"signs must be \+1 or -1"):
        MirrorMaps(**{**good, "obs_sign": [2.0, 2.0, 1.0]})
    with pytest.raises(ValueError, match=r"perm \(2,\) and sign \(3,\)"):
        MirrorMaps(**{**good, "action_sign": [1.0, 1.0, 1.0]})
