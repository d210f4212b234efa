"""agents/foot_transfer.py: a two-segment-foot gait policy carried to the one-segment foot."""

import json

import numpy as np
import pytest

import envs  # noqa: F401
from agents import foot_transfer
from agents.policy import PolicyError, load_policy

SOURCE = "models/mimic_gait_ff"


@pytest.fixture(scope="module")
def carried(tmp_path_factory):
    out = tmp_path_factory.mktemp("one") / "policy"
    foot_transfer.main(["--policy", SOURCE, "--foot", "one", "--out", str(out)])
    return load_policy(SOURCE), load_policy(out)


def test_the_carried_policy_acts_as_the_source_when_the_cut_inputs_are_at_their_mean(carried):
    source, target = carried
    source_env, target_env = source.make_env(["deepmimic:walk"]), target.make_env(["deepmimic:walk"])
    assert target.foot == "one" and target_env.observation_space.shape == (304,)
    assert source_env.observation_space.shape == (330,) and target_env.action_space.shape == (20,)
    inputs = foot_transfer.shared_inputs(source_env.unwrapped, target_env.unwrapped)
    cut = np.setdiff1d(np.arange(330), inputs)
    # 3 x 4 entries per toe body (p, v, dp, dv) and the two toe hinges' previous actions
    assert len(cut) == 2 * 12 + 2 and len(np.unique(inputs)) == 304
    obs, _ = source_env.reset(seed=3)
    obs = obs.copy()
    obs[cut] = source.normalizer.obs_rms.mean[cut]  # normalised to 0: the cut weights read nothing
    joints = foot_transfer.driven_joint_names(source_env.unwrapped)
    kept = [joints.index(n) for n in foot_transfer.driven_joint_names(target_env.unwrapped)]
    assert joints[20:] == ["l_toe_y", "r_toe_y"] and kept == list(range(20))
    np.testing.assert_allclose(target(obs[inputs]), source(obs)[kept], atol=1e-5)
    # with the toe inputs as observed the actions differ: the check above is not vacuous
    real, _ = source_env.reset(seed=3)
    assert np.abs(target(real[inputs]) - source(real)[kept]).max() > 1e-3
    np.testing.assert_array_equal(target.normalizer.obs_rms.var, source.normalizer.obs_rms.var[inputs])
    np.testing.assert_array_equal(target.model.policy.log_std.detach().numpy(),
                                  source.model.policy.log_std.detach().numpy()[kept])


def test_on_the_one_segment_foot_it_sees_straight_toe_targets(carried):
    """The target task observes toe targets of 0 (no toe hinge); the carried policy acts there as
    the source acts on the same observation with its toe-body inputs at their mean."""
    source, target = carried
    source_env, target_env = source.make_env(["deepmimic:walk"]), target.make_env(["deepmimic:walk"])
    inputs = foot_transfer.shared_inputs(source_env.unwrapped, target_env.unwrapped)
    obs, _ = target_env.reset(seed=4)
    toe = target_env.unwrapped.obs_slices["ref_toe"]
    assert np.all(obs[toe] == 0) and np.any(source.normalizer.obs_rms.mean[inputs][toe] != 0)
    lifted = source.normalizer.obs_rms.mean.astype(np.float32)  # cut inputs at their mean
    lifted[inputs] = obs
    np.testing.assert_allclose(target(obs), source(lifted)[:20], atol=1e-5)


def test_sidecar_continues_the_source_record_in_the_new_task(carried):
    source, target = carried
    sidecar = json.loads((target.path / "sidecar.json").read_text())
    assert sidecar["env"]["foot"] == "one" and sidecar["transferred_from"] == SOURCE
    assert sidecar["env"]["gait"] == source.sidecar["env"]["gait"]
    assert sidecar["metrics"] == {} and sidecar["score"] is None and "evaluation" not in sidecar
    training = target.record.training
    assert training.init_from == SOURCE and training.steps == source.record.training.steps
    assert training.commands[:-1] == source.record.training.commands
    assert training.commands[-1].endswith(f"--out {target.path}") and sidecar["command"] == training.commands[-1]
    assert target.model.learning_rate == source.model.learning_rate
    assert (target.model.n_steps, target.model.batch_size, target.model.n_epochs) == \
        (source.model.n_steps, source.model.batch_size, source.model.n_epochs)


def test_refuses_what_it_cannot_carry(carried, tmp_path):
    source, target = carried
    with pytest.raises(PolicyError, match="already a foot='two' policy"):
        foot_transfer.transfer(source, "two", tmp_path / "a")
    with pytest.raises(PolicyError, match=r"bodies the source lacks \(\['l_toe', 'r_toe'\]\)"):
        foot_transfer.transfer(target, "two", tmp_path / "b")
    with pytest.raises(PolicyError, match="unknown foot 'three'"):
        foot_transfer.transfer(source, "three", tmp_path / "c")
    with pytest.raises(PolicyError, match="is the source policy"):
        foot_transfer.transfer(source, "one", source.path)
    with pytest.raises(SystemExit, match="invalid choice"):
        foot_transfer.main(["--policy", SOURCE, "--foot", "three", "--out", str(tmp_path / "x")])
    assert not any(tmp_path.iterdir())  # nothing written by a refused transfer
