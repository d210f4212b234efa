import numpy as np
import pytest

from agents.metrics import episode_length_ratio, max_reward_ratio, progress_ratio, root_displacement_error, survived


def test_rollout_metrics_on_a_hand_made_rollout():
    assert episode_length_ratio(150, 300) == 0.5
    assert survived(270, 300) == 1.0 and survived(269, 300) == 0.0
    root = np.zeros((4, 3))
    ref = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.3]])
    assert root_displacement_error(root, ref) == pytest.approx((0.01 + 0.04 + 0.09) / 4)
    assert max_reward_ratio(np.full(75, 1.5), 150) == pytest.approx(0.25)  # 75 x 1.5 / (3 x 150)
    assert max_reward_ratio(np.full(75, 0.5), 150, max_step_reward=1.0) == pytest.approx(0.25)  # MimicGait-v0


def test_progress_ratio_on_hand_made_paths():
    ref = np.array([[0.0, 0, 0.9], [1.0, 1.0, 0.9], [3.0, 4.0, 0.95]])  # 5 m along (0.6, 0.8)
    behind = np.array([[0.1, 0, 0.9], [0.5, 0.5, 0.9], [2.5, 3.2, 0.9]])  # (2.4, 3.2): 4 m of the 5
    assert progress_ratio(behind, ref) == pytest.approx(0.8)
    sideways = np.array([[0.0, 0, 0.9], [0, 0, 0.9], [-4.0, 3.0, 0.9]])  # across the way: no progress
    assert progress_ratio(sideways, ref) == pytest.approx(0.0)
    assert progress_ratio(ref[::-1], ref) == pytest.approx(-1.0)
    assert np.isnan(progress_ratio(ref, np.zeros((3, 3))))  # a reference standing still


def test_rollout_metrics_reject_bad_input():
    with pytest.raises(ValueError, match="reference_frames"):
        episode_length_ratio(3, 0)
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        root_displacement_error(np.zeros((3, 3)), np.zeros((4, 3)))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        progress_ratio(np.zeros((3, 2)), np.zeros((3, 2)))


def test_per_clip_table_on_hand_made_rollouts():
    from agents.evaluation import Rollout, per_clip

    def run(clip: str, elr: float) -> Rollout:
        return Rollout(clip=clip, start_frame=0, elr=elr, sr90=float(elr >= 0.9), rde=0.0, mrr=0.0,
                       ended_by="", simulated=None, reference=None)

    rows = per_clip([run("walk", 1.0), run("back", 0.2), run("walk", 0.8), run("back", 0.4), run("run", 0.95)])
    assert [r["clip"] for r in rows] == ["back", "walk", "run"]
    assert rows[0] == {"clip": "back", "rollouts": 2, "ELR": pytest.approx(0.3), "SR90": 0.0}
    assert rows[1]["ELR"] == pytest.approx(0.9) and rows[1]["SR90"] == 0.5
