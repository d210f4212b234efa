"""agents/train_ppo.py end to end on a tiny budget: checkpoints, evaluation, best model, resume."""

import argparse
import json
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np
import pytest
import torch
from stable_baselines3 import PPO

from agents.policy import PolicyError, load_policy, mlp_mean_action
from agents.train_ppo import (build_parser, changed_settings, deferred_signals, env_kwargs, main, newest_checkpoint,
                              posture_ranges, recorded_progress, run_args, stance_extra, training_motions,
                              warped_clips)
from agents.warm_start import FIRST_LAYERS, widen_hidden, widen_inputs, widen_statistics
from envs.config import ArtefactMix, MimicConfig
from reference_motion.cli import UsageError
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.humanoid.model import load_model
from reference_motion.swing_lift import SwingLift
from reference_motion.transforms import PostureRanges

WALK_POLICY = Path(__file__).parents[1] / "models" / "mimic_walk"


def test_train_checkpoint_evaluate_and_resume(tmp_path, capsys):
    run = tmp_path / "run"
    common = ["--run-dir", str(run), "--no-progress", "--n-envs", "2", "--n-steps", "128", "--batch-size", "64",
              "--checkpoint-every", "256", "--eval-every", "256", "--eval-episodes", "1", "--net", "32,32"]
    main(["--clips", "deepmimic:walk", "--total-steps", "512", *common])
    assert newest_checkpoint(run).name == "step_512.zip"
    assert (run / "best" / "model.zip").exists() and (run / "best" / "model_vecnormalize.pkl").exists()
    sidecar = json.loads((run / "best" / "sidecar.json").read_text())
    assert sidecar["env_id"] == "MimicIMU-v0" and sidecar["seed"] == 0 and sidecar["steps"] in (256, 512)
    assert set(sidecar["metrics"]) >= {"ELR_mean", "SR90", "RDE_mean", "MRR_mean"} and sidecar["wall_s"] > 0
    evals = [json.loads(line) for line in (run / "evaluations.jsonl").read_text().splitlines()]
    assert [e["steps"] for e in evals] == [256, 512]
    assert 0.0 < evals[0]["ELR_mean"] <= 1.0 and "SR90" in evals[0]
    model = PPO.load(run / "best" / "model.zip", device="cpu")
    assert model.policy.log_std.detach().exp().pow(2).allclose(model.policy.log_std.new_full((20,), 0.03))
    assert tuple(model.observation_space.shape) == (273,)

    wall = json.loads((run / "wall.json").read_text())  # the wall time at the newest checkpoint
    assert wall["steps"] == 512 and wall["wall_s"] >= evals[-1]["wall_s"] > 0
    checkpoint = load_policy(newest_checkpoint(run))  # a checkpoint is a policy, in the run's environment
    assert checkpoint.record.training.steps == 512 and checkpoint.record.training.wall_s == wall["wall_s"]
    assert checkpoint.record.env == load_policy(run / "best").record.env and checkpoint.record.score is None

    main(["--run-dir", str(run), "--resume", "--total-steps", "768", "--no-progress"])  # picks up at 512
    assert newest_checkpoint(run).name == "step_768.zip"
    resumed = json.loads((run / "wall.json").read_text())
    assert resumed["steps"] == 768 and resumed["wall_s"] > wall["wall_s"]  # the resumed command adds to it
    stored = json.loads((run / "args.json").read_text())
    assert stored["net"] == "32,32"  # stored settings kept
    assert len(stored["commands"]) == 2 and "--resume" in stored["commands"][1]  # the run's whole history
    assert stored["vec"] == "batched"  # the kind it ran with, not the default of the day

    capsys.readouterr()
    main(["--run-dir", str(run), "--resume", "--total-steps", "1024", "--no-progress", "--n-envs", "4",
          "--n-steps", "32"])  # a resume may change the rollout: 4 envs × 32 steps
    said = [line for line in capsys.readouterr().out.splitlines() if line.startswith("resuming with")]
    assert said == [f"resuming with {option} changed: {change} (checkpoints from now on record the new value; "
                    "args.json's commands keep every command)"
                    for option, change in [("--n-envs", "2 -> 4"), ("--n-steps", "128 -> 32"),
                                           ("--total-steps", "768 -> 1024")]]
    resumed = PPO.load(newest_checkpoint(run), device="cpu")
    assert newest_checkpoint(run).name == "step_1024.zip" and (resumed.n_envs, resumed.n_steps) == (4, 32)
    (run / "checkpoints" / "step_1024_sidecar.json").unlink()  # as checkpoints were saved before they had one
    with pytest.raises(PolicyError, match="checkpoint without a sidecar"):
        load_policy(newest_checkpoint(run))


def test_mirror_and_speed_augmentation_of_training_clips():
    args = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walker/turn_left0", "--mirror",
                                      "--speeds", "0.9", "1.1"])
    clips = training_motions(args)
    assert [round(c.duration / clips[0].duration, 2) for c in clips] == [1.0, 0.82, 1.0, 0.82]
    assert [c.source.get("mirrored", False) for c in clips] == [False, False, True, True]
    plain = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk"])
    assert training_motions(plain) == ["deepmimic:walk"]  # no augmentation: the envs load the sources


def test_reverse_adds_the_matching_clips_played_backwards():
    args = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "deepmimic:run",
                                      "--reverse", "*:walk", "--mirror"])
    clips = training_motions(args)
    assert [c.name for c in clips] == ["deepmimic:walk", "deepmimic:walk (mirrored)", "deepmimic:run",
                                       "deepmimic:run (mirrored)", "deepmimic:walk (reversed)",
                                       "deepmimic:walk (reversed) (mirrored)"]
    np.testing.assert_array_equal(clips[4].qpos, clips[0].qpos[::-1])
    typo = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "--reverse", "*walk_*"])
    with pytest.raises(ValueError, match=r"--reverse '\*walk_\*' matches none of the 1 training clips"):
        training_motions(typo)


def test_warp_adds_the_matching_clips_at_their_own_extra_speeds():
    args = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "deepmimic:run",
                                      "--warp", "*:walk=1.25,1.5", "*walk=1.5,2", "--mirror"])
    clips = training_motions(args)
    assert [c.name for c in clips[4:]] == ["deepmimic:walk (x1.25 speed)", "deepmimic:walk (x1.5 speed)",
                                           "deepmimic:walk (x2 speed)", "deepmimic:walk (x1.25 speed) (mirrored)",
                                           "deepmimic:walk (x1.5 speed) (mirrored)",
                                           "deepmimic:walk (x2 speed) (mirrored)"]  # 1.5 once, though named twice
    walk = clips[0]
    np.testing.assert_allclose([walk.duration / c.duration for c in clips[4:7]], [1.25, 1.5, 2.0], rtol=0.005)
    assert np.isclose(abs(clips[6].qpos[-1, 0] - clips[6].qpos[0, 0]) / clips[6].duration,
                      2 * abs(walk.qpos[-1, 0] - walk.qpos[0, 0]) / walk.duration, rtol=0.02)  # twice as fast
    episode = 2 * (MimicConfig().episode_frames + 1)  # each warped copy still lasts two episodes
    assert all(c.n_frames >= episode for c in clips) and clips[2].n_frames < 2 * episode  # run: not warped, not stretched
    alone = training_motions(build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk",
                                                        "--speeds", "1.0", "1.25", "--warp", "*=1.0,1.25,1.5"]))
    assert [c.name for c in alone] == ["deepmimic:walk", "deepmimic:walk (x1.25 speed)",
                                       "deepmimic:walk (x1.5 speed)"]  # no mirror; no speed --speeds has twice
    assert warped_clips(["deepmimic:walk", "deepmimic:run"], ["*=1.1"]) == {"deepmimic:walk": [1.1],
                                                                            "deepmimic:run": [1.1]}
    with pytest.raises(ValueError, match=r"--warp '\*back\*' matches none of the 2 training clips"):
        warped_clips(["deepmimic:walk", "deepmimic:run"], ["*back*=1.5"])
    for bad in ("*walk*", "*walk*=", "=1.5", "*walk*=1.5,x", "*walk*=0", "*walk*=-1,2", "*walk*=nan"):
        with pytest.raises(UsageError, match="expected GLOB=SPEED"):
            build_parser().parse_args(["--run-dir", "unused", "--warp", bad])


def test_postures_add_seeded_copies_of_every_reference_carried_differently():
    args = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "deepmimic:run",
                                      "--mirror", "--postures", "2", "--seed", "3"])
    clips = training_motions(args)
    assert [c.name for c in clips[4:6]] == ["deepmimic:walk (posture 0)", "deepmimic:walk (posture 1)"]
    assert len(clips) == 4 * 3 and clips[-1].name == "deepmimic:run (mirrored) (posture 1)"
    postures = [np.array(c.source["posture_rad"]) for c in clips[4:]]
    assert all(np.abs(a - b).max() > 0.01 for i, a in enumerate(postures) for b in postures[:i])
    again = training_motions(args)  # a resumed run trains on the same copies
    assert all(np.array_equal(a.qpos, b.qpos) for a, b in zip(clips, again))
    other = training_motions(build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk",
                                                        "--postures", "1", "--seed", "4"]))
    assert not np.array_equal(other[1].qpos, clips[4].qpos)


def test_run_args_are_the_stored_settings_over_the_defaults(tmp_path):
    with pytest.raises(FileNotFoundError, match="no run in"):
        run_args(tmp_path)
    (tmp_path / "args.json").write_text(json.dumps({"strength": [0.75, 1.25], "variants_per_clip": 6,
                                                    "run_dir": "elsewhere"}))
    args = run_args(tmp_path)
    assert args.strength == [0.75, 1.25] and args.variants_per_clip == 6  # stored
    defaults = build_parser().parse_args(["--run-dir", "x"])
    assert args.corrupted_fraction == defaults.corrupted_fraction and args.lr == defaults.lr  # not stored: defaults
    assert args.run_dir == tmp_path  # where it is now, not where it was written
    mix = env_kwargs(args, [], 0.5)["artefacts"]  # the run's corrupted variants can be rebuilt from it
    assert mix.strength == (0.75, 1.25) and mix.variants_per_clip == 6 and mix.seed == args.seed


def test_a_resume_names_the_settings_it_changes():
    parser = build_parser()
    given = parser.parse_args(["--run-dir", "r", "--resume", "--warp", "*back*=1.5", "--strength", "0.5", "1.0",
                               "--mirror"])
    stored = {"warp": ["*back*=1.25"], "strength": [0.5, 1.0], "mirror": False, "run_dir": "elsewhere"}
    changed = changed_settings(parser, stored, given, {"warp", "strength", "mirror", "resume", "run_dir"})
    assert changed == {"--warp": (["*back*=1.25"], ["*back*=1.5"]), "--mirror": (False, True)}  # a tuple is its list


def test_train_refuses_to_overwrite_or_resume_nothing(tmp_path):
    with pytest.raises(SystemExit, match="no run in"):
        main(["--run-dir", str(tmp_path / "none"), "--resume"])
    run = tmp_path / "run"
    run.mkdir()
    (run / "args.json").write_text("{}")
    with pytest.raises(SystemExit, match="already holds a run"):
        main(["--run-dir", str(run)])
    with pytest.raises(SystemExit, match="--exclude names clips not in the training set"):
        main(["--run-dir", str(tmp_path / "x"), "--clips", "locomotion", "--exclude", "deepmimic:kick"])


def test_sidecar_reads_both_layouts_and_rebuilds_the_env():
    """The shipped walk policy has the earlier flat sidecar; the typed one round-trips."""
    from agents.policy import load_policy
    from agents.sidecar import PolicySidecar

    policy = load_policy("models/mimic_walk")
    record = policy.record
    assert record.env.env_id == "MimicIMU-v0" and record.env.foot == "one"
    assert record.ppo.lr == 1e-4 and record.ppo.net == "256,256" and record.training.clips == ["deepmimic:walk"]
    assert record.training.steps == 1_500_000 and record.metrics["SR90"] == 1.0
    again = PolicySidecar.from_dict(record.to_dict())
    assert again.env == record.env and again.ppo == record.ppo and again.training == record.training
    wide = replace(record, training=replace(record.training, stances=1, stance_extra_m=(0.1, 0.2)))
    assert PolicySidecar.from_dict(json.loads(json.dumps(wide.to_dict()))).training == wide.training  # via JSON
    env = policy.make_env(["deepmimic:walk"])
    assert env.unwrapped.config.episode_frames == 300 and env.observation_space.shape == (273,)


def test_gait_and_heading_frame_runs_record_their_task_in_the_sidecar(tmp_path):
    """--env-id MimicGait-v0 trains on humanoid_2seg by default; an ablation, the heading-frame
    observation and the PD lead are recorded, and the policy's env is rebuilt from the sidecar alone."""
    from agents.policy import load_policy
    run = tmp_path / "gait"
    main(["--env-id", "MimicGait-v0", "--gait-ablation", "no_toeref", "--obs-frame", "heading",
          "--velocity-feedforward", "--clips", "deepmimic:walk", "--total-steps", "256", "--run-dir", str(run), "--no-progress", "--n-envs", "2",
          "--n-steps", "128", "--batch-size", "64", "--eval-every", "256", "--eval-episodes", "1", "--net", "32,32"])
    policy = load_policy(run / "best")
    assert policy.record.env.foot == "two" and policy.record.env.contacts == "vgrf"
    assert policy.record.env.gait["toe_reference"] is False and policy.record.env.config["obs_frame"] == "heading"
    env = policy.make_env(["deepmimic:walk"])
    assert env.unwrapped.gait_config.toe_reference is False and env.observation_space.shape == (330,)
    assert policy.record.env.config["velocity_feedforward"] and env.unwrapped.pd_lead_s is not None
    assert not env.unwrapped.toe_targets[0].any()
    mrr = json.loads((run / "evaluations.jsonl").read_text().splitlines()[0])["MRR_mean"]
    assert 0.0 < mrr <= 1.0  # the gait reward's maximum is 1 per step, not ADAPT's 3
    with pytest.raises(SystemExit, match="--gait-ablation is an ablation of MimicGait-v0"):
        main(["--gait-ablation", "no_fc", "--run-dir", str(tmp_path / "x")])


def test_a_run_on_denoised_references_records_its_denoiser(tmp_path):
    """--denoise passes the corrupted references (training and --eval-strength evaluation) through
    the IMU denoiser; the sidecar says which, so that cleaning can denoise takes the same way."""
    from agents.policy import load_policy
    from perception.imu_denoiser import DEFAULT_DENOISER
    run = tmp_path / "denoised"
    main(["--clips", "deepmimic:walk", "--corrupted-fraction", "1", "--denoise", "--eval-strength", "1",
          "--total-steps", "256", "--run-dir", str(run), "--no-progress", "--n-envs", "2", "--n-steps", "128",
          "--batch-size", "64", "--eval-every", "256", "--eval-episodes", "1", "--net", "16,16"])
    policy = load_policy(run / "best")
    assert policy.record.training.denoiser == "models/imu_denoiser_soles_quint_mirror"  # from the repository root
    stored = argparse.Namespace(**json.loads((run / "args.json").read_text()))
    assert stored.denoise == str(DEFAULT_DENOISER)
    assert env_kwargs(stored, ["deepmimic:walk"], 1.0)["artefacts"].denoiser == str(DEFAULT_DENOISER)
    assert policy.preparation_note(DEFAULT_DENOISER) is None and "not denoised" in policy.preparation_note(None)
    with pytest.raises(SystemExit, match="this run has none"):
        main(["--clips", "deepmimic:walk", "--denoise", "--run-dir", str(tmp_path / "x")])
    with pytest.raises(SystemExit, match="an IMU denoiser for humanoid_1seg at 60 Hz; this run's environments "
                                         "simulate humanoid_2seg"):
        main(["--env-id", "MimicGait-v0", "--clips", "deepmimic:walk", "--corrupted-fraction", "0.5", "--denoise",
              "--run-dir", str(tmp_path / "y")])


def test_a_run_can_track_references_prepared_as_evaluation_prepares_takes(tmp_path):
    """--even-legs --part-legs --ground --swing-lift --judge given: every training reference has its legs evened and parted,
    is set on the floor and swing-lifted before the policy tracks it, and judged against the reference as made; the sidecar
    records the preparation, so evaluation can prepare takes the same way."""
    from agents.policy import load_policy
    run = tmp_path / "prepared"
    main(["--clips", "deepmimic:walk", "--even-legs", "--part-legs", "--ground", "--swing-lift", "--judge", "given",
          "--total-steps", "256", "--run-dir", str(run), "--no-progress", "--n-envs", "2", "--n-steps", "128",
          "--batch-size", "64", "--eval-every", "256", "--eval-episodes", "1", "--net", "16,16"])
    policy = load_policy(run / "best")
    training = policy.record.training
    assert training.grounding == asdict(Grounding()) and training.lift == asdict(SwingLift())
    assert training.legs == asdict(LegGap())
    assert training.leg_symmetry == json.loads(json.dumps(asdict(LegSymmetry())))
    assert policy.preparation_note(None, Grounding(), SwingLift(), legs=LegGap(), symmetry=LegSymmetry()) is None
    assert "--part-legs" in policy.preparation_note(None, Grounding(), SwingLift(), symmetry=LegSymmetry())
    assert "--even-legs" in policy.preparation_note(None, Grounding(), SwingLift(), legs=LegGap())
    mix = env_kwargs(run_args(run), ["deepmimic:walk"], 0.0)["artefacts"]  # clean only, yet prepared
    assert mix.fraction == 0.0 and mix.grounding == Grounding() and mix.lift == SwingLift() and mix.judge == "given"
    assert mix.legs == LegGap() and mix.symmetry == LegSymmetry()
    assert mix.prepares(False) and mix.prepares(True)
    plain = argparse.Namespace(**{**vars(run_args(run)), "even_legs": False, "part_legs": None, "ground": False,
                                  "swing_lift": None})
    assert env_kwargs(plain, ["deepmimic:walk"], 0.0)["artefacts"] is None
    with pytest.raises(SystemExit, match="--judge given judges against the reference as made.*prepares none"):
        main(["--clips", "deepmimic:walk", "--judge", "given", "--run-dir", str(tmp_path / "x")])
    for judge in ("clean_pose", "unslid_pose"):
        with pytest.raises(SystemExit, match=fr"--judge {judge} judges corrupted episodes.*--corrupted-fraction > 0"):
            main(["--clips", "deepmimic:walk", "--judge", judge, "--run-dir", str(tmp_path / "x")])
    with pytest.raises(SystemExit, match="--swing-from goes with --swing-lift"):
        main(["--clips", "deepmimic:walk", "--swing-from", "speed", "--run-dir", str(tmp_path / "y")])
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


def test_a_warm_start_takes_the_weights_but_its_own_exploration_noise(tmp_path):
    """--init-from copies the source's layers and statistics; --action-variance sets σ² anew."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--action-variance", "0.01",
          "--run-dir", str(run), "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64",
          "--total-steps", "128", "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "1000"])
    model = PPO.load(newest_checkpoint(run), device="cpu")
    assert model.policy.log_std.detach().exp().pow(2).allclose(model.policy.log_std.new_full((20,), 0.01))
    weights, started = model.policy.state_dict(), source.model.policy.state_dict()
    layers = [k for k in started if k != "log_std"]
    assert layers and all(torch.allclose(weights[k], started[k], atol=1e-6) for k in layers)  # lr ~0: unchanged


def test_widened_inputs_leave_the_network_unchanged_whatever_the_new_inputs():
    """widen_inputs: 2 zero-weight inputs inserted at index 1 of a 3-input first layer; the outputs
    for any values of the new inputs equal the source's on the old ones."""
    torch.manual_seed(0)
    layers = {name: torch.nn.Linear(3, 4) for name in FIRST_LAYERS}
    source = {name: layer.weight.detach().clone() for name, layer in layers.items()}
    wide = widen_inputs(source, insert_at=1, n_new=2)
    x_old = torch.tensor([0.5, -1.0, 2.0])
    for name in FIRST_LAYERS:
        assert wide[name].shape == (4, 5) and not wide[name][:, 1:3].any()
        for new_inputs in ([0.0, 0.0], [3.0, -7.0]):
            x_new = torch.tensor([0.5, *new_inputs, -1.0, 2.0])
            assert torch.allclose(wide[name] @ x_new, source[name] @ x_old)
    with pytest.raises(PolicyError, match="mlp_extractor.value_net.0.weight"):
        widen_inputs({FIRST_LAYERS[0]: source[FIRST_LAYERS[0]]}, 1, 2)
    mean, var = widen_statistics(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]), 1, np.array([0.04, 0.04]))
    assert np.array_equal(mean, [1.0, 0, 0, 2.0, 3.0]) and np.allclose(var, [4.0, 0.04, 0.04, 5.0, 6.0])


def test_a_warm_start_onto_the_com_offset_observation_acts_as_the_source(tmp_path):
    """--init-from a world-frame policy with --com-offset: the run observes 3 more values (dp_com),
    and before any learning it takes the source's actions whatever the offset."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--com-offset", "--run-dir", str(run),
          "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--total-steps", "128",
          "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "128", "--eval-episodes", "1"])
    widened = load_policy(run / "best")
    env = widened.make_env(["deepmimic:walk"])
    assert widened.record.env.mimic_config().com_offset and env.observation_space.shape == (276,)
    obs, _ = env.reset(seed=0)
    moved = obs.copy()
    moved[13:16] += [0.4, -0.3, 0.1]  # the character 0.5 m off the reference
    assert np.allclose(widened(obs), widened(moved), atol=1e-5)
    assert np.allclose(widened(obs), source(np.delete(obs, np.s_[13:16])), atol=1e-4)


def test_a_warm_start_onto_the_reference_window_acts_as_the_source_with_the_new_inputs_scaled(tmp_path):
    """--init-from a policy with --lookahead 1 5 --lookbehind 3: the run observes 3 × 66 more
    values, takes the source's actions whatever they hold, and normalises them with its own envs'
    statistics. From that policy, a run with a window of more steps (--lookahead 1 5 10
    --lookbehind 3 6) keeps the old steps' weights and statistics and acts as it does whatever the
    new steps hold; one that drops a step is refused, naming it."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--lookahead", "1", "5", "--lookbehind", "3",
          "--run-dir", str(run), "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64",
          "--total-steps", "128", "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "128",
          "--eval-episodes", "1"])
    widened = load_policy(run / "best")
    config = widened.record.env.mimic_config()
    assert config.lookahead == (1, 5) and config.lookbehind == (3,)
    env = widened.make_env(["deepmimic:walk"])
    assert env.observation_space.shape == (273 + 198,)
    obs, _ = env.reset(seed=0)
    window = slice(273, 273 + 198)
    moved = obs.copy()
    moved[window] += np.random.default_rng(0).normal(0, 0.5, 198)
    assert np.allclose(widened(obs), widened(moved), atol=1e-5)
    assert np.allclose(widened(obs), source(obs[:273]), atol=1e-4)
    stats = widened.normalizer.obs_rms
    normalised = (obs[window] - stats.mean[window]) / np.sqrt(stats.var[window])
    assert np.abs(normalised).max() < 10 and stats.var[window].min() > 0
    assert 0.02 < stats.mean[window][0] < 0.06  # walk's CoM moves ~1.2 m/s × 1/30 s along +x in one control step
    behind = env.unwrapped.obs_slices["lookbehind"]
    assert -0.18 < stats.mean[behind][0] < -0.06  # and back ~0.12 m in three
    with pytest.raises(SystemExit, match=r"lookahead 1 5, lookbehind 3; this run's \(lookahead 1 5\) lacks lookbehind 3\. "
                                         r"A warm start may add window steps, not drop them"):
        main(["--clips", "deepmimic:walk", "--init-from", str(run / "best"), "--lookahead", "1", "5",
              "--run-dir", str(tmp_path / "other"), "--no-progress", "--n-envs", "2", "--n-steps", "64",
              "--batch-size", "64", "--total-steps", "128"])

    # a longer window: lookahead 1 5 10, lookbehind 3 6 from 1 5 / 3; the old steps keep their weights
    longer = tmp_path / "longer"
    main(["--clips", "deepmimic:walk", "--init-from", str(run / "best"), "--lookahead", "1", "5", "10",
          "--lookbehind", "3", "6", "--run-dir", str(longer), "--no-progress", "--n-envs", "2", "--n-steps", "64",
          "--batch-size", "64", "--total-steps", "128", "--lr", "1e-12", "--checkpoint-every", "1000",
          "--eval-every", "128", "--eval-episodes", "1"])
    wider = load_policy(longer / "best")
    assert wider.record.env.mimic_config().window_steps == (1, 5, 10, -3, -6)
    wide_env = wider.make_env(["deepmimic:walk"])
    wide_obs, _ = wide_env.reset(seed=0)
    assert wide_obs.shape == (273 + 5 * 66,)
    kept = np.r_[0:273 + 132, 273 + 198:273 + 264]  # lookahead 1, 5 and lookbehind 3 of the wider layout
    assert np.allclose(wide_obs[kept], env.reset(seed=0)[0], atol=1e-5)
    new_steps = np.r_[273 + 132:273 + 198, 273 + 264:273 + 330]
    moved = wide_obs.copy()
    moved[new_steps] += np.random.default_rng(1).normal(0, 0.5, 132)
    assert np.allclose(wider(wide_obs), wider(moved), atol=1e-5)
    assert np.allclose(wider(wide_obs), widened(wide_obs[kept]), atol=1e-4)
    wide_stats = wider.normalizer.obs_rms
    assert np.allclose(wide_stats.mean[kept], stats.mean, atol=1e-3)  # the source's, barely moved at lr ~0
    assert -0.36 < wide_stats.mean[273 + 264] < -0.12  # lookbehind 6: the CoM ~0.24 m back


class Actor(torch.nn.Module):
    """SB3's actor, named as SB3 names it: a tanh MLP ``mlp_extractor.policy_net`` (layers 0, 2, ...)
    and the linear ``action_net``; ``sizes`` = (inputs, hidden ..., actions)."""

    def __init__(self, sizes: list[int]):
        super().__init__()
        layers = []
        for a, b in zip(sizes[:-2], sizes[1:-1]):
            layers += [torch.nn.Linear(a, b), torch.nn.Tanh()]
        self.mlp_extractor = torch.nn.Module()
        self.mlp_extractor.policy_net = torch.nn.Sequential(*layers)
        self.action_net = torch.nn.Linear(sizes[-2], sizes[-1])

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.action_net(self.mlp_extractor.policy_net(x))


def test_widened_hidden_layers_compute_the_source_and_train_their_new_units():
    """widen_hidden: a 3-4-4-2 actor embedded in a 3-7-6-2 one gives the same outputs for any input,
    and a loss on the outputs sends gradient into the new units' outgoing weights."""
    torch.manual_seed(0)
    small, wide = Actor([3, 4, 4, 2]), Actor([3, 7, 6, 2])
    wide.load_state_dict(widen_hidden(small.state_dict(), wide.state_dict()))
    x = torch.randn(50, 3) * 3
    assert torch.allclose(wide(x), small(x), atol=1e-6)
    second, out = wide.mlp_extractor.policy_net[2], wide.action_net
    assert second.weight[4:].abs().min() > 0  # new units read every unit, old and new
    assert not second.weight[:4, 4:].any() and not out.weight[:, 4:].any()  # nothing reads a new unit
    wide(x).pow(2).sum().backward()
    assert out.weight.grad[:, 4:].abs().sum() > 0 and second.weight.grad[:4, 4:].abs().sum() > 0
    with pytest.raises(PolicyError, match=r"policy_net.2.weight is \(4, 4\) in the source and \(3, 4\)"):
        widen_hidden(small.state_dict(), Actor([3, 4, 3, 2]).state_dict())
    with pytest.raises(PolicyError, match="different layers"):
        widen_hidden(small.state_dict(), Actor([3, 4, 4, 4, 2]).state_dict())


def test_a_wider_network_may_not_grow_its_inputs_or_outputs():
    """widen_hidden on SB3's layer names: hidden units may be new, observation inputs and actions not."""
    def policy(n_obs: int, hidden: int, n_act: int) -> dict[str, torch.Tensor]:
        state = {}
        for net in ("policy_net", "value_net"):
            state[f"mlp_extractor.{net}.0.weight"] = torch.randn(hidden, n_obs)
            state[f"mlp_extractor.{net}.0.bias"] = torch.randn(hidden)
        state["action_net.weight"], state["action_net.bias"] = torch.randn(n_act, hidden), torch.randn(n_act)
        state["value_net.weight"], state["value_net.bias"] = torch.randn(1, hidden), torch.randn(1)
        state["log_std"] = torch.zeros(n_act)
        return state

    wide = widen_hidden(policy(5, 4, 2), policy(5, 9, 2))
    assert wide["action_net.weight"].shape == (2, 9) and not wide["action_net.weight"][:, 4:].any()
    for target, grown in ((policy(6, 9, 2), "mlp_extractor.policy_net.0.weight"), (policy(5, 9, 3), "action_net.weight")):
        with pytest.raises(PolicyError, match=f"{grown} is .* --net may only widen the source's hidden layers"):
            widen_hidden(policy(5, 4, 2), target)


def test_a_warm_start_onto_wider_hidden_layers_acts_as_the_source(tmp_path):
    """--init-from a 256,256 policy with --net 300,260: before any learning the run takes the
    source's actions and values the states as the source does."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--net", "300,260", "--run-dir", str(run),
          "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--total-steps", "128",
          "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "128", "--eval-episodes", "1"])
    wide = load_policy(run / "best")
    state = wide.model.policy.state_dict()
    assert state["mlp_extractor.value_net.2.weight"].shape == (260, 300)
    assert state["action_net.weight"][:, 256:].abs().max() < 1e-6  # the new units are still not read
    env = wide.make_env(["deepmimic:walk"])
    obs, _ = env.reset(seed=0)
    assert np.allclose(wide(obs), source(obs), atol=1e-4)
    values = [p.model.policy.predict_values(torch.as_tensor(p.normalizer.normalize_obs(obs))[None].float())
              for p in (wide, source)]
    assert torch.allclose(*values, rtol=1e-4)  # the running statistics moved a little in 128 steps


def test_a_warm_start_refuses_a_policy_observed_in_another_frame(tmp_path):
    """A world-frame policy cannot seed a heading-frame run (the same observation size as world +
    dp_com would otherwise load it silently)."""
    with pytest.raises(SystemExit, match="observed in the 'world' frame; a warm start cannot change the frame to 'heading'"):
        main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--obs-frame", "heading",
              "--run-dir", str(tmp_path / "run"), "--no-progress", "--n-envs", "2", "--n-steps", "64",
              "--batch-size", "64", "--total-steps", "64"])


def test_a_kill_during_a_checkpoint_is_held_until_the_save_is_done():
    """deferred_signals: SIGTERM sent inside the block runs the handler from before only after the
    block (once, however often it came); a SIG_IGN handler from before stays ignored."""
    import os
    import signal

    seen = []
    previous = signal.signal(signal.SIGTERM, lambda signum, frame: seen.append(("handled", signum)))
    try:
        with deferred_signals():
            os.kill(os.getpid(), signal.SIGTERM)
            os.kill(os.getpid(), signal.SIGTERM)
            seen.append("saved")
        assert seen == ["saved", ("handled", signal.SIGTERM)]
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        with deferred_signals():
            os.kill(os.getpid(), signal.SIGTERM)
        assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN and len(seen) == 2
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_recorded_progress_is_the_newest_checkpoints_else_the_last_evaluations(tmp_path):
    """What a resumed run adds its wall time to and agents/ship.py records as the run's totals:
    wall.json (written with each checkpoint) runs past the last evaluation; runs from before
    wall.json fall back on the evaluation log; a run with neither has none."""
    assert recorded_progress(tmp_path) is None
    (tmp_path / "evaluations.jsonl").write_text(json.dumps({"steps": 6_000_000, "wall_s": 2917.7}) + "\n")
    assert recorded_progress(tmp_path) == (6_000_000, 2917.7)
    (tmp_path / "wall.json").write_text(json.dumps({"steps": 6_245_376, "wall_s": 2968.6}))
    assert recorded_progress(tmp_path) == (6_245_376, 2968.6)


def test_a_kl_following_learning_rate_falls_after_too_large_updates(tmp_path):
    """--target-kl: with a rate far too large for σ² = 0.03 the updates' KL exceeds twice the target,
    so the rate is divided by 1.5 after each update; it is saved with the checkpoint."""
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--target-kl", "1e-6", "--lr", "1e-3", "--run-dir", str(run), "--no-progress",
          "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--total-steps", "384", "--net", "16,16",
          "--checkpoint-every", "384", "--eval-every", "1000"])
    model = PPO.load(newest_checkpoint(run), device="cpu")
    # three updates (128 steps each); each after the first lowers the rate for the next
    assert model.learning_rate == pytest.approx(1e-3 / 1.5 ** 2)
    assert json.loads((run / "args.json").read_text())["target_kl"] == 1e-6


def test_a_warm_start_with_a_wider_action_limit_keeps_the_weights_and_records_the_limit(tmp_path):
    """--init-from with --action-limit 1.5: the run's action space is ±1.5 rad, its sidecar
    records the limit, and before any learning it takes the source's action wherever that is
    inside ±1 rad (the source's own clip) and its unclipped mean up to ±1.5 elsewhere."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--init-from", str(WALK_POLICY), "--action-limit", "1.5", "--run-dir",
          str(run), "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64", "--total-steps", "128",
          "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "128", "--eval-episodes", "1"])
    wide = load_policy(run / "best")
    assert wide.record.env.mimic_config().action_limit_rad == 1.5
    assert np.array_equal(wide.model.action_space.high, np.full(20, 1.5, np.float32))
    env = wide.make_env(["deepmimic:walk"])
    assert np.array_equal(env.action_space.high, np.full(20, 1.5, np.float32))
    obs, _ = env.reset(seed=0)
    mean = mlp_mean_action(source.model.policy, np.asarray(source.normalizer.normalize_obs(obs), np.float32))
    assert np.allclose(wide(obs), np.clip(mean, -1.5, 1.5), atol=1e-3)
    assert np.allclose(source(obs), np.clip(mean, -1.0, 1.0), atol=1e-6)


def test_a_warm_start_onto_every_hinge_acts_as_the_key_joint_source(tmp_path):
    """--init-from a MimicIMU-v0 policy (8 key joints, 20 actions) with --env-id MimicFullAction-v0
    (all 43 hinges): before any learning the run gives each key hinge the source's action, every
    other hinge a zero offset, and values the states as the source does."""
    source = load_policy(WALK_POLICY)
    run = tmp_path / "run"
    main(["--clips", "deepmimic:walk", "--env-id", "MimicFullAction-v0", "--init-from", str(WALK_POLICY),
          "--run-dir", str(run), "--no-progress", "--n-envs", "2", "--n-steps", "64", "--batch-size", "64",
          "--total-steps", "128", "--lr", "1e-12", "--checkpoint-every", "1000", "--eval-every", "128",
          "--eval-episodes", "1"])
    full = load_policy(run / "best")
    assert full.env_id == "MimicFullAction-v0" and full.model.action_space.shape == (43,)
    full_env, key_env = full.make_env(["deepmimic:walk"]), source.make_env(["deepmimic:walk"])
    driven = key_env.unwrapped.driven
    full_obs, _ = full_env.reset(seed=0, options={"start_frame": 20})
    key_obs, _ = key_env.reset(seed=0, options={"start_frame": 20})
    for _ in range(3):  # the previous action in the observation moves with its hinge
        action = full(full_obs)
        np.testing.assert_allclose(action[driven], source(key_obs), atol=2e-3)
        assert np.abs(np.delete(action, driven)).max() < 1e-6
        full_obs, *_ = full_env.step(action)
        key_obs, *_ = key_env.step(action[driven])
    values = [p.values(o[None])[0] for p, o in ((full, full_obs), (source, key_obs))]
    assert values[0] == pytest.approx(values[1], rel=1e-3)


def test_a_warm_start_may_not_drive_fewer_hinges():
    from agents.warm_start import drive_more_hinges

    state = {"mlp_extractor.policy_net.0.weight": torch.zeros(4, 6), "mlp_extractor.value_net.0.weight": torch.zeros(4, 6),
             "action_net.weight": torch.zeros(2, 4), "action_net.bias": torch.zeros(2), "log_std": torch.zeros(2)}
    with pytest.raises(PolicyError, match=r"drives actuators \[7\]"):
        drive_more_hinges(state, np.zeros(6), np.ones(6), np.array([3, 7]), np.array([1, 2, 3]), 4)


def test_move_block_places_each_old_entry_at_its_new_index():
    from agents.warm_start import move_block

    values = torch.tensor([[1.0, 2.0, 3.0, 4.0, 5.0]])  # block [2, 3] at columns 1..2, among 0 and 4, 5
    moved = move_block(values, 1, 1, torch.tensor([2, 0]), 3, fill=-1.0)
    assert moved.tolist() == [[1.0, 3.0, -1.0, 2.0, 4.0, 5.0]]
    rows = move_block(torch.tensor([7.0, 8.0]), 0, 0, torch.tensor([1, 3]), 4, fill=0.5)
    assert rows.tolist() == [0.5, 7.0, 0.5, 8.0]


def test_posture_ranges_change_what_the_copies_are_drawn_from():
    """``--posture-range stance_width=10,10`` with every other change at zero: each copy stands
    10° wider on each hip than its reference; bad values are refused as the option is read."""
    zero = [f"{name}=0,0" for name in ("trunk_flexion", "neck_flexion", "crouch", "elbow_flexion")]
    args = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "--postures", "1",
                                      "--posture-range", "stance_width=-4,12", *zero, "stance_width=10,10"])
    assert posture_ranges(args).stance_width_deg == (10.0, 10.0)  # the later value wins
    walk, wide = training_motions(args)
    hm = load_model(walk.model)
    for hinge, sign in (("l_thigh_x", 1), ("r_thigh_x", -1)):
        change = wide.qpos[:, hm.qpos_index(hinge)] - walk.qpos[:, hm.qpos_index(hinge)]
        assert np.degrees(np.median(change)) * sign == pytest.approx(10.0, abs=0.5)
    assert np.degrees(np.abs(wide.qpos[:, hm.qpos_index("chest_y")] - walk.qpos[:, hm.qpos_index("chest_y")]).max()) \
        < 0.5  # no stoop drawn
    for bad in ("stance_width", "stance_width=12,-4", "stoop=0,10", "stance_width=1,x", "stance_width=nan,1",
                "stance_width=-inf,inf", "stance_width=1,2,3"):
        with pytest.raises(UsageError, match="expected NAME=LOW,HIGH"):
            build_parser().parse_args(["--run-dir", "unused", "--posture-range", bad])
    alone = build_parser().parse_args(["--run-dir", "unused", "--posture-range", "stance_width=0,5"])
    with pytest.raises(ValueError, match="give --postures N as well"):
        posture_ranges(alone)
    cleared = build_parser().parse_args(["--run-dir", "unused", "--posture-range"])  # e.g. on a resume
    assert posture_ranges(cleared) == PostureRanges()


def test_stance_copies_walk_wider_and_sway_with_the_steps():
    """``--stances 1 --stance-extra 0.3 0.3``: a copy of the walk whose feet are 0.3 m further apart
    sideways and whose centre of mass sways more, as the pendulum needs; seeded."""
    args = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "--stances", "1",
                                      "--stance-extra", "0.3", "0.3"])
    walk, wide = training_motions(args)
    assert wide.name == "deepmimic:walk (stance +0.3 m)" and wide.source["extra_stance_m"] == 0.3
    hm = load_model(walk.model)
    window = np.ones(31) / 31  # about a stride: a running mean over it leaves the sway

    def sideways(kin) -> tuple[float, float]:
        """Mean sideways distance of the toes and std of the CoM's sideways sway (m), sideways
        along the line between the hips averaged over a stride."""
        hips = kin.body_pos[:, hm.body_names.index("l_thigh"), :2] - kin.body_pos[:, hm.body_names.index("r_thigh"), :2]
        side = np.stack([np.convolve(hips[:, k], window, mode="valid") for k in range(2)], axis=1)
        side /= np.linalg.norm(side, axis=1, keepdims=True)
        toes = (kin.foot_points[15:-15, 0, :2] - kin.foot_points[15:-15, 1, :2])
        com = kin.com[15:-15, :2] - np.stack([np.convolve(kin.com[:, k], window, mode="valid") for k in range(2)], 1)
        return float(np.abs(np.sum(toes * side, axis=1)).mean()), float(np.sum(com * side, axis=1).std())

    (narrow_feet, narrow_sway), (wide_feet, wide_sway) = (sideways(hm.forward_kinematics(m.qpos)) for m in (walk, wide))
    assert 0.25 < wide_feet - narrow_feet < 0.33
    assert wide_sway > 1.3 * narrow_sway and wide_sway - narrow_sway < 0.15  # more, far from the feet's 0.15 each
    drawn = build_parser().parse_args(["--run-dir", "unused", "--clips", "deepmimic:walk", "deepmimic:run",
                                       "--stances", "2", "--stance-extra", "0.1", "0.3", "--seed", "3"])
    copies = training_motions(drawn)[2:]
    extras = [c.source["extra_stance_m"] for c in copies]
    assert all(0.1 <= e <= 0.3 for e in extras) and len(set(extras)) == 4  # each copy its own draw
    assert [c.source["extra_stance_m"] for c in training_motions(drawn)[2:]] == extras  # the same copies again
    drawn.seed = 4
    assert [c.source["extra_stance_m"] for c in training_motions(drawn)[2:]] != extras
    for bad in (["0.3", "0.1"], ["nan", "0.1"], ["-0.5", "0.1"]):
        with pytest.raises(ValueError, match="--stance-extra"):
            stance_extra(build_parser().parse_args(["--run-dir", "unused", "--stance-extra", *bad]))


def test_a_run_can_track_references_behind_the_denoisers_slow_corrections(tmp_path):
    """--denoise --denoise-slow: the corrupted references pass through the denoiser's slowed
    corrections (ArtefactMix.denoise_slow_s), the sidecar records it, evaluation without it draws a
    note, and --denoise-slow without --denoise is refused before any work."""
    from agents.policy import load_policy
    from perception.imu_denoiser import DEFAULT_DENOISER
    run = tmp_path / "slow"
    main(["--clips", "deepmimic:walk", "--corrupted-fraction", "1", "--denoise", str(DEFAULT_DENOISER),
          "--denoise-slow", "0.5", "--total-steps", "256", "--run-dir", str(run), "--no-progress", "--n-envs", "2",
          "--n-steps", "128", "--batch-size", "64", "--eval-every", "256", "--eval-episodes", "1", "--net", "16,16"])
    policy = load_policy(run / "best")
    assert policy.record.training.denoise_slow_s == 0.5
    assert policy.preparation_note(DEFAULT_DENOISER, denoise_slow_s=0.5) is None
    assert "--denoise-slow" in policy.preparation_note(DEFAULT_DENOISER)
    mix = env_kwargs(run_args(run), ["deepmimic:walk"], 1.0)["artefacts"]
    assert mix.denoise_slow_s == 0.5 and mix.denoiser == str(DEFAULT_DENOISER)
    with pytest.raises(SystemExit, match="--denoise-slow 0.5 slows a denoiser's corrections: give --denoise too"):
        main(["--clips", "deepmimic:walk", "--denoise-slow", "--run-dir", str(tmp_path / "x")])
    with pytest.raises(ValueError, match="ArtefactMix.denoise_slow_s must be .* go with a denoiser"):
        ArtefactMix(denoise_slow_s=0.5)
