"""agents/expert_iteration.py: the search's kept lineage turned into labelled states, and the command
end to end with a resume, with the shipped walk policy on the DeepMimic walk."""

import json
from pathlib import Path

import numpy as np
import pytest

from agents.expert_iteration import (ExpertIterationConfig, SearchTask, draw_tasks, issued_actions, main, replayed,
                                     search_labels)
from agents.distill import Labels
from agents.policy import MimicPolicy, load_policy
from agents.rollout import run_episode
from agents.search import SearchConfig
from reference_motion.library import load_motion

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


@pytest.fixture(scope="module")
def walk_policy() -> MimicPolicy:
    return load_policy(WALK_POLICY)


def test_issued_actions_undo_the_smoothing():
    # smoothing 0.2, two frames per control step: the smoothed action follows 0.2·issued + 0.8·previous
    issued = np.array([[0.5, -1.0], [0.0, 0.25], [1.0, 1.0]])
    smoothed = [np.zeros(2)]
    for a in issued:
        smoothed.append(0.2 * a + 0.8 * smoothed[-1])
    per_frame = np.array([smoothed[0]] + [s for s in smoothed[1:] for _ in range(2)])  # (7, 2): start + 6 frames

    class Recorded:
        actions = per_frame
        frames = 6

    np.testing.assert_allclose(issued_actions(Recorded, 0.2, 2), issued, atol=1e-12)


def test_a_replay_sees_the_observations_the_policy_acted_on(walk_policy, walk):
    env = walk_policy.make_env([walk], artefacts=None)
    seen = []

    def noisy(obs):
        seen.append(obs)
        return np.clip(walk_policy(obs) + 0.2 * np.sin(len(seen)), -1, 1)

    episode = run_episode(env, noisy, {"clip": 0, "start_frame": 0}, max_frames=60)
    fpc = env.unwrapped.config.frames_per_control
    actions = issued_actions(episode, env.unwrapped.config.action_smoothing, fpc)
    assert actions.shape == (30, 20)
    np.testing.assert_allclose(actions[:5], [np.clip(walk_policy(o) + 0.2 * np.sin(k + 1), -1, 1)
                                             for k, o in enumerate(seen[:5])], atol=1e-5)
    obs = replayed(env, episode, actions)
    np.testing.assert_allclose(obs, np.asarray(seen, dtype=np.float32), atol=1e-5)
    # a replay that parts from the episode keeps only the steps before it did
    wrong = actions.copy()
    wrong[10:] = -1.0
    assert 10 < len(replayed(env, episode, wrong)) < 30


def test_search_labels_label_the_lineage_and_drop_the_windows_before_a_fall(walk_policy, walk):
    config = ExpertIterationConfig(search=SearchConfig(beam=2, samples=4))
    labels = search_labels(walk_policy, SearchTask(walk, 0, seed=3), config)
    assert labels["ended_by"] == "" and labels["frames"] >= 300 and labels["labelled"] == 150
    assert labels["obs"].shape == (150, 273) and labels["actions"].shape == (150, 20)
    assert np.abs(labels["actions"]).max() <= 1.0 and labels["values"].shape == (150,)
    gap = np.sqrt(((np.stack([walk_policy(o) for o in labels["obs"]]) - labels["actions"]) ** 2).mean())
    assert 0.05 < gap < 0.3  # the kept actions are the policy's plus noise of its σ (0.17)

    backwards = walk.with_qpos(walk.qpos[::-1].copy(), loop=False)  # the walk policy cannot walk it
    failed = search_labels(walk_policy, SearchTask(backwards, 0, seed=3), config)
    assert failed["ended_by"] in ("fallen", "lagging")
    window, steps = config.search.window_steps, failed["frames"] // 2  # whole windows before the fall's
    assert failed["labelled"] == max(0, ((steps - 1) // window - config.drop_windows) * window)
    assert len(failed["obs"]) == len(failed["actions"]) == failed["labelled"]


def test_draw_tasks_spans_the_clip_and_corrupts_the_share_asked():
    walk = load_motion("deepmimic:walk", "humanoid_1seg", min_frames=700)
    rng = np.random.default_rng(0)
    clean = draw_tasks([walk], 40, 0.0, (1.0, 1.0), 300, rng)
    assert all(t.motion is walk and t.strength is None for t in clean)
    starts = [t.start_frame for t in clean]
    assert min(starts) >= 0 and max(starts) <= walk.n_frames - 301 and len(set(starts)) > 10
    corrupted = draw_tasks([walk], 20, 1.0, (0.5, 1.0), 300, rng)
    assert all(0.5 <= t.strength <= 1.0 for t in corrupted) and len({t.seed for t in corrupted}) == 20


def test_config_refuses_nonsense():
    with pytest.raises(ValueError, match="episodes_per_round"):
        ExpertIterationConfig(episodes_per_round=0)
    with pytest.raises(ValueError, match="holdout"):
        ExpertIterationConfig(holdout=1.0)


def test_expert_iteration_end_to_end_writes_a_policy_and_resumes(tmp_path, walk_policy):
    out = tmp_path / "exit"
    main(["--policy", str(WALK_POLICY), "--clips", "deepmimic:walk", "--corrupted-fraction", "0", "--rounds", "1",
          "--episodes-per-round", "2", "--search-beam", "2", "--search-samples", "4", "--epochs", "2",
          "--out", str(out), "--no-progress"])
    student = load_policy(out / "student")
    env = walk_policy.make_env(["deepmimic:walk"])
    obs = env.reset(seed=0)[0]
    assert student.record.ppo.net == walk_policy.record.ppo.net
    assert 0 < np.abs(student(obs) - walk_policy(obs)).max() < 0.5  # fitted, from the walk policy's weights
    main(["--out", str(out), "--resume", "--rounds", "2", "--no-progress"])
    rounds = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    assert [r["round"] for r in rounds] == [0, 1] and rounds[1]["guided_by"].endswith("student")
    assert rounds[1]["states"] > rounds[0]["states"] > 200
    # stopped after writing the labels and the student but not the log line: the student's record rules
    log = out / "log.jsonl"
    log.write_text(log.read_text().splitlines(keepends=True)[0])
    labels = Labels.load(out / "data.npz")
    (labels + labels.take(slice(7))).save(out / "data.npz")  # and labels of a round never finished
    main(["--out", str(out), "--resume", "--rounds", "3", "--no-progress"])
    rounds = [json.loads(line) for line in log.read_text().splitlines()]
    assert [r["round"] for r in rounds] == [0, 1, 2]
    assert rounds[2]["states"] == rounds[1]["states"] + rounds[2]["labelled"] == len(Labels.load(out / "data.npz"))
    with pytest.raises(SystemExit, match="--epochs cannot change on --resume"):
        main(["--out", str(out), "--resume", "--epochs", "3"])
    with pytest.raises(SystemExit, match="already holds"):
        main(["--policy", str(WALK_POLICY), "--clips", "deepmimic:walk", "--out", str(out), "--no-progress"])
    with pytest.raises(SystemExit, match="no expert iteration to resume"):
        main(["--out", str(tmp_path / "none"), "--resume"])


def test_a_corrupted_task_is_searched_on_its_corrupted_reference_judged_as_asked(walk_policy, walk):
    task = SearchTask(walk, 0, seed=4, strength=0.3)  # the walk policy, trained on clean takes, falls at 0.5
    small = SearchConfig(beam=4, samples=8)
    adapt = search_labels(walk_policy, task, ExpertIterationConfig(search=small))
    clean = search_labels(walk_policy, task, ExpertIterationConfig(search=small, judge="clean"))
    assert adapt["labelled"] == clean["labelled"] == 150
    # the first observation is the corrupted reference's start, whatever the judge
    np.testing.assert_array_equal(adapt["obs"][0], clean["obs"][0])
    env = walk_policy.make_env([walk], artefacts=None)
    assert not np.allclose(env.reset(options={"clip": 0, "start_frame": 0})[0], adapt["obs"][0])
    # judged differently, the searches keep different lineages
    assert not np.allclose(adapt["actions"], clean["actions"])
    with pytest.raises(ValueError, match="judge must be one of"):
        ExpertIterationConfig(judge="oracle")
