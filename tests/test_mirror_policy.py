"""agents/mirror_policy.py: a policy's mirror image, on hand-made weights and a shipped policy."""

from dataclasses import replace

import numpy as np
import pytest
import torch
from stable_baselines3 import PPO

from agents.mirror import MirrorMaps
from agents.mirror_policy import main, mirror_policy, mirrored_statistics, mirrored_weights
from agents.policy import PolicyError, load_policy
from agents.symmetric_policy import SymmetricActorCriticPolicy, maps_as_kwargs
from agents.train_ppo import policy_kwargs

# a 3-component observation whose components 0 and 1 swap and whose component 2 changes sign, and a
# 2-component action whose components swap and change sign (a hinge about x on each side): each
# map its own inverse, as a left/right mirror is
MAPS = MirrorMaps(obs_perm=np.array([1, 0, 2]), obs_sign=np.array([1.0, 1.0, -1.0], np.float32),
                  action_perm=np.array([1, 0]), action_sign=np.array([-1.0, -1.0], np.float32))


def tiny_state() -> dict[str, torch.Tensor]:
    def layer(rows, cols, start):
        return torch.arange(start, start + rows * cols, dtype=torch.float32).reshape(rows, cols)
    return {"mlp_extractor.policy_net.0.weight": layer(2, 3, 1), "mlp_extractor.value_net.0.weight": layer(2, 3, 7),
            "mlp_extractor.policy_net.0.bias": torch.tensor([0.5, -0.5]),
            "action_net.weight": layer(2, 2, 13), "action_net.bias": torch.tensor([1.0, 2.0]),
            "log_std": torch.tensor([-1.0, -2.0])}


def test_weights_move_as_the_maps_say():
    out = mirrored_weights(tiny_state(), MAPS)
    # input columns: column j of the mirrored layer is column perm[j] of the source times its sign
    assert out["mlp_extractor.policy_net.0.weight"].tolist() == [[2.0, 1.0, -3.0], [5.0, 4.0, -6.0]]
    assert out["mlp_extractor.value_net.0.weight"].tolist() == [[8.0, 7.0, -9.0], [11.0, 10.0, -12.0]]
    # output rows: row k is row perm[k] of the source times the sign of action component k
    assert out["action_net.weight"].tolist() == [[-15.0, -16.0], [-13.0, -14.0]]
    assert out["action_net.bias"].tolist() == [-2.0, -1.0]
    assert out["log_std"].tolist() == [-2.0, -1.0]  # a spread has no sign
    assert out["mlp_extractor.policy_net.0.bias"].tolist() == [0.5, -0.5]  # hidden layers stay


def test_the_mirrored_linear_actor_acts_on_o_as_the_source_on_the_mirrored_o():
    state, out = tiny_state(), mirrored_weights(tiny_state(), MAPS)
    mean, var = np.array([0.3, -0.2, 0.7]), np.array([4.0, 1.0, 9.0])
    mean2, var2 = mirrored_statistics(mean, var, MAPS)

    def act(s, m, v, o):
        x = torch.as_tensor((o - m) / np.sqrt(v), dtype=torch.float32)
        hidden = s["mlp_extractor.policy_net.0.weight"] @ x + s["mlp_extractor.policy_net.0.bias"]
        return (s["action_net.weight"] @ hidden + s["action_net.bias"]).numpy()

    o = np.array([1.5, -0.4, 2.0])
    np.testing.assert_allclose(act(out, mean2, var2, o), MAPS.action(act(state, mean, var, MAPS.observation(o))),
                               rtol=1e-6)


def test_a_network_of_another_layout_is_refused_by_name():
    state = tiny_state()
    del state["log_std"]
    with pytest.raises(PolicyError, match="no log_std"):
        mirrored_weights(state, MAPS)
    state = tiny_state()
    state["action_net.weight"] = torch.zeros(3, 2)
    with pytest.raises(PolicyError, match="action_net.weight has 3 rows; the mirror maps an action of 2"):
        mirrored_weights(state, MAPS)


def test_a_shipped_policy_mirrors_into_its_mirror_image_and_back(tmp_path):
    source = load_policy("models/mimic_walk")
    once = load_policy(main(["models/mimic_walk", "--out", str(tmp_path / "once")]))
    twice = load_policy(main([str(tmp_path / "once"), "--out", str(tmp_path / "twice")]))
    env = source.make_env(["deepmimic:walker/turn_right0"], artefacts=None)
    maps = MirrorMaps.of(env)
    obs, _ = env.reset(seed=0)
    for _ in range(20):  # states of a turn, which its mirror image is not
        expected = maps.action(source.mean_action(maps.observation(obs)))
        assert np.abs(expected - source.mean_action(obs)).max() > 0.01
        np.testing.assert_allclose(once.mean_action(obs), expected, atol=1e-4)
        np.testing.assert_allclose(once.values(obs[None]), source.values(maps.observation(obs)[None]), rtol=1e-4)
        np.testing.assert_allclose(twice.mean_action(obs), source.mean_action(obs), atol=1e-4)
        obs, *_ = env.step(source.mean_action(obs))
    assert once.sidecar["mirrored_from"] == "models/mimic_walk" and once.record.metrics == {}
    assert source.model.policy.optimizer.state_dict()["state"]  # the source's Adam moments, for its weights,
    assert not once.model.policy.optimizer.state_dict()["state"]  # are not carried: a fresh optimizer


def test_the_symmetric_actor_is_refused_as_its_own_mirror_image():
    walk = load_policy("models/mimic_walk")
    env = walk.make_env(["deepmimic:walk"], artefacts=None)
    kwargs = {**policy_kwargs("16,16", 0.03), "mirror": maps_as_kwargs(MirrorMaps.of(env))}
    model = PPO(SymmetricActorCriticPolicy, env, policy_kwargs=kwargs, n_steps=64, batch_size=64, device="cpu")
    with pytest.raises(PolicyError, match="runs/sym: trained as the symmetric actor .* which is its own mirror image"):
        mirror_policy(replace(walk, model=model), "runs/sym")
    env.close()
