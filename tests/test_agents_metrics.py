import numpy as np
import pytest

from agents.metrics import episode_length_ratio, max_reward_ratio, root_displacement_error, survived


def test_rollout_metrics_on_a_hand_made_rollout():
    assert episode_length_ratio(150, 300) == 0.5
    assert survived(270, 300) == 1.0 and survived(269, 300) == 0.0
    root = np.zeros((4, 3))
    ref = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.3]])
    assert root_displacement_error(root, ref) == pytest.approx((0.01 + 0.04 + 0.09) / 4)
    assert max_reward_ratio(np.full(75, 1.5), 150) == pytest.approx(0.25)  # 75 x 1.5 / (3 x 150)
    assert max_reward_ratio(np.full(75, 0.5), 150, max_step_reward=1.0) == pytest.approx(0.25)  # MimicGait-v0


def test_rollout_metrics_reject_bad_input():
    with pytest.raises(ValueError, match="reference_frames"):
        episode_length_ratio(3, 0)
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        root_displacement_error(np.zeros((3, 3)), np.zeros((4, 3)))


def test_per_clip_table_on_hand_made_rollouts():
    from agents.evaluation import Rollout, per_clip

    def run(clip: str, elr: float) -> Rollout:
        return Rollout(clip=clip, start_frame=0, elr=elr, sr90=float(elr >= 0.9), rde=0.0, mrr=0.0,
                       ended_by="", simulated=None, reference=None)

    rows = per_clip([run("walk", 1.0), run("back", 0.2), run("walk", 0.8), run("back", 0.4), run("run", 0.95)])
    assert [r["clip"] for r in rows] == ["back", "walk", "run"]
    assert rows[0] == {"clip": "back", "rollouts": 2, "ELR": pytest.approx(0.3), "SR90": 0.0}
    assert rows[1]["ELR"] == pytest.approx(0.9) and rows[1]["SR90"] == 0.5
