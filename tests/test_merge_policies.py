"""agents/merge_policies.py: several policies as one network acting as the mean of their actions."""

import json

import numpy as np
import pytest
import torch

from agents.merge_policies import main, merged_weights
from agents.policy import PolicyError, load_policy, mlp_mean_action

D, G = "models/mimic_general_privileged", "models/mimic_general_stance_avg"


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
    out = main([G, D, "--out", str(tmp_path / "merged")])
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
        main([G, "--out", str(tmp_path / "one")])
    with pytest.raises(SystemExit, match="mimic_walk: trained in another environment"):
        main([G, "models/mimic_walk", "--out", str(tmp_path / "other")])
