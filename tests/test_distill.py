"""agents/distill.py: DAgger from a policy set into one network, on the DeepMimic walk and the same
walk played backwards (two teachers), and the command end to end with a resume."""

import argparse
import json
from dataclasses import asdict, replace
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
import torch
from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

import agents.distill
import agents.teachers
from agents.distill import (DistillConfig, Labels, Teachers, artefact_mix, build_parser, center_values, collect, fit,
                            fit_report, label_rows, load_teachers, main, new_student, rmse_text, split_holdout,
                            student_task, symmetric_teacher, teacher_mix, teacher_observation, teacher_weight)
from agents.mirror import MirrorMaps
from agents.policy import PolicyError, load_policy
from agents.policy_set import PolicySet
from agents.teachers import check_teacher_layouts, mean_actions, mean_actions_and_values
from agents.train_ppo import artefact_mix as ppo_artefact_mix
from agents.train_ppo import build_parser as build_ppo_parser
from envs import ArtefactMix
from envs.reference import ReferenceTrack
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.library import load_motion

MODELS = Path(__file__).parents[1] / "models"


def test_each_episode_is_labelled_by_the_teacher_its_clip_routes_to_and_a_student_fits_them(tmp_path):
    walk = load_motion("deepmimic:walk", "humanoid_1seg", min_frames=700)
    backwards = replace(walk.with_qpos(walk.qpos[::-1].copy(), loop=False), name="walk_backwards")
    PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_imu").save()
    teachers = load_teachers(tmp_path / "set", lambda foot: [walk, backwards])
    assert teachers.names == ["mimic_walk", "mimic_imu"] and teachers.default == 0
    assert teachers.of_clip == {walk.name: 0, "walk_backwards": 1}

    default = teachers.policies[0]
    env = default.make_env(teachers.motions, artefacts=None)
    rng = np.random.default_rng(0)
    labels = collect(env, None, teachers, 600, 0.17, rng, first_episode=0, progress=False)
    assert len(labels) == 600 and set(np.unique(labels.teacher)) == {0, 1}  # both clips were met
    for i, teacher in enumerate(teachers.policies):  # each row carries its own teacher's mean action
        rows = labels.teacher == i
        assert np.allclose(labels.actions[rows], mean_actions_and_values(teacher, labels.obs[rows])[0], atol=1e-5)
    assert not np.allclose(*(mean_actions_and_values(t, labels.obs[:50])[0] for t in teachers.policies))

    student = new_student(env, default, DistillConfig(net="64,64"))
    before = fit_report(student, labels, teachers.names)
    center_values(student, labels)
    assert abs(fit_report(student, labels, teachers.names)["value_r2"]) < 0.2  # the mean is matched, no more
    fit(student, labels, DistillConfig(net="64,64", epochs=30, batch_size=64, lr=1e-3), 0.17, rng, progress=False)
    after = fit_report(student, labels, teachers.names)
    assert after["action_rmse"] < 0.5 * before["action_rmse"] and after["value_r2"] > 0.3  # from ~0 once centred
    assert set(after) == {"action_rmse", "value_r2", "action_rmse_mimic_walk", "action_rmse_mimic_imu"}


def test_distill_end_to_end_writes_a_policy_and_resumes(tmp_path):
    out = tmp_path / "distill"
    common = ["--net", "32,32", "--steps-per-round", "200", "--epochs", "2", "--batch-size", "64", "--no-progress"]
    main(["--teacher", str(MODELS / "mimic_walk"), "--clips", "deepmimic:walk", "--corrupted-fraction", "0",
          "--rounds", "1", "--warp", "*:walk=1.5", "--out", str(out), *common])
    student = load_policy(out / "student")
    assert student.record.training.warps == {"deepmimic:walk": [1.5]}  # what it was distilled on, recorded
    assert student.model.policy.state_dict()["mlp_extractor.policy_net.2.weight"].shape == (32, 32)
    assert student.record.ppo.net == "32,32" and student.record.env.env_id == "MimicIMU-v0"
    env = student.make_env(["deepmimic:walk"])
    assert student(env.reset(seed=0)[0]).shape == (20,)
    # a stop after the next round's labels were written, before its student and log line: the
    # student's sidecar says one round is done, so the resume cuts the labels back and redoes it
    labels = Labels.load(out / "data.npz")
    (labels + labels).save(out / "data.npz")
    (out / "log.jsonl").write_text("")
    main(["--out", str(out), "--resume", "--rounds", "2", "--no-progress"])
    rounds = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    assert [r["round"] for r in rounds] == [0, 1] and [r["acted_by"] for r in rounds] == ["teachers", "student"]
    record = load_policy(out / "student").record
    assert rounds[1]["states"] == 400 and record.extra["distillation"]["rounds"][1]["round"] == 1
    assert len(record.training.commands) == 2 and "--resume" in record.training.commands[1]  # the run's history
    assert record.training.warps == {"deepmimic:walk": [1.5]}  # the resumed run distils on the same warps
    with pytest.raises(SystemExit, match="already holds a distillation"):
        main(["--teacher", str(MODELS / "mimic_walk"), "--clips", "deepmimic:walk", "--out", str(out), *common])
    with pytest.raises(SystemExit, match="no distillation to resume"):
        main(["--out", str(tmp_path / "none"), "--resume"])


def test_teacher_weights_pull_the_fit_toward_the_heavier_teachers_labels():
    """The same states labelled by two teachers that disagree (+0.1 and -0.1 rad on every action, values
    10 and 20): weighted 4 : 1, the least-squares student settles on the weighted means, +0.06 rad and 12,
    and the loss it reports is the weighted mean, by hand (0.16² + 4·0.04²) / 5 / 0.17² + (8² + 4·2²) / 5 / 25
    = 0.857 (var(V_t) = 25)."""
    default = load_policy(MODELS / "mimic_walk")
    env = default.make_env(["deepmimic:walk"], artefacts=None)
    rng = np.random.default_rng(0)
    obs = np.stack([env.reset(seed=s)[0] for s in range(64)])
    n, n_act = len(obs), env.action_space.shape[0]
    labels = Labels(np.concatenate([obs, obs]), np.concatenate([np.full((n, n_act), 0.1), np.full((n, n_act), -0.1)]).astype(np.float32),
                    np.concatenate([np.full(n, 10.0), np.full(n, 20.0)]).astype(np.float32),
                    np.repeat([0, 1], n), np.arange(2 * n))
    names = ["b", "a"]  # teacher 0 is "b", weighted 4: the weights follow the names' order, not their sorting
    config = DistillConfig(net="16,16", epochs=300, batch_size=128, lr=3e-3, teacher_weights=(("b", 4.0),))
    assert config.weights_of(names).tolist() == [4.0, 1.0]
    student = new_student(env, default, config)
    center_values(student, labels)  # the unweighted mean, 15
    loss = fit(student, labels, config, 0.17, rng, progress=False, teacher_names=names)
    actions, values = mean_actions_and_values(student, obs)
    assert np.allclose(actions, 0.06, atol=0.01) and np.allclose(values, 12.0, atol=0.5)
    assert loss == pytest.approx(0.857, abs=0.03)
    with pytest.raises(ValueError, match="teacher_names must name"):
        fit(student, labels, config, 0.17, rng, progress=False)
    with pytest.raises(ValueError, match=r"names \['mimic_walk_bak'\], which are not teachers"):
        DistillConfig(teacher_weights=(("mimic_walk_bak", 4.0),)).weights_of(["mimic_general", "mimic_walk_back"])
    with pytest.raises(ValueError, match=r"teacher_weights\['b'\] must be a finite number > 0"):
        DistillConfig(teacher_weights=(("b", 0.0),))
    with pytest.raises(ValueError, match="names a teacher twice"):
        DistillConfig(teacher_weights=(("b", 1.0), ("b", 2.0)))
    assert teacher_weight("mimic_walk_back=4") == ("mimic_walk_back", 4.0)
    for bad in ("mimic_walk_back", "mimic_walk_back=0", "=4", "mimic_walk_back=inf"):
        with pytest.raises(argparse.ArgumentTypeError, match="expected NAME=W"):
            teacher_weight(bad)


def test_a_fit_on_rows_of_the_labels_is_the_fit_on_their_copy_and_policies_answer_a_chunk_at_a_time(monkeypatch):
    """The distillation fits the held-out split's training rows in place (indices, no copy): the
    same loss and weights as a fit on the copy with the same generator; a policy's answers for many
    observations, plain or as its symmetric actor, are the same answered 7 at a time, and so is the
    critic's centring; ``mean_actions`` gives the same actions without the critic."""
    default = load_policy(MODELS / "mimic_walk")
    env = default.make_env(["deepmimic:walk"], artefacts=None)
    obs = np.stack([env.reset(seed=s)[0] for s in range(40)])
    symmetric = replace(default, mirror=MirrorMaps.of(env))
    whole = [mean_actions_and_values(p, obs) for p in (default, symmetric)]
    labels = Labels(obs, whole[0][0] + 0.05, whole[0][1] + 3.0, np.zeros(40, int), np.arange(40))
    rows = np.arange(0, 40, 3)
    centred_whole = new_student(env, default, DistillConfig(net="16,16"))
    center_values(centred_whole, labels, rows)
    monkeypatch.setattr(agents.distill, "ANSWER_CHUNK", 7)  # the critic's centring
    monkeypatch.setattr(agents.teachers, "ANSWER_CHUNK", 7)  # the policies' answers
    for policy, (actions, values) in zip((default, symmetric), whole):
        chunked = mean_actions_and_values(policy, obs)
        np.testing.assert_allclose(chunked[0], actions, atol=1e-6)
        np.testing.assert_allclose(chunked[1], values, rtol=1e-6)
        np.testing.assert_allclose(mean_actions(policy, obs), actions, atol=1e-6)  # without the critic: the same
    assert not np.allclose(whole[0][0], whole[1][0])  # the symmetric actor answers otherwise
    none_actions, none_values = mean_actions_and_values(default, obs[:0])
    assert none_actions.shape == (0, env.action_space.shape[0]) and none_values.shape == (0,)
    assert mean_actions(default, obs[:0]).shape == (0, env.action_space.shape[0])
    centred_chunked = new_student(env, default, DistillConfig(net="16,16"))
    center_values(centred_chunked, labels, rows)
    assert centred_chunked.model.policy.value_net.bias.item() == pytest.approx(
        centred_whole.model.policy.value_net.bias.item(), rel=1e-6)

    rows, held_out = split_holdout(labels, 0.25, 0)
    held = np.setdiff1d(np.arange(40), rows)
    assert 0 < len(held) < 40 and np.array_equal(held_out.obs, obs[held]) and np.array_equal(held_out.episode, held)
    train = labels.take(rows)
    config = DistillConfig(net="16,16", epochs=3, batch_size=8, lr=1e-3)
    in_place, copied = new_student(env, default, config), new_student(env, default, config)
    center_values(in_place, labels, rows)
    center_values(copied, train)
    loss_in_place = fit(in_place, labels, config, 0.17, np.random.default_rng(1), progress=False, rows=rows)
    loss_copied = fit(copied, train, config, 0.17, np.random.default_rng(1), progress=False)
    assert loss_in_place == loss_copied
    for (name, a), b in zip(in_place.model.policy.state_dict().items(), copied.model.policy.state_dict().values()):
        assert torch.equal(a, b), name
    with pytest.raises(ValueError, match=r"got bool of shape \(40,\); give np.flatnonzero\(mask\)"):
        label_rows(labels, np.isin(np.arange(40), rows))  # a mask of the training rows
    with pytest.raises(ValueError, match=r"indices must lie in \[0, 40\), got 3..40"):
        label_rows(labels, np.array([3, 40]))
    with pytest.raises(ValueError, match="no labelled state"):
        center_values(in_place, labels, np.array([], int))


def test_a_resumed_distillation_keeps_its_weights_and_reads_an_older_run(tmp_path):
    """--resume refuses new weights; a run recorded before --teacher-weight existed resumes unweighted."""
    out = tmp_path / "distill"
    common = ["--net", "32,32", "--steps-per-round", "200", "--epochs", "2", "--batch-size", "64", "--no-progress"]
    main(["--teacher", str(MODELS / "mimic_walk"), "--clips", "deepmimic:walk", "--corrupted-fraction", "0",
          "--rounds", "1", "--teacher-weight", "mimic_walk=2", "--out", str(out), *common])
    assert load_policy(out / "student").record.extra["distillation"]["config"]["teacher_weights"] == [["mimic_walk", 2.0]]
    with pytest.raises(SystemExit, match="cannot change on --resume"):
        main(["--out", str(out), "--resume", "--rounds", "2", "--teacher-weight", "mimic_walk=3"])
    settings = json.loads((out / "args.json").read_text())
    del settings["teacher_weight"]  # as written before the option existed
    (out / "args.json").write_text(json.dumps(settings))
    main(["--out", str(out), "--resume", "--rounds", "2", "--no-progress"])
    assert load_policy(out / "student").record.extra["distillation"]["config"]["teacher_weights"] == []


def test_a_student_from_the_default_policy_starts_acting_as_it(tmp_path):
    """--from-default: the student takes the default teacher's weights (and skips the value
    centring), so before any fit it gives the default's actions, in wider hidden layers too; a
    narrower --net is refused."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg", min_frames=700)
    teachers = load_teachers(MODELS / "mimic_walk", lambda foot: [walk])
    default = teachers.policies[0]
    env = default.make_env(teachers.motions, artefacts=None)
    student = new_student(env, default, DistillConfig(net="256,256", from_default=True))
    obs = np.stack([env.reset(seed=s)[0] for s in range(3)])
    np.testing.assert_allclose(mean_actions_and_values(student, obs)[0], mean_actions_and_values(default, obs)[0],
                               atol=1e-6)
    wider = new_student(env, default, DistillConfig(net="320,288", from_default=True))
    np.testing.assert_allclose(mean_actions_and_values(wider, obs)[0], mean_actions_and_values(default, obs)[0],
                               atol=1e-5)
    with pytest.raises(PolicyError, match="does not fit a --net 64,64 student"):
        new_student(env, default, DistillConfig(net="64,64", from_default=True))


def test_a_perfect_fit_reads_as_zero_and_a_teacher_without_held_out_states_as_a_dash():
    assert rmse_text(0.0) == "0.000" and rmse_text(0.0264) == "0.026" and rmse_text(None) == "-"


def test_posture_and_stance_copies_join_the_distillation_and_reach_the_teacher_their_name_routes_to(tmp_path):
    """``--postures 1``: each clip also carried in a posture drawn from ``--posture-range`` (and, with
    ``--stances 1``, walked wider); a set routing the copies (``*(posture 0)``, ``*(stance +*``) to
    another policy gets their states labelled by it."""
    PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_walk",
              clips=(("*(posture 0)", MODELS / "mimic_imu"), ("*(stance +*", MODELS / "mimic_imu"))).save()
    out = tmp_path / "distill"
    zero = [f"{name}=0,0" for name in ("trunk_flexion", "neck_flexion", "crouch", "elbow_flexion")]
    main(["--teacher", str(tmp_path / "set"), "--clips", "deepmimic:walk", "--corrupted-fraction", "0",
          "--postures", "1", "--posture-range", "stance_width=8,8", *zero, "--stances", "1", "--stance-extra", "0.1",
          "0.2", "--rounds", "1", "--steps-per-round",
          "1200", "--epochs", "1", "--net", "32,32", "--no-progress", "--out", str(out)])
    labels = Labels.load(out / "data.npz")
    assert set(np.unique(labels.teacher)) == {0, 1}  # states of the walk and of its copies
    record = load_policy(out / "student").record.training
    assert record.postures == 1 and record.posture_ranges["stance_width_deg"] == [8.0, 8.0]
    assert record.stances == 1 and tuple(record.stance_extra_m) == (0.1, 0.2)


def test_a_privileged_teacher_reads_the_clean_take_and_the_symmetric_labels_come_mirrored_too():
    """``--teacher-reads clean --mirror-average``: in a corrupted episode the teacher's label is its
    symmetric actor's action on the clean take at the simulated state, in a clean one on what the
    student sees; every state comes twice, the second its mirror image with the mirrored label."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg", min_frames=700)
    policy = load_policy(MODELS / "mimic_walk")
    env = policy.make_env([walk], artefacts=ArtefactMix(fraction=1.0, variants_per_clip=1, seed=3))
    maps = MirrorMaps.of(env)
    teacher = policy.mirror_averaged(env)
    teachers = Teachers([teacher], {walk.name: 0}, 0, [walk])
    base = env.unwrapped

    obs, info = env.reset(seed=0, options={"corrupted": True})
    for _ in range(5):
        obs, *_, info = env.step(np.zeros(env.action_space.shape))
    seen = teacher_observation(env, obs, info, "clean")
    assert info["corrupted"] and seen.shape == obs.shape and np.abs(seen - obs).max() > 0.01
    assert np.array_equal(teacher_observation(env, obs, info, "track"), obs)
    assert np.allclose(base.observation_against(base.current_track), obs, atol=1e-6)  # its own track: its own view
    env.reset(seed=0, options={"corrupted": False})
    obs, *_, info = env.step(np.zeros(env.action_space.shape))
    assert np.array_equal(teacher_observation(env, obs, info, "clean"), obs)  # a clean episode: nothing hidden
    with pytest.raises(ValueError, match="frames"):
        base.observation_against(ReferenceTrack.build(walk.with_qpos(walk.qpos[:100].copy(), loop=False),
                                                      base.humanoid, base.actuator_qpos, base.jointed, base.parent,
                                                      base.config.cube_size_m))

    # the batched symmetric label is the symmetric actor's action, and exactly mirror symmetric
    batch = np.stack([obs, seen])
    mean, _ = mean_actions_and_values(teacher, batch)
    plain, _ = mean_actions_and_values(policy, batch)
    assert np.abs(mean - plain).max() > 1e-3
    mirrored, _ = mean_actions_and_values(teacher, maps.observation(batch))
    assert np.allclose(maps.action(mirrored), mean, atol=1e-5)

    rng = np.random.default_rng(0)
    labels = collect(env, None, teachers, 200, 0.17, rng, first_episode=0, progress=False,
                     teacher_reads="clean", maps=maps)
    assert len(labels) == 400
    first, second = labels.take(slice(0, 200)), labels.take(slice(200, 400))
    assert np.allclose(second.obs, maps.observation(first.obs)) and np.allclose(second.actions,
                                                                                 maps.action(first.actions))
    assert np.array_equal(second.episode, first.episode)
    # every episode is corrupted (fraction 1): no label is the teacher's action on what the student saw
    own, _ = mean_actions_and_values(teacher, first.obs)
    assert np.abs(own - first.actions).max(axis=1).min() > 1e-3


def test_distill_refuses_a_privileged_teacher_without_corrupted_episodes(tmp_path):
    with pytest.raises(SystemExit, match="corrupted-fraction"):
        main(["--teacher", str(MODELS / "mimic_walk"), "--clips", "deepmimic:walk", "--corrupted-fraction", "0",
              "--teacher-reads", "clean", "--out", str(tmp_path / "d"), "--no-progress"])


def test_plain_teachers_label_as_their_plain_actor_under_mirror_average(tmp_path):
    """``--plain-teachers``: with ``--mirror-average`` the named teacher's states carry its plain
    action, the others' their symmetric actor's; a name that is no teacher, or the option without
    ``--mirror-average``, is refused before any work."""
    import shutil
    plain = tmp_path / "walk_plain"
    plain.mkdir()
    for name in ("model.zip", "model_vecnormalize.pkl", "sidecar.json"):
        shutil.copy(MODELS / "mimic_walk" / name, plain / name)
    PolicySet(tmp_path / "set", MODELS / "mimic_walk", MODELS / "mimic_walk", clips=(("deepmimic:walk", plain),)).save()
    common = ["--teacher", str(tmp_path / "set"), "--clips", "deepmimic:walk", "deepmimic:walker/0walk_forward",
              "--corrupted-fraction", "0", "--net", "32,32", "--steps-per-round", "1500", "--epochs", "1",
              "--batch-size", "64", "--rounds", "1", "--no-progress"]
    with pytest.raises(SystemExit, match="nobody name no teacher"):
        main([*common, "--mirror-average", "--plain-teachers", "nobody", "--out", str(tmp_path / "a")])
    with pytest.raises(SystemExit, match="which is not given"):
        main([*common, "--plain-teachers", "walk_plain", "--out", str(tmp_path / "b")])
    main([*common, "--mirror-average", "--plain-teachers", "walk_plain", "--out", str(tmp_path / "c")])
    labels = Labels.load(tmp_path / "c" / "data.npz")
    first = np.arange(len(labels)) < len(labels) // 2  # the states as met; the second half is their mirror image
    teacher = load_policy(plain)
    env = teacher.make_env(["deepmimic:walk"], artefacts=None)
    symmetric = load_policy(MODELS / "mimic_walk").mirror_averaged(env)
    env.close()
    names = load_policy(tmp_path / "c" / "student").record.extra["distillation"]["teachers"]
    for index, actor in ((names.index("walk_plain"), teacher), (names.index("mimic_walk"), symmetric)):
        rows = first & (labels.teacher == index)
        assert rows.sum() > 20
        np.testing.assert_allclose(labels.actions[rows], mean_actions_and_values(actor, labels.obs[rows])[0], atol=1e-5)


def test_a_student_that_also_sees_a_window_of_the_take_starts_as_its_teacher_and_is_labelled_on_its_view(tmp_path):
    """--lookahead / --lookbehind: the student observes the default teacher's observation and the
    reference window after it; from the default it acts as the teacher before any fit (zero weights
    on the window, statistics sampled for it), the teachers label from the leading values (as their
    symmetric actors with --mirror-average), and the saved student observes the window and resumes."""
    walk = load_motion("deepmimic:walk", "humanoid_1seg", min_frames=700)
    teachers = load_teachers(MODELS / "mimic_walk", lambda foot: [walk])
    default = teachers.policies[0]
    config = DistillConfig(net="256,256", from_default=True, lookahead=(2,), lookbehind=(1, 4))
    env = student_task(default, config).make(teachers.motions, artefacts=None)
    size = default.model.observation_space.shape[0]
    assert env.observation_space.shape == (size + 3 * 66,)
    student = new_student(env, default, config)
    obs = np.stack([env.reset(seed=s)[0] for s in range(3)])
    np.testing.assert_allclose(mean_actions_and_values(student, obs)[0],
                               mean_actions_and_values(default, obs[:, :size])[0], atol=1e-5)
    window = student.normalizer.obs_rms
    assert window.mean.shape == (size + 198,) and window.var[size:].min() > 0
    assert np.array_equal(window.mean[:size], default.normalizer.obs_rms.mean)
    maps = MirrorMaps.of(env)
    teacher = symmetric_teacher(default, maps)
    labels = collect(env, None, Teachers([teacher], {walk.name: 0}, 0, [walk]), 60, 0.17, np.random.default_rng(0),
                     first_episode=0, progress=False, maps=maps)
    assert labels.obs.shape == (120, size + 198)
    np.testing.assert_allclose(labels.actions, mean_actions_and_values(teacher, labels.obs[:, :size])[0], atol=1e-5)
    windowed = replace(default, sidecar=replace(default.record, env=student_task(default, config)).to_dict())
    with pytest.raises(PolicyError, match="observes a reference window already"):
        student_task(windowed, config)

    out = tmp_path / "window"
    common = ["--net", "256,256", "--steps-per-round", "150", "--epochs", "1", "--batch-size", "64", "--no-progress",
              "--out", str(out)]
    main(["--teacher", str(MODELS / "mimic_walk"), "--clips", "deepmimic:walk", "--corrupted-fraction", "0.5",
          "--teacher-reads", "clean", "--mirror-average", "--from-default", "--lookahead", "2", "--lookbehind", "1",
          "4", "--part-legs", "--rounds", "1", *common])
    saved = load_policy(out / "student")
    assert saved.record.env.mimic_config().window_steps == (2, -1, -4)
    assert saved.record.training.legs == asdict(LegGap())  # the preparation it tracked, recorded
    assert saved.record.training.leg_symmetry is None
    assert saved.normalizer.obs_rms.mean.shape == (size + 198,)
    student_env = saved.make_env(["deepmimic:walk"], artefacts=None)
    saved.check_env(student_env)
    VecNormalize.load(str(out / "student" / "model_vecnormalize.pkl"), DummyVecEnv([lambda: student_env]))  # as adapting does
    main(["--resume", "--rounds", "2", "--no-progress", "--out", str(out)])
    resumed = load_policy(out / "student")
    assert len(resumed.record.extra["distillation"]["rounds"]) == 2
    np.testing.assert_array_equal(resumed.normalizer.obs_rms.mean, saved.normalizer.obs_rms.mean)
    check_teacher_layouts([saved], env)  # its window is the student's: all of it
    mixed = Teachers([default, saved], {walk.name: 0, "walk copy": 1}, 1, [walk, replace(walk, name="walk copy")])
    mixed_env = student_task(saved, DistillConfig()).make(mixed.motions, artefacts=None)
    check_teacher_layouts(mixed.policies, mixed_env)
    both = collect(mixed_env, saved, mixed, 400, 0.17, np.random.default_rng(1), first_episode=0, progress=False)
    for i, reads in ((0, size), (1, mixed_env.observation_space.shape[0])):  # the leading values, or all of them
        rows = both.teacher == i
        assert rows.sum() >= 20
        np.testing.assert_allclose(both.actions[rows],
                                   mean_actions_and_values(mixed.policies[i], both.obs[rows, :reads])[0], atol=1e-5)
    other_window = student_task(default, replace(config, lookbehind=(1,))).make(teachers.motions, artefacts=None)
    with pytest.raises(PolicyError, match=r"observes \d+ values with reference window \[2, -1, -4\]; a teacher reads "
                                          r".* or, with the student's window \[2, -1\], all of it"):
        check_teacher_layouts([saved], other_window)
    other_actions = load_policy(MODELS / "mimic_walk")
    other_actions.model.action_space = gym.spaces.Box(-1.0, 1.0, (3,), np.float32)
    with pytest.raises(PolicyError, match="acts with 3 values; the student's environment takes"):
        check_teacher_layouts([other_actions], env)


def test_a_teacher_behind_the_denoiser_reads_the_same_corrupted_variant_denoised(tmp_path):
    """--teacher-reads denoised: the student's env tracks the corrupted take as given, the teacher
    reads the same corruption (same artefact seed and variant) after the denoiser, at the student's
    state; without --denoise it is refused, and the student's sidecar records no denoiser."""
    args = argparse.Namespace(teacher_reads="denoised", denoise=str(MODELS / "imu_denoiser_soles"),
                              corrupted_fraction=1.0, strength=(1.0, 1.0), variants_per_clip=2, ground=False,
                              swing_lift=None, swing_from=None, denoise_slow=None, even_legs=False, part_legs=None)
    mix = artefact_mix(args, 5)
    readers = teacher_mix(args, mix)
    assert mix.denoiser is None and readers.denoiser == args.denoise and readers.seed == mix.seed == 5
    slow = teacher_mix(argparse.Namespace(**{**vars(args), "denoise_slow": 0.5}), mix)
    assert slow.denoiser == args.denoise and slow.denoise_slow_s == 0.5 and mix.denoise_slow_s is None
    policy = load_policy(MODELS / "mimic_walk")
    env, teacher_env = (policy.make_env(["deepmimic:walk"], artefacts=m) for m in (mix, readers))
    obs, info = env.reset(seed=0, options={"corrupted": True})
    for _ in range(5):
        obs, *_, info = env.step(np.zeros(env.action_space.shape))
    base, variant = env.unwrapped, env.unwrapped.variant_index
    raw, denoised = base.track(0, variant), teacher_env.unwrapped.track(0, variant)
    np.testing.assert_array_equal(teacher_env.unwrapped.track(0, variant, as_given=True).pos, raw.pos)
    assert np.abs(denoised.pos_rel_com - raw.pos_rel_com).max() > 0.01  # the denoiser moved the bodies (m)
    seen = teacher_observation(env, obs, info, "denoised", teacher_env=teacher_env)
    np.testing.assert_allclose(seen, base.observation_against(denoised), atol=1e-6)
    assert np.abs(seen - obs).max() > 0.01
    with pytest.raises(ValueError, match="needs the teacher's env"):
        teacher_observation(env, obs, info, "denoised")
    with pytest.raises(ValueError, match="give --denoise"):
        artefact_mix(argparse.Namespace(**{**vars(args), "denoise": None}), 5)

    out = tmp_path / "behind"
    main(["--teacher", str(MODELS / "mimic_walk"), "--clips", "deepmimic:walk", "--corrupted-fraction", "1",
          "--variants-per-clip", "1", "--teacher-reads", "denoised", "--denoise", args.denoise, "--lookahead", "2",
          "--rounds", "1", "--net", "32,32", "--steps-per-round", "120", "--epochs", "1", "--batch-size", "64",
          "--no-progress", "--out", str(out)])
    student = load_policy(out / "student")
    assert student.record.training.denoiser is None  # the student tracked the takes as given
    record = student.record.extra["distillation"]
    assert record["teacher_reads"] == "denoised" and record["teacher_denoiser"].endswith("imu_denoiser_soles")


def test_the_student_tracks_references_prepared_as_train_ppo_prepares_them(tmp_path):
    """--denoise-slow, --even-legs and --part-legs reach the distillation's ArtefactMix as train_ppo.py's
    do (a student of a policy trained on prepared takes sees them prepared alike); on clean episodes
    alone the legs' preparation still makes a mix; --denoise-slow without --denoise is refused."""
    flags = ["--corrupted-fraction", "0.75", "--strength", "0.75", "1.5", "--variants-per-clip", "3",
             "--denoise", str(MODELS / "imu_denoiser_soles"), "--denoise-slow", "0.5", "--even-legs", "--part-legs",
             "--ground", "--swing-lift"]
    ours = artefact_mix(build_parser().parse_args(["--out", str(tmp_path / "a"), *flags]), 7)
    theirs = ppo_artefact_mix(build_ppo_parser().parse_args(["--clips", "deepmimic:walk", "--run-dir",
                                                              str(tmp_path / "run"), *flags]), 0.75)
    assert ours.denoise_slow_s == 0.5 and ours.symmetry == LegSymmetry() and ours.legs == LegGap(min_gap_m=0.15)
    for field in ("denoiser", "denoise_slow_s", "symmetry", "legs", "grounding", "lift", "fraction", "strength"):
        assert getattr(ours, field) == getattr(theirs, field), field
    assert ours.judge == "given"  # judged against the take as given, as evaluate.py judges a prepared take
    legs_only = artefact_mix(build_parser().parse_args(
        ["--out", str(tmp_path / "b"), "--corrupted-fraction", "0", "--part-legs", "0.2"]), 7)
    assert legs_only.legs == LegGap(min_gap_m=0.2) and legs_only.symmetry is None and legs_only.denoiser is None
    with pytest.raises(ValueError, match="--denoise-slow 0.5 slows a denoiser's corrections"):
        artefact_mix(build_parser().parse_args(["--out", str(tmp_path / "c"), "--denoise-slow"]), 7)
