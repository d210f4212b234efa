"""bench/student_fit.py: students of several widths fitted to a run's labelled states, on a hand-made run."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from agents.distill import Labels
from agents.policy import load_policy

REPOSITORY = Path(__file__).resolve().parents[1]
sys.path.append(str(REPOSITORY / "bench"))
from student_fit import main  # noqa: E402

TEACHER = REPOSITORY / "models" / "mimic_general_stance_avg"


def hand_made_run(run: Path, episodes: int = 60, steps: int = 50) -> float:
    """A distillation directory whose labels are a smooth function of the teacher's normalised
    observation; returns the labels' RMS (the error of a student that answers 0)."""
    teacher = load_policy(TEACHER)
    rng = np.random.default_rng(0)
    mean, var = teacher.normalizer.obs_rms.mean, teacher.normalizer.obs_rms.var
    n, dim = episodes * steps, mean.shape[0]
    obs = (mean + np.sqrt(var) * rng.standard_normal((n, dim))).astype(np.float32)
    weights = rng.standard_normal((dim, 4)) / np.sqrt(dim)
    actions = np.zeros((n, teacher.model.action_space.shape[0]), dtype=np.float32)
    actions[:, :4] = 0.3 * np.tanh(teacher.normalizer.normalize_obs(obs) @ weights)
    run.mkdir()
    Labels(obs, actions, np.zeros(n, np.float32), np.zeros(n, int), np.repeat(np.arange(episodes), steps)).save(
        run / "data.npz")
    (run / "args.json").write_text(json.dumps({"teacher": str(TEACHER), "batch_size": 128, "lr": 1e-3, "seed": 0}))
    return float(np.sqrt((actions ** 2).mean()))


def test_students_fit_a_learnable_labelling_closer_with_more_epochs(tmp_path):
    zero_answer = hand_made_run(tmp_path / "run")
    result = main(["--run", str(tmp_path / "run"), "--nets", "32,32", "128,128", "--epochs", "6", "--report-every", "3"])
    assert [row["net"] for row in result["rows"]] == ["32,32", "128,128"]
    assert result["held_out_states"] + result["train_states"] == result["states"] == 3000
    for row in result["rows"]:
        first, last = row["curve"]
        assert [first["epochs"], last["epochs"]] == [3, 6]
        assert last["train_rmse"] < first["train_rmse"] and last["held_out_rmse"] < 0.6 * zero_answer


def test_a_run_without_its_labelled_states_is_named(tmp_path):
    (tmp_path / "args.json").write_text("{}")
    with pytest.raises(SystemExit, match=r"data.npz: missing; --run must be an agents/distill.py --out directory"):
        main(["--run", str(tmp_path)])
