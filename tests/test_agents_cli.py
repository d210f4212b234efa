"""evaluate.py, clean.py and policy loading with a tiny policy trained here (a few seconds)."""

import json
import shutil
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest

from agents import clean, evaluate, evaluation
from agents.evaluation import evaluate_tracking, rollout, zero_policy
from agents.policy import PolicyError, load_policy
from agents.train_ppo import main as train
from envs.config import MODELS_DIR, MimicConfig
from perception.imu_denoiser import DEFAULT_DENOISER, STANCES_DENOISER, denoise
from perception.weights import shared_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.bvh import load as load_bvh
from reference_motion.cli import UsageError
from reference_motion.motion import Motion


@pytest.fixture(scope="module")
def policy_dir(tmp_path_factory):
    run = tmp_path_factory.mktemp("run")
    train(["--run-dir", str(run), "--no-progress", "--clips", "deepmimic:walk", "--total-steps", "256",
           "--n-envs", "2", "--n-steps", "128", "--batch-size", "64", "--eval-every", "256", "--eval-episodes", "1",
           "--net", "16,16"])
    return run / "best"


def test_evaluate_reports_adapt_metrics_and_artefacts(policy_dir, tmp_path):
    out = tmp_path / "eval.json"
    result = evaluate.main(["--policy", str(policy_dir), "--clips", "deepmimic:walk", "--episodes", "3",
                            "--corrupt", "imu", "--strength", "0.5", "--seed", "1000", "--json", str(out)])
    saved = json.loads(out.read_text())
    assert saved["rollouts"] == 3 and result["rollouts"] == 3
    for key in ("ELR_mean", "ELR_std", "SR90", "RDE_mean", "MRR_mean"):
        assert np.isfinite(saved[key])
    assert 0 < saved["ELR_mean"] <= 1 and 0 <= saved["SR90"] <= 1
    for metric in ("foot_skate_mps", "penetration_max_m", "floating_m", "jitter", "self_penetration_frac"):
        assert set(saved["artefacts"][metric]) == {"input", "output", "reduction"}
    assert saved["artefacts"]["jitter"]["input"] > 0 and saved["corrupt"] == "imu"
    [row] = saved["per_clip"]  # one clip: its row is the whole evaluation
    assert row["rollouts"] == 3 and row["ELR"] == pytest.approx(saved["ELR_mean"])
    quieter = evaluate.main(["--policy", str(policy_dir), "--clips", "deepmimic:walk", "--episodes", "3",
                             "--corrupt", "imu", "--without", "jitter", "noise", "--strength", "0.5", "--seed", "1000"])
    assert quieter["without"] == ["jitter", "noise"]
    assert quieter["artefacts"]["jitter"]["input"] < saved["artefacts"]["jitter"]["input"]
    with pytest.raises(SystemExit, match="it switches kinds off in --corrupt imu; got --corrupt skate"):
        evaluate.main(["--policy", str(policy_dir), "--clips", "deepmimic:walk", "--corrupt", "skate",
                       "--without", "noise"])


def test_evaluate_through_the_denoiser_judges_against_the_clip_as_given(policy_dir):
    """--denoise: the policy mimics the denoised clip, but each rollout is judged against, and its
    input artefacts and RDE measured on, the corrupted clip as given."""
    result = evaluate.main(["--policy", str(policy_dir), "--clips", "deepmimic:walk", "--episodes", "2",
                            "--corrupt", "imu", "--seed", "1000", "--denoise"])
    assert result["denoiser"] == str(DEFAULT_DENOISER) and result["rollouts"] == 2
    policy = load_policy(policy_dir)
    [given] = evaluate.reference_clips(["deepmimic:walk"], "humanoid_1seg", MimicConfig(), "imu", 1.0, 1000)
    performed = denoise(shared_network(str(DEFAULT_DENOISER), "denoiser"), given)
    env = policy.make_env([performed], artefacts=None, judged_clips=[given])
    env.reset(seed=0)
    run = rollout(env, policy, 0, 0)
    np.testing.assert_array_equal(run.reference.qpos, given.qpos[:run.reference.n_frames])
    np.testing.assert_array_equal(env.unwrapped.current_track.motion.qpos, performed.qpos)
    summary, runs = evaluate_tracking(policy, [performed], [given], episodes=2)
    assert summary["ELR_mean"] == pytest.approx(result["ELR_mean"])  # the CLI took this very path
    np.testing.assert_array_equal(runs[0].reference.qpos, given.qpos[:runs[0].reference.n_frames])
    still = zero_policy(env.action_space.shape[0])  # another actor in the policy's environment
    _, acted = evaluate_tracking(policy, [performed], [given], episodes=2, actor=still)
    env.reset(seed=0)
    _, by_hand = evaluation.evaluate(env, still, episodes=2)
    assert [r.elr for r in acted] == [r.elr for r in by_hand]
    np.testing.assert_array_equal(acted[0].simulated.qpos, by_hand[0].simulated.qpos)
    assert not np.array_equal(acted[0].simulated.qpos, runs[0].simulated.qpos[:acted[0].simulated.n_frames])
    prepared = []  # (model, its torque limits as they were)

    def weaken(env):  # prepare_env: the environment's body given 5% of its torques before the first reset
        model = env.unwrapped.model
        prepared.append((model, model.actuator_forcerange.copy()))
        model.actuator_forcerange[:] *= 0.05

    try:
        _, weak = evaluate_tracking(policy, [performed], [given], episodes=2, prepare_env=weaken)
    finally:  # the model may be the one every environment of the humanoid shares
        for model, limits in prepared:
            model.actuator_forcerange[:] = limits
    assert len(prepared) == 1 and all(w.elr < r.elr for w, r in zip(weak, runs, strict=True))
    _, again = evaluate_tracking(policy, [performed], [given], episodes=2)
    assert [r.elr for r in again] == [r.elr for r in runs]  # the shared model as it was


def test_clean_writes_a_motion_of_the_same_length(policy_dir, tmp_path):
    """Zero-shot (adaptation: tests/test_clean.py): a barely trained policy fails often, and every
    failure ends in a retry or a re-anchor, never in frames copied from the reference."""
    result = clean.main(["deepmimic:walker/turn_left0", "--policy", str(policy_dir), "--out", str(tmp_path / "c.npz"),
                         "--bvh", str(tmp_path / "c.bvh"), "--no-adapt"])
    cleaned = Motion.load(tmp_path / "c.npz")
    assert cleaned.n_frames == 75 and cleaned.fps == 60.0 and cleaned.name.endswith("(cleaned)")
    assert cleaned.source["reanchors"] == result["reanchors"] and np.isfinite(cleaned.qpos).all()
    assert cleaned.source["simulated_fraction"] == result["simulated_fraction"] == 1 - len(result["reanchors"]) / 74
    assert "kinematic_frames" not in cleaned.source
    assert load_bvh(tmp_path / "c.bvh").n_frames == 75
    assert set(result["input"]) >= {"foot_skate_mps", "jitter"}


def test_clean_can_denoise_an_imu_take_first(policy_dir, tmp_path):
    """--denoise: the policy re-performs the denoised take; the input metrics are the take as given."""
    args = ["deepmimic:walker/turn_left0", "--policy", str(policy_dir), "--no-adapt", "--search", "off",
            "--corrupt", "imu", "--seed", "3"]
    plain = clean.main(args + ["--out", str(tmp_path / "plain.npz")])
    denoised = clean.main(args + ["--out", str(tmp_path / "denoised.npz"), "--denoise"])
    assert plain["denoiser"] is None and denoised["denoiser"] == str(DEFAULT_DENOISER)
    assert denoised["input"] == plain["input"]
    assert not np.allclose(Motion.load(tmp_path / "plain.npz").qpos, Motion.load(tmp_path / "denoised.npz").qpos)
    with pytest.raises(SystemExit):
        clean.main(args + ["--out", str(tmp_path / "d.npz"), "--method", "diffpd", "--denoise"])


def test_a_preset_stands_for_its_policy_and_flags_and_given_flags_win():
    """--preset fills --policy and the preparation flags (clean.PRESETS); what the command line
    gives wins; no policy and no preset, or a preset with diffpd, is the parser's error."""
    def parsed(*argv):
        return clean.parse_clean_args(clean.build_parser(), ["deepmimic:walk", "--out", "c.npz", *argv])

    imu = parsed("--preset", "imu")
    assert imu.policy == MODELS_DIR / "mimic_general_expert_set" and imu.denoise == STANCES_DENOISER
    assert (imu.denoise_slow, imu.even_legs, imu.part_legs, imu.ground) == (None, True, 0.15, True)
    assert (imu.swing_lift, imu.mirror_average, imu.no_adapt) == (15.0, True, True)
    optical = parsed("--preset", "optical")
    assert optical.policy == MODELS_DIR / "mimic_general_stance_avg" and optical.denoise is None
    assert (optical.even_legs, optical.part_legs, optical.ground, optical.mirror_average) == (False, None, True, True)
    assert (optical.denoise_slow, optical.swing_lift, optical.no_adapt) == (None, 15.0, True)
    options = {action.dest for action in clean.build_parser()._actions}
    assert all(set(asdict(preset)) <= options for preset in clean.PRESETS.values())  # every field is a flag
    mine = parsed("--preset", "imu", "--policy", "models/mimic_walk", "--denoise-slow", "1.0", "--part-legs", "0.2")
    assert (mine.policy, mine.denoise_slow, mine.part_legs) == ("models/mimic_walk", 1.0, 0.2)
    assert mine.denoise == STANCES_DENOISER and mine.even_legs  # the rest of the preset still holds
    plain = parsed("--policy", "models/mimic_walk")
    assert (plain.preset, plain.denoise, plain.ground, plain.mirror_average, plain.no_adapt) == (None, None, False, False, False)
    assert clean.cleans_as_preset(imu) and clean.cleans_as_preset(optical)
    assert not clean.cleans_as_preset(mine) and not clean.cleans_as_preset(plain)
    assert not clean.cleans_as_preset(parsed("--preset", "imu", "--denoise-slow", "0.5"))
    assert not clean.cleans_as_preset(parsed("--preset", "imu", "--swing-from", "speed"))
    assert clean.cleans_as_preset(parsed("--preset", "imu", "--policy", str(MODELS_DIR / "mimic_general_expert_set"),
                                         "--denoise", str(STANCES_DENOISER)))  # the preset's own, restated
    with pytest.raises(UsageError, match="required: --policy \\(or --preset\\)"):
        parsed()
    with pytest.raises(UsageError, match="--preset imu cleans with a PPO policy; it goes with --method ppo"):
        parsed("--preset", "imu", "--method", "diffpd")
    with pytest.raises(UsageError, match="invalid choice: 'marker'"):
        parsed("--preset", "marker")


def test_the_imu_preset_cleans_as_its_flags_do(tmp_path, capsys):
    """clean.py --preset imu performs an IMU take exactly as the flags it stands for do, with the
    shipped policy set validation chose for IMU takes, and records the preset; the note on a
    preparation unlike the policy's training is left to the flags given by hand (the turning expert
    trained behind slowed corrections; validation gives it the whole ones)."""
    take = ["deepmimic:walker/turn_left0", "--corrupt", "imu", "--seed", "3", "--search", "off"]
    preset = clean.main(take + ["--preset", "imu", "--out", str(tmp_path / "preset.npz")])
    assert "note:" not in capsys.readouterr().out
    flags = clean.main(take + ["--policy", "models/mimic_general_expert_set", "--denoise", str(STANCES_DENOISER),
                               "--even-legs",
                               "--part-legs", "--ground", "--swing-lift", "--mirror-average", "--no-adapt",
                               "--out", str(tmp_path / "flags.npz")])
    assert "was trained on references behind the denoiser's corrections slowed to 0.5 s" in capsys.readouterr().out
    np.testing.assert_array_equal(Motion.load(tmp_path / "preset.npz").qpos, Motion.load(tmp_path / "flags.npz").qpos)
    assert preset["preset"] == "imu" and flags["preset"] is None and preset["adaptation"] is None
    assert preset["policy"] == flags["policy"] == "models/mimic_general_expert_set"  # recorded from the repository root
    assert preset["denoiser"] == str(STANCES_DENOISER) and preset["denoise_slow_s"] is None and preset["mirror_average"]
    assert preset["simulated_fraction"] == 1.0 and not preset["reanchors"]


def test_clean_can_lift_the_backward_steps_first(policy_dir, tmp_path, walk):
    """--swing-lift: the policy re-performs the take with its backward steps' knees lifted in swing;
    the input metrics are the take as given; with diffpd it is refused."""

    from reference_motion.swing_lift import SwingLift
    from reference_motion.transforms import reversed_in_time
    take = reversed_in_time(walk).save(tmp_path / "walked_backward.npz")
    args = [str(take), "--policy", str(policy_dir), "--no-adapt", "--search", "off"]
    plain = clean.main(args + ["--out", str(tmp_path / "plain.npz")])
    lifted = clean.main(args + ["--out", str(tmp_path / "lifted.npz"), "--swing-lift", "12", "--swing-from", "speed"])
    assert plain["swing_lift"] is None
    assert lifted["swing_lift"] == asdict(SwingLift(knee_deg=12.0, swing_from="speed"))
    assert lifted["input"] == plain["input"]
    assert not np.allclose(Motion.load(tmp_path / "plain.npz").qpos, Motion.load(tmp_path / "lifted.npz").qpos)
    with pytest.raises(SystemExit):
        clean.main(args + ["--out", str(tmp_path / "d.npz"), "--method", "diffpd", "--swing-lift"])


def test_clean_can_set_the_take_on_the_floor_first(policy_dir, tmp_path, walk):
    """--ground: the policy re-performs the take set on the floor; the input metrics are the take as
    given (floating 5 cm); the JSON records the grounding; with diffpd it is refused."""

    from reference_motion.grounding import Grounding
    qpos = walk.qpos.copy()
    qpos[:, 2] += 0.05
    take = walk.with_qpos(qpos).save(tmp_path / "floating.npz")
    args = [str(take), "--policy", str(policy_dir), "--no-adapt", "--search", "off"]
    plain = clean.main(args + ["--out", str(tmp_path / "plain.npz")])
    grounded = clean.main(args + ["--out", str(tmp_path / "grounded.npz"), "--ground"])
    assert plain["grounding"] is None and grounded["grounding"] == asdict(Grounding())
    assert grounded["input"] == plain["input"] and plain["input"]["floating_m"] > 0.04
    assert not np.allclose(Motion.load(tmp_path / "plain.npz").qpos, Motion.load(tmp_path / "grounded.npz").qpos)
    with pytest.raises(SystemExit):
        clean.main(args + ["--out", str(tmp_path / "d.npz"), "--method", "diffpd", "--ground"])


def test_evaluate_and_clean_can_even_the_legs_first(policy_dir, tmp_path, walk):
    """--even-legs: the JSON names the actor that mimics the take with its legs evened and records
    the settings (that it is judged against the take as given: tests/test_leg_symmetry.py); clean.py
    prepares the take the same way, and refuses it with diffpd."""

    from reference_motion.leg_symmetry import LegSymmetry
    imu = ["--clips", "deepmimic:walk", "--episodes", "2", "--corrupt", "imu", "--seed", "1000"]
    plain = evaluate.main(["--policy", str(policy_dir), *imu])
    evened = evaluate.main(["--policy", str(policy_dir), *imu, "--even-legs"])
    assert plain["leg_symmetry"] is None and evened["leg_symmetry"] == asdict(LegSymmetry())
    assert evened["policy"] == f"{policy_dir} + legs evened"
    assert evened["rollouts"] == plain["rollouts"] == 2
    take = corrupt(walk, ArtefactRecipe.imu(1.0), 1000).save(tmp_path / "imu.npz")
    args = [str(take), "--policy", str(policy_dir), "--no-adapt", "--search", "off"]
    cleaned = clean.main(args + ["--out", str(tmp_path / "evened.npz"), "--even-legs"])
    assert cleaned["leg_symmetry"] == asdict(LegSymmetry())
    with pytest.raises(SystemExit):
        clean.main(args + ["--out", str(tmp_path / "d.npz"), "--method", "diffpd", "--even-legs"])


def test_slowed_corrections_are_refused_without_a_denoiser_or_a_positive_time(walk, tmp_path):
    take = str(walk.save(tmp_path / "walk.npz"))
    with pytest.raises(SystemExit, match="--denoise-slow: expected a positive number"):
        evaluate.main(["--policy", "models/mimic_walk", "--clips", "deepmimic:walk", "--denoise-slow", "-1"])
    with pytest.raises(SystemExit, match="--denoise-slow 0.5 slows a denoiser's corrections: give --denoise too"):
        evaluate.main(["--policy", "models/mimic_walk", "--clips", "deepmimic:walk", "--denoise-slow"])
    with pytest.raises(SystemExit, match="--denoise-slow 0.5 slows a denoiser's corrections: give --denoise too"):
        clean.main([take, "--policy", "models/mimic_walk", "--out", str(tmp_path / "c.npz"), "--denoise-slow"])


def test_the_symmetric_actor_evaluates_and_cleans(policy_dir, tmp_path):
    """--mirror-average: evaluate.py names the actor and scores it otherwise than the policy as it is;
    clean.py re-performs with it (a different simulation) and records it; with diffpd it is refused.
    Its stochastic actions are its symmetric action plus the policy's own Gaussian noise."""
    from agents.policy import load_policy
    from agents.rollout import sampling_policy, seeded
    args = ["--policy", str(policy_dir), "--clips", "deepmimic:walker/turn_left0", "--episodes", "2"]
    plain, symmetric = evaluate.main(args), evaluate.main(args + ["--mirror-average"])
    assert symmetric["policy"] == f"{policy_dir} (mirror-averaged)" and symmetric["mirror_average"]
    assert plain["RDE_mean"] != symmetric["RDE_mean"]
    cleaning = ["deepmimic:walker/turn_left0", "--policy", str(policy_dir), "--no-adapt", "--search", "off"]
    a = clean.main(cleaning + ["--out", str(tmp_path / "a.npz")])
    b = clean.main(cleaning + ["--out", str(tmp_path / "b.npz"), "--mirror-average"])
    assert not a["mirror_average"] and b["mirror_average"]
    assert Motion.load(tmp_path / "b.npz").source["cleaned_by"] == f"{policy_dir} (mirror-averaged)"
    assert not np.allclose(Motion.load(tmp_path / "a.npz").qpos, Motion.load(tmp_path / "b.npz").qpos)
    with pytest.raises(SystemExit):
        clean.main(cleaning + ["--out", str(tmp_path / "d.npz"), "--method", "diffpd", "--mirror-average"])
    policy = load_policy(policy_dir)
    env = policy.make_env(["deepmimic:walker/turn_left0"], artefacts=None)
    obs, _ = env.reset(seed=0)
    actor = policy.mirror_averaged(env)
    with seeded(0):
        draws = np.array([sampling_policy(actor)(obs) for _ in range(2000)])
    std = policy.model.policy.log_std.detach().exp().numpy()
    np.testing.assert_allclose(draws.mean(0), actor(obs), atol=4 * std.max() / np.sqrt(2000))
    np.testing.assert_allclose(draws.std(0), std, rtol=0.1)
    assert np.abs(actor(obs) - policy(obs)).max() > 1e-3
    from agents.adaptation import adapt_policy
    from reference_motion.library import load_motion
    with pytest.raises(ValueError, match="adaptation trains the network itself"):
        adapt_policy(actor, load_motion("deepmimic:walker/turn_left0"))


def test_bad_or_mismatched_policy_files_give_clear_errors(policy_dir, tmp_path):
    with pytest.raises(PolicyError, match="no such policy file"):
        load_policy(tmp_path / "nowhere")
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "model.zip").write_text("not a zip")
    with pytest.raises(PolicyError, match="not a stable-baselines3 model"):
        load_policy(broken)
    no_stats = tmp_path / "no_stats"
    shutil.copytree(policy_dir, no_stats)
    (no_stats / "model_vecnormalize.pkl").unlink()
    with pytest.raises(PolicyError, match="observation statistics"):
        load_policy(no_stats)
    other_foot = tmp_path / "other_foot"
    shutil.copytree(policy_dir, other_foot)
    sidecar = json.loads((other_foot / "sidecar.json").read_text())
    sidecar["env"]["foot"] = "two"  # the typed sidecar's environment (agents/sidecar.py)
    (other_foot / "sidecar.json").write_text(json.dumps(sidecar))
    with pytest.raises(SystemExit, match=r"expects observations \(273,\).*\(297,\)"):
        evaluate.main(["--policy", str(other_foot), "--clips", "deepmimic:walk", "--episodes", "1"])


def test_shipped_walk_policy_walks(tmp_path):
    """models/mimic_walk loads with evaluate.py and re-performs walk (README: 20 rollouts)."""
    result = evaluate.main(["--policy", str(Path(__file__).parents[1] / "models" / "mimic_walk"), "--clips", "deepmimic:walk", "--episodes", "3",
                            "--offset-step", "10"])
    assert result["ELR_mean"] > 0.9 and result["SR90"] >= 2 / 3
    assert result["artefacts"]["jitter"]["output"] < result["artefacts"]["jitter"]["input"]


def test_a_policy_trained_on_prepared_takes_notes_takes_prepared_otherwise():
    """models/mimic_general_prepared trained on takes denoised, set on the floor and swing-lifted:
    takes prepared the same draw no note; each preparation missing or changed is named."""
    from reference_motion.grounding import Grounding
    from reference_motion.swing_lift import SwingLift
    policy = load_policy("models/mimic_general_prepared")
    denoiser = policy.record.training.denoiser
    assert policy.preparation_note(denoiser, Grounding(), SwingLift(knee_deg=15.0)) is None
    note = policy.preparation_note(None)
    assert note.startswith("note: models/mimic_general_prepared was trained on references passed through the IMU "
                           "denoiser models/imu_denoiser_soles_quint_mirror; these takes are not denoised (--denoise)")
    assert "set on the floor; these takes are not (--ground)" in note
    assert "lifted in backward swing (15.0°); these takes are not (--swing-lift)" in note
    note = policy.preparation_note(denoiser, Grounding(smooth_s=0.5), SwingLift(knee_deg=15.0))
    assert note.endswith("trained on references set on the floor; these takes are set on it otherwise (--ground)")
    note = policy.preparation_note(denoiser, Grounding(), SwingLift(knee_deg=25.0))
    assert "--swing-lift" in note and "--ground" not in note and "--denoise" not in note
    # a policy trained on takes as given draws no note for takes prepared now
    assert load_policy("models/mimic_general_stance_avg").preparation_note(denoiser, Grounding(), None) is None


def test_sidecars_record_the_default_denoiser_from_the_repository_and_compare_it_from_anywhere(tmp_path, monkeypatch):
    """The bare --denoise flag gives an absolute path; a sidecar records it from the repository root,
    and a policy trained behind it draws no note for the same denoiser named from another directory."""
    from agents.sidecar import REPOSITORY, repository_relative
    from reference_motion.grounding import Grounding
    from reference_motion.swing_lift import SwingLift
    assert repository_relative(DEFAULT_DENOISER) == "models/imu_denoiser_soles_quint_mirror"
    monkeypatch.chdir(tmp_path)
    assert repository_relative("denoiser") == str((tmp_path / "denoiser").resolve())
    assert repository_relative(None) is None
    policy = load_policy(REPOSITORY / "models" / "mimic_general_prepared")
    assert policy.record.training.denoiser == "models/imu_denoiser_soles_quint_mirror"
    assert policy.preparation_note(DEFAULT_DENOISER, Grounding(), SwingLift(knee_deg=15.0)) is None
    assert "--denoise" in policy.preparation_note(tmp_path / "denoiser", Grounding(), SwingLift(knee_deg=15.0))


def test_recorded_settings_are_compared_where_the_sidecar_has_them():
    from agents.policy import recorded_as
    from reference_motion.grounding import Grounding
    recorded = json.loads(json.dumps(asdict(Grounding())))
    del recorded["smooth_s"]  # a sidecar written before the field existed
    assert recorded_as(recorded, Grounding()) and recorded_as(recorded, Grounding(smooth_s=9.0))
    recorded["quality"]["contact_height"] = 0.05  # nested settings count
    assert not recorded_as(recorded, Grounding()) and not recorded_as(recorded, None)
