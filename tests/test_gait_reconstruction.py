"""Gait reconstruction (issue: MimicGait-v0): the pure metrics on hand-made cases, and the command
end to end on a real clip with a tiny policy."""

import json
import math

import numpy as np
import pytest

from agents.gait_metrics import (contact_f1, forward_displacement_error, joint_angle_rmse_deg, simulated_contacts,
                                 summarize_push_offs, toe_push_off)
from reference_motion.library import load_motion


def test_joint_angle_rmse_by_hand():
    ref = np.zeros((2, 3))
    sim = np.array([[math.radians(3), 0, 0], [math.radians(-3), 0, 0]])  # 3° on one of 3 hinges
    assert joint_angle_rmse_deg(sim, ref) == pytest.approx(math.sqrt(9 / 3))
    with pytest.raises(ValueError, match=r"\(T, H\)"):
        joint_angle_rmse_deg(sim, ref[:1])


def test_contact_f1_by_hand():
    targets = np.array([[1, 0, 1, 0], [1, 1, 0, 0]], bool)
    sim = np.array([[1, 0, 0, 0], [1, 1, 0, 1]], bool)  # tp 3, one miss, one false alarm: 6 / 8
    assert contact_f1(sim, targets) == pytest.approx(0.75)
    assert contact_f1(np.zeros((3, 4), bool), np.zeros((3, 4), bool)) == 1.0


def test_toe_push_off_by_hand():
    target = np.zeros((20, 2))
    target[5:10, 0] = np.radians([10, 20, 30, 42, 21])  # left: peak 42° at frame 8
    sim = np.zeros((20, 2))
    sim[5:10, 0] = np.radians([5, 10, 20, 30, 35])  # simulated peak 35° at frame 9
    pushes = toe_push_off(sim, target)
    assert len(pushes) == 1 and (pushes[0].foot, pushes[0].start, pushes[0].stop) == (0, 5, 10)
    assert pushes[0].target_peak_deg == pytest.approx(42) and pushes[0].target_peak_frame == 8
    assert pushes[0].peak_deg == pytest.approx(35) and pushes[0].peak_frame == 9
    summary = summarize_push_offs(pushes, fps=60.0)
    assert summary.count == 1 and summary.timing_ms == pytest.approx(1000 / 60)
    assert math.isnan(summarize_push_offs([], 60.0).peak_deg)


def test_forward_displacement_error_by_hand():
    ref = np.array([[0, 0, 0.9], [2.0, 0, 0.9]])
    assert forward_displacement_error(np.array([[0, 0, 0.9], [1.9, 0, 0.8]]), ref) == pytest.approx(0.05)
    assert forward_displacement_error(ref, np.zeros((2, 3))) == math.inf


def test_simulated_contacts_of_a_standing_pose_and_a_lifted_one():
    walk = load_motion("deepmimic:walk", "humanoid_2seg")
    poses = walk.qpos[:2].copy()
    poses[0, 2] -= 0.03  # pressed 3 cm into the floor: the stance foot's sole touches
    poses[1, 2] += 0.5   # lifted half a metre: nothing touches
    contacts = simulated_contacts(walk.with_qpos(poses))
    assert contacts[0].any() and not contacts[1].any()


def test_reconstruct_gait_end_to_end(tmp_path):
    from agents.reconstruct_gait import main as reconstruct
    from agents.train_ppo import main as train
    run = tmp_path / "run"
    train(["--env-id", "MimicGait-v0", "--clips", "deepmimic:walk", "--total-steps", "128", "--run-dir", str(run),
           "--no-progress", "--n-envs", "1", "--n-steps", "128", "--batch-size", "64", "--eval-every", "128",
           "--eval-episodes", "1", "--net", "16,16"])
    out = tmp_path / "walk.npz"
    strip = tmp_path / "push_off.png"
    report = reconstruct(["deepmimic:walk", "--policy", str(run / "best"), "--no-adapt", "--out", str(out),
                          "--json", str(tmp_path / "walk.json"), "--push-off-strip", str(strip)])
    assert out.exists() and json.loads((tmp_path / "walk.json").read_text())["frames"] == report["frames"] == 76
    assert 0.0 <= report["contact_f1"] <= 1.0 and report["joint_rmse_deg"] > 0.0
    assert report["push_off"]["count"] >= 1 and report["push_off"]["target_peak_deg"] > 20
    import imageio.v2 as imageio
    assert imageio.imread(strip).shape == (240, 7 * 320, 3)  # seven close-ups of the feet
    assert set(report["gait_parameters"]["targets"]) >= {"stance", "swing", "single_support", "double_support"}
    with pytest.raises(SystemExit, match="gait reconstruction needs a MimicGait-v0 policy"):
        reconstruct(["deepmimic:walk", "--policy", "models/mimic_walk", "--no-adapt", "--out", str(out)])


def test_gait_reconstruction_adapts_per_sequence_by_default_and_clean_does_not():
    from agents.clean import build_parser as clean_parser
    from agents.reconstruct_gait import GAIT_ADAPTATION, build_parser
    gait = build_parser().parse_args(["deepmimic:walk", "--policy", "models/mimic_gait", "--out", "o.npz"])
    assert (gait.adapt_target, gait.adapt_budget_s, gait.adapt_variance, gait.adapt_lr, gait.adapt_keep) == (
        None, 1200.0, 0.03, None, "performance")
    assert GAIT_ADAPTATION.target_sr90 is None
    told = build_parser().parse_args(["deepmimic:walk", "--policy", "p", "--out", "o.npz", "--adapt-target", "0.9",
                                      "--adapt-budget-s", "60"])
    assert (told.adapt_target, told.adapt_budget_s) == (0.9, 60.0)
    clean = clean_parser().parse_args(["deepmimic:walk", "--policy", "models/mimic_walk", "--out", "o.npz"])
    assert (clean.adapt_target, clean.adapt_budget_s, clean.adapt_variance, clean.adapt_keep) == (
        0.9, 300.0, None, "performance")


def test_a_gait_policy_under_an_ablation_adapts_in_the_ablated_task(tmp_path):
    """MimicPolicy.ablated: the same weights in ContactVision Fig. 12's ablated tasks (no contact
    reward; toe targets 0); adapting the copy fine-tunes it there and caches it apart from the policy."""
    from agents.adaptation import AdaptConfig, adapt_policy, adaptation_key
    from agents.policy import PolicyError, load_policy

    full = load_policy("models/mimic_gait_ff")
    reference = load_motion("deepmimic:walk", "humanoid_2seg")
    tasks = {name: policy.make_env([reference], artefacts=None).unwrapped
             for name, policy in (("full", full), ("no_fc", full.ablated("no_fc")),
                                  ("no_toeref", full.ablated("no_toeref")))}
    assert [t.gait_config.w_fc for t in tasks.values()] == [0.3, 0.0, 0.3]
    assert np.degrees(tasks["full"].toe_targets[0].max()) > 20 and not tasks["no_toeref"].toe_targets[0].any()
    keys = {adaptation_key(reference, p) for p in (full, full.ablated("no_fc"), full.ablated("no_toeref"))}
    assert len(keys) == 3  # an ablated adaptation never comes back from the cache as the full one
    adapted = adapt_policy(full.ablated("no_fc"), reference,
                           AdaptConfig(budget_s=120, target_sr90=None, max_steps=1024, chunk_steps=1024, n_envs=2,
                                       n_steps=256, eval_episodes=1, cache_dir=tmp_path), progress=False)
    assert adapted.steps == 1024 and adapted.policy.record.env.gait_config().w_fc == 0.0
    assert adapted.policy.record.extra["ablation"] == "no_fc"
    with pytest.raises(PolicyError, match="gait ablations apply to MimicGait-v0"):
        load_policy("models/mimic_walk").ablated("no_fc")
    with pytest.raises(PolicyError, match=r"unknown gait ablation 'no_feet'; expected one of \('no_fc', 'no_toeref'\)"):
        full.ablated("no_feet")
    with pytest.raises(PolicyError, match="already in an ablated task"):
        adapted.policy.ablated("no_toeref")  # ablations are compared one at a time, not stacked
