"""bench/ensemble.py's MeanAction: the mean of its members' actions, symmetric when asked."""

import sys
from pathlib import Path

import numpy as np
import pytest

from agents.mirror import MirrorAveraged, MirrorMaps
from agents.policy import PolicyError, load_policy

REPOSITORY = Path(__file__).resolve().parents[1]
sys.path.append(str(REPOSITORY / "bench"))
from ensemble import MeanAction, ensemble_label  # noqa: E402

D, G = REPOSITORY / "models/mimic_general_privileged", REPOSITORY / "models/mimic_general_stance_avg"


def test_the_mean_of_two_policies_and_of_their_symmetric_actors():
    d, g = load_policy(D), load_policy(G)
    env = g.make_env(["deepmimic:walk"], artefacts=None)
    observations = [env.reset(seed=seed)[0] for seed in range(3)]
    maps = MirrorMaps.of(env)
    env.close()
    mean = MeanAction([d, g])
    for obs in observations:
        np.testing.assert_allclose(mean(obs), (d(obs) + g(obs)) / 2, atol=1e-6)
        symmetric = MirrorAveraged(mean, maps)(obs)
        np.testing.assert_allclose(symmetric, (MirrorAveraged(d, maps)(obs) + MirrorAveraged(g, maps)(obs)) / 2,
                                   atol=1e-6)
        assert np.abs(d(obs) - g(obs)).max() > 1e-3  # the members differ
    assert ensemble_label([str(D), str(G)]) == f"mean action of {D} and {G}"


def test_members_of_other_tasks_are_refused():
    with pytest.raises(PolicyError, match="share their task"):
        MeanAction([load_policy(G), load_policy(REPOSITORY / "models/mimic_walk")])
