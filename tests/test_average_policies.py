"""agents/average_policies.py: weight averaging of checkpoints, and (``--actions``) several policies as one network
acting as the mean of their actions, on hand-made tensors and shipped policies."""

import json

import numpy as np
import pytest
import torch

from agents.average_policies import averaged_weights, main, merged_weights, pooled_statistics
from agents.policy import PolicyError, load_policy, mlp_mean_action

D, G = "models/mimic_general_privileged", "models/mimic_general_stance_avg"


def test_weights_are_averaged_element_by_element():
    a = {"w": torch.tensor([[0.0, 2.0]]), "b": torch.tensor([1.0])}
    b = {"w": torch.tensor([[4.0, -2.0]]), "b": torch.tensor([3.0])}
    mean = averaged_weights([a, b], ["a", "b"])
    assert torch.equal(mean["w"], torch.tensor([[2.0, 0.0]])) and torch.equal(mean["b"], torch.tensor([2.0]))


def test_networks_of_other_shapes_are_refused_by_name():
    a = {"w": torch.zeros(2, 3)}
    b = {"w": torch.zeros(2, 4)}
    with pytest.raises(PolicyError, match=r"second: a different network from first \(parameters \['w'\]"):
        averaged_weights([a, b], ["first", "second"])


def test_pooled_statistics_are_those_of_the_equal_mixture():
    # N(0, 1) and N(2, 1) mixed equally: mean 1, variance 1 + 1 = 2
    mean, var = pooled_statistics(np.array([[0.0], [2.0]]), np.array([[1.0], [1.0]]))
    assert mean.tolist() == [1.0] and var.tolist() == pytest.approx([2.0])
    rng = np.random.default_rng(0)
    x, y = rng.normal(0, 1, 200_000), rng.normal(3, 2, 200_000)
    mean, var = pooled_statistics(np.array([[x.mean()], [y.mean()]]), np.array([[x.var()], [y.var()]]))
    both = np.concatenate([x, y])
    assert mean[0] == pytest.approx(both.mean()) and var[0] == pytest.approx(both.var())


def test_two_shipped_policies_average_into_a_loadable_policy_between_them(tmp_path):
    pair = ["models/mimic_general_stance", "models/mimic_general_dr"]
    out = main([*pair, "--out", str(tmp_path / "avg")])
    averaged, (a, b) = load_policy(out), [load_policy(p) for p in pair]
    key = "mlp_extractor.policy_net.0.weight"
    expected = (a.model.policy.state_dict()[key] + b.model.policy.state_dict()[key]) / 2
    assert torch.allclose(averaged.model.policy.state_dict()[key], expected)
    assert np.allclose(averaged.normalizer.obs_rms.mean, (a.normalizer.obs_rms.mean + b.normalizer.obs_rms.mean) / 2)
    assert averaged.sidecar["averaged_from"] == pair
    obs = np.zeros(averaged.model.observation_space.shape, dtype=np.float32)
    assert averaged(obs).shape == averaged.model.action_space.shape


def test_a_single_policy_is_refused(tmp_path):
    with pytest.raises(SystemExit):
        main(["models/mimic_general_stance", "--out", str(tmp_path / "avg")])


def test_policies_trained_in_other_environments_are_refused(tmp_path):
    with pytest.raises(SystemExit, match="models/mimic_walk: trained in another environment"):
        main(["models/mimic_general_stance", "models/mimic_walk", "--out", str(tmp_path / "avg")])



def test_hand_made_layers_side_by_side_and_heads_averaged():
    def net(scale):
        return {"mlp_extractor.policy_net.0.weight": scale * torch.ones(2, 3),
                "mlp_extractor.policy_net.0.bias": torch.zeros(2),
                "mlp_extractor.policy_net.2.weight": scale * torch.eye(2),
                "mlp_extractor.policy_net.2.bias": torch.ones(2),
                "mlp_extractor.value_net.0.weight": torch.ones(2, 3), "mlp_extractor.value_net.0.bias": torch.zeros(2),
                "action_net.weight": scale * torch.ones(1, 2), "action_net.bias": torch.tensor([scale]),
                "value_net.weight": torch.ones(1, 2), "value_net.bias": torch.tensor([scale]),
                "log_std": torch.tensor([np.log(scale)], dtype=torch.float32)}
    merged = merged_weights([net(1.0), net(3.0)])
    assert merged["mlp_extractor.policy_net.0.weight"].shape == (4, 3)
    second = merged["mlp_extractor.policy_net.2.weight"]
    assert torch.equal(second, torch.block_diag(torch.eye(2), 3 * torch.eye(2)))
    assert torch.equal(merged["action_net.weight"], torch.tensor([[0.5, 0.5, 1.5, 1.5]]))
    assert merged["action_net.bias"].item() == 2.0 and merged["value_net.bias"].item() == 2.0
    assert merged["log_std"].item() == pytest.approx(0.5 * np.log(3.0))


def test_the_merged_policy_acts_and_values_as_the_mean_of_its_inputs(tmp_path):
    out = main([G, D, "--actions", "--out", str(tmp_path / "merged")])
    merged, g, d = load_policy(out), load_policy(G), load_policy(D)
    env = g.make_env(["deepmimic:walk"], artefacts=None)
    obs = np.stack([env.reset(seed=seed)[0] for seed in range(4)])
    env.close()
    x = g.normalizer.normalize_obs(obs).astype(np.float32)
    np.testing.assert_allclose(mlp_mean_action(merged.model.policy, x),
                               (mlp_mean_action(g.model.policy, x) + mlp_mean_action(d.model.policy, x)) / 2, atol=1e-5)
    np.testing.assert_allclose(merged.values(obs), (g.values(obs) + d.values(obs)) / 2, atol=1e-4)
    sidecar = json.loads((out / "sidecar.json").read_text())
    assert sidecar["ppo"]["net"] == "512,512" and sidecar["merged_from"] == [G, D]


def test_inputs_that_cannot_join_are_named(tmp_path):
    with pytest.raises(SystemExit, match="at least two policies"):
        main([G, "--actions", "--out", str(tmp_path / "one")])
    with pytest.raises(SystemExit, match="mimic_walk: trained in another environment"):
        main([G, "models/mimic_walk", "--actions", "--out", str(tmp_path / "other")])
