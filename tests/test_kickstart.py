"""agents/kickstart.py: the supervised step between PPO updates that pulls the policy towards a
teacher on the takes a policy set routes to it, on the DeepMimic walk (PPO alone) and run (taught)."""

from pathlib import Path

import numpy as np
import pytest
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

from agents.kickstart import Kickstart, KickstartConfig, Teaching, kickstart_loss
from agents.policy import load_policy
from agents.policy_set import PolicySet
from agents.teachers import mean_actions_and_values
from envs import ArtefactMix
from agents.train_ppo import main as train_main
from reference_motion.library import load_motion

MODELS = Path(__file__).parents[1] / "models"


def test_the_loss_is_the_mean_squared_distance_of_the_actions():
    mean = torch.tensor([[0.0, 0.0], [1.0, 1.0]])
    teacher = torch.tensor([[1.0, 0.0], [1.0, 3.0]])
    assert float(kickstart_loss(mean, teacher)) == pytest.approx((1.0 + 4.0) / 2)
    assert float(kickstart_loss(teacher, teacher)) == 0.0


def teaching_set(tmp_path: Path) -> Path:
    """A set whose default is mimic_walk and whose "*run*" takes mimic_imu teaches."""
    PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_walk",
              clips=(("*run*", MODELS / "mimic_imu"),)).save()
    return tmp_path / "set"


def test_only_the_clips_the_set_routes_to_a_policy_of_their_own_are_taught(tmp_path):
    walk = load_policy(MODELS / "mimic_walk")
    teaching = Teaching.load(teaching_set(tmp_path), walk.make_env(["deepmimic:walk"]))
    assert [Path(t.path).name for t in teaching.teachers] == ["mimic_imu"]
    assert teaching.teacher_of("deepmimic:run") == 0
    assert teaching.teacher_of("deepmimic:run (mirrored) (x1.5 speed)") == 0  # a copy goes where its source goes
    assert teaching.teacher_of("deepmimic:walk") is None  # the default's takes: PPO alone
    PolicySet(tmp_path / "plain", MODELS / "mimic_walk", MODELS / "mimic_walk").save()
    with pytest.raises(ValueError, match="routes no clip to a policy of its own"):
        Teaching.load(tmp_path / "plain", walk.make_env(["deepmimic:walk"]))
    with pytest.raises(ValueError, match="epochs and batch_size must be >= 1"):
        KickstartConfig(policy_set="x", epochs=0)


def test_a_rollout_gathers_the_taught_states_with_the_teachers_actions_and_a_fit_pulls_the_policy_to_them(tmp_path):
    walker = load_policy(MODELS / "mimic_walk")
    clips = [load_motion(name, "humanoid_1seg", min_frames=400) for name in ("deepmimic:walk", "deepmimic:run")]
    venv = VecNormalize(DummyVecEnv([lambda: walker.make_env(clips) for _ in range(2)]), norm_reward=False,
                        training=False)
    venv.obs_rms = walker.normalizer.obs_rms
    model = PPO.load(MODELS / "mimic_walk" / "model.zip", env=venv, n_steps=64, n_epochs=1)
    kick = Kickstart(Teaching.load(teaching_set(tmp_path), venv.envs[0]), KickstartConfig("set", epochs=40, lr=1e-3))
    model.learn(128, callback=kick)  # one rollout; its states are fitted before the next one
    obs, actions = kick.labels()
    assert 0 < len(obs) < 128  # some of the 2 x 64 states were the run's, some the walk's
    raw = np.asarray(kick._raw, np.float32)
    np.testing.assert_allclose(obs, venv.normalize_obs(raw), rtol=1e-5, atol=1e-5)  # the states acted on
    np.testing.assert_allclose(actions, mean_actions_and_values(kick.teaching.teachers[0], raw)[0], atol=1e-6)
    before = kick.fit()
    assert kick.labels()[0].shape[0] == 0  # cleared
    with torch.no_grad():
        mean = model.policy.get_distribution(torch.as_tensor(obs)).distribution.mean
    after = float(kickstart_loss(mean, torch.as_tensor(actions)))
    assert before > 0.05 and after < 0.5 * before


@pytest.mark.parametrize("corrupted", [False, True])
def test_corrupted_episodes_are_taught_only_when_asked_for(tmp_path, corrupted):
    walker = load_policy(MODELS / "mimic_walk")
    every_one_corrupted = ArtefactMix(strength=(1.0, 1.0), fraction=1.0, variants_per_clip=1, seed=0)
    venv = VecNormalize(DummyVecEnv([lambda: walker.make_env(["deepmimic:run"], artefacts=every_one_corrupted)]),
                        norm_reward=False, training=False)
    venv.obs_rms = walker.normalizer.obs_rms
    model = PPO.load(MODELS / "mimic_walk" / "model.zip", env=venv, n_steps=32, n_epochs=1, batch_size=32)
    kick = Kickstart(Teaching.load(teaching_set(tmp_path), venv.envs[0]),
                     KickstartConfig("set", corrupted=corrupted))
    model.learn(32, callback=kick)
    assert len(kick.labels()[0]) == (32 if corrupted else 0)


def test_train_ppo_kickstarts_and_records_it(tmp_path, monkeypatch):
    fits = []
    fit = Kickstart.fit
    monkeypatch.setattr(Kickstart, "fit", lambda self: fits.append(len(self._who)) or fit(self))
    run = tmp_path / "run"
    common = ["--init-from", str(MODELS / "mimic_walk"), "--n-envs", "2", "--n-steps", "64", "--batch-size", "64",
              "--vec", "dummy", "--no-progress", "--eval-every", "100000"]
    train_main(["--clips", "deepmimic:walk", "deepmimic:run", "--kickstart", str(teaching_set(tmp_path)),
                "--kickstart-epochs", "3", "--total-steps", "256", "--checkpoint-every", "128", "--run-dir", str(run),
                *common])
    assert len(fits) == 1 and 0 < fits[0] < 128  # after the first of two rollouts' update, on some of its states
    policy = load_policy(sorted((run / "checkpoints").glob("step_*.zip"))[-1])
    assert policy.record.training.kickstart == {"policy_set": str(tmp_path / "set"), "epochs": 3, "lr": 5e-5,
                                                "batch_size": 512, "corrupted": False}
    refused = ["--run-dir", str(tmp_path / "refused"), *common]
    PolicySet(tmp_path / "plain", MODELS / "mimic_walk", MODELS / "mimic_walk").save()
    for extra, error in ((["--clips", "deepmimic:walk", "--kickstart", str(tmp_path / "plain")], "routes no clip"),
                         (["--clips", "deepmimic:walk", "--kickstart", str(tmp_path / "set")],
                          r"no training clip matches a glob of the set \(\*run\*\)"),
                         (["--clips", "deepmimic:run", "--kickstart", str(tmp_path / "set"), "--corrupted-fraction",
                           "1"], "--corrupted-fraction 1 leaves none"),
                         (["--clips", "deepmimic:run", "--kickstart-lr", "1e-3"],
                          "--kickstart-lr sets the kickstarting")):
        with pytest.raises(SystemExit, match=error):
            train_main([*extra, *refused])
        assert not (tmp_path / "refused").exists()  # refused before the run
