"""The "reference" observation frame: ADAPT's observation in axes turned with the reference's
heading, so a clip walked any way is observed as if it walked towards +x; a world-frame policy
runs in it as it is (MimicPolicy.observing); clips turned about z (transforms.turned)."""

from pathlib import Path

import numpy as np
import pytest

import envs  # noqa: F401  (registers the ids)
from agents.adaptation import adaptation_key
from agents.policy import PolicyError, load_policy
from envs.config import MimicConfig
from envs.mimic import MimicEnv
from reference_motion import rotations as rot
from reference_motion.transforms import turned

MODELS = Path(__file__).parents[1] / "models"


def test_turned_rotates_the_root_path_and_heading_and_keeps_the_hinges(walk):
    quarter = turned(walk, np.pi / 2)
    # a point at (x, y) goes to (−y, x); the heading gains 90°; the pose is the same
    np.testing.assert_allclose(quarter.root_pos[:, 0], -walk.root_pos[:, 1], atol=1e-12)
    np.testing.assert_allclose(quarter.root_pos[:, 1], walk.root_pos[:, 0], atol=1e-12)
    np.testing.assert_allclose(quarter.root_pos[:, 2], walk.root_pos[:, 2])
    gained = np.angle(np.exp(1j * (rot.yaw(quarter.root_quat) - rot.yaw(walk.root_quat))))
    np.testing.assert_allclose(gained, np.pi / 2, atol=1e-9)
    np.testing.assert_array_equal(quarter.hinges, walk.hinges)
    np.testing.assert_allclose(turned(quarter, 1.5 * np.pi).qpos[:, :3], walk.qpos[:, :3], atol=1e-12)


@pytest.mark.parametrize("start", [0, 100])
def test_the_reference_frame_observes_a_clip_the_same_whichever_way_it_walks(walk, start):
    """Walk and walk turned by 130° give the same observations in the reference frame, at the reset
    and, up to the friction pyramid (MuJoCo's default cone, whose facets do not turn with the
    body), after the same actions; in world axes they differ by far more. Where the reference
    faces +x the reference frame is the world frame."""
    other = turned(walk, np.radians(130))
    action = np.full(20, 0.1, dtype=np.float32)

    def observations(clip, frame):
        env = MimicEnv([clip], episode_frames=60, config=MimicConfig(obs_frame=frame))
        obs, _ = env.reset(seed=0, options={"clip": 0, "start_frame": start})
        seen = [obs]
        for _ in range(5):
            seen.append(env.step(action)[0])
        return np.array(seen)

    reference, reference_turned = observations(walk, "reference"), observations(other, "reference")
    np.testing.assert_allclose(reference_turned[0], reference[0], atol=1e-4)
    world, world_turned = observations(walk, "world"), observations(other, "world")
    assert np.abs(reference_turned - reference).max() < 0.2 < 2 < np.abs(world_turned - world).max()
    if abs(rot.yaw(walk.root_quat[start])) < 1e-3:  # the clip starts facing +x
        np.testing.assert_allclose(reference[0], world[0], atol=1e-3)


def test_a_world_frame_policy_can_observe_in_the_reference_frame(walk):
    policy = load_policy(MODELS / "mimic_walk")
    assert policy.record.env.mimic_config().obs_frame == "world"
    assert policy.observing("world") is policy
    turned_policy = policy.observing("reference")
    assert turned_policy.record.env.mimic_config().obs_frame == "reference"
    assert turned_policy.record.extra["observed_in"] == "world"
    env = turned_policy.make_env([walk], artefacts=None)
    assert env.unwrapped.config.obs_frame == "reference"
    # back again: the record keeps the frame it was trained in; the weights are shared, not copied
    back = turned_policy.observing("world")
    assert back.record.extra["observed_in"] == "world" and back.model is policy.model
    # an adaptation of the same weights in another frame is another policy: another cache key; back in
    # the frame they were trained in, the key (and so any cached adaptation) is the original's
    assert adaptation_key(walk, turned_policy) != adaptation_key(walk, policy)
    assert adaptation_key(walk, back) == adaptation_key(walk, policy)


def test_a_heading_frame_policy_cannot_run_in_the_reference_frame():
    gait = load_policy(MODELS / "mimic_gait")
    assert gait.record.env.mimic_config().obs_frame == "heading"
    with pytest.raises(PolicyError, match="'heading' frame.*cannot run in 'reference'"):
        gait.observing("reference")


def test_the_shipped_generalist_observes_in_the_reference_frame():
    general = load_policy(MODELS / "mimic_general")
    assert general.record.env.mimic_config().obs_frame == "reference"
    assert general.record.extra["observed_in"] == "world"


def test_the_480_hz_generalist_trained_observing_in_the_reference_frame_at_480_hz():
    fine = load_policy(MODELS / "mimic_general_480")
    task = fine.record.env.mimic_config()
    assert task.obs_frame == "reference" and "observed_in" not in fine.record.extra
    assert task.physics_rate_hz == 480.0 and fine.make_env(["deepmimic:walk"]).unwrapped.substeps == 8
