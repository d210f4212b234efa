"""The IMU denoiser: its features, a tiny network trained here on the DeepMimic clips, the shipped
one on a held-out walker, and evaluation through it (``agents/evaluate.py --denoise``)."""

import json
from dataclasses import replace

import numpy as np
import pytest
import torch

from perception.__main__ import main as perception_main
from perception.denoiser_training import (DenoiserTask, DenoiserTrainConfig, correction_loss, correction_target,
                                          sole_points_in_pelvis_frame, train_denoiser)
from perception.imu_denoiser import DEFAULT_DENOISER, IMUDenoiser, denoise, mirror_maps, motion_features
from perception.kinematics import torch_kinematics
from perception.weights import load_network
from reference_motion import rotations as rot
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.leg_gap import median_foot_gap
from reference_motion.library import load_motion
from reference_motion.stance import wider_stance
from reference_motion.transforms import mirror, resample


@pytest.fixture(scope="module")
def walk():
    return load_motion("deepmimic:walker/turn_left0")


def test_features_ignore_where_the_take_is_and_which_way_it_faces(walk):
    yaw = rot.from_axis_angle(np.array([0.0, 0.0, 1.0]), np.array(1.2))
    qpos = walk.qpos.copy()
    c, s = np.cos(1.2), np.sin(1.2)
    qpos[:, :2] = qpos[:, :2] @ np.array([[c, s], [-s, c]]) + [3.0, -7.0]
    qpos[:, 3:7] = rot.multiply(yaw, qpos[:, 3:7])
    moved = walk.with_qpos(qpos)
    assert motion_features(walk).shape == (walk.n_frames, 43 + 18)
    np.testing.assert_allclose(motion_features(moved), motion_features(walk), atol=1e-4)
    hm = load_model("humanoid_1seg")
    knee = hm.qpos_index("l_shin_y")
    np.testing.assert_array_equal(motion_features(walk)[:, knee - 7], walk.qpos[:, knee].astype(np.float32))


def test_network_takes_any_length_and_denoise_checks_model_and_rate(walk):
    net = IMUDenoiser(hidden=16)
    for frames in (2, 61, 300):
        assert net(torch.zeros(1, frames, 61)).shape == (1, frames, 44)
    out = denoise(net, walk)  # untrained: changes nothing
    assert out.source["denoised"] and np.array_equal(out.qpos, walk.qpos)
    with pytest.raises(ValueError, match="at 30 Hz.*reads 60 Hz"):
        denoise(net, resample(walk, 30.0))
    with pytest.raises(ValueError, match="humanoid_2seg.*humanoid_1seg"):
        denoise(net, load_motion("deepmimic:walk", "humanoid_2seg"))


def test_correction_target_is_what_turns_the_corrupted_take_back(walk):
    bad = corrupt(walk, ArtefactRecipe.imu(1.0), 3)
    target = correction_target(walk, bad)
    assert target.shape == (walk.n_frames, 44)
    np.testing.assert_allclose(bad.qpos[:, 7:] + target[:, :-1], walk.qpos[:, 7:], atol=1e-5)
    np.testing.assert_allclose(bad.qpos[:, 2] + target[:, -1], walk.qpos[:, 2], atol=1e-5)


def test_a_few_epochs_learn_to_undo_artefacts_on_a_held_out_clip(tmp_path):
    """Trained 12 small epochs on two DeepMimic clips, the denoiser already leaves less error
    on a walker it never saw (clean, and corrupted at strengths 0.5 and 1) than doing nothing; a
    run stopped and resumed ends as the run never stopped, and one on other clips is refused."""
    config = DenoiserTrainConfig(hidden=32, windows_per_epoch=256, batch_size=16, max_epochs=12, window=120)
    clips, val = ["deepmimic:walk", "deepmimic:run"], ["deepmimic:walker/turn_left0"]
    sidecar = train_denoiser(clips, val, tmp_path / "run", config, progress=False)
    untrained = DenoiserTask(clips, val, config).validation_score(IMUDenoiser(hidden=32))
    assert sidecar["best_val"] < 0.8 * untrained
    # stopped after 6 epochs and resumed to 12: the same weights as the run never stopped
    train_denoiser(clips, val, tmp_path / "stopped", replace(config, max_epochs=6), progress=False)
    resumed = train_denoiser(clips, val, tmp_path / "stopped", config, progress=False)
    assert resumed["epochs"] == 12 and resumed["best_val"] == sidecar["best_val"]
    assert torch.equal(torch.load(tmp_path / "stopped" / "best.pt")["out.weight"],
                       torch.load(tmp_path / "run" / "best.pt")["out.weight"])
    with pytest.raises(ValueError, match="holds a run on other clips"):
        train_denoiser(["deepmimic:walk"], val, tmp_path / "run", config, progress=False)


def test_posture_copies_join_the_training_takes_seeded():
    """``postures=2``: every take (mirrored copies too) twice more, each with its own posture drawn
    from the seed (the same for the same seed), the same for both legs."""
    config = DenoiserTrainConfig(postures=2, seed=5)
    task = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], config)
    assert [m.name for m in task.train] == ["deepmimic:walk", "deepmimic:walk (mirrored)", "deepmimic:walk (posture 0)",
                                            "deepmimic:walk (posture 1)", "deepmimic:walk (mirrored) (posture 0)",
                                            "deepmimic:walk (mirrored) (posture 1)"]
    hm = load_model("humanoid_1seg")
    offsets = [np.array(m.source["posture_rad"]) for m in task.train[2:]]
    assert all(np.abs(a - b).max() > 0.01 for i, a in enumerate(offsets) for b in offsets[:i])
    left, right = hm.qpos_index("l_thigh_x") - 7, hm.qpos_index("r_thigh_x") - 7
    assert all(abs(o[left] + o[right]) < 1e-9 for o in offsets)  # both legs out (or in) alike
    again = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], config)
    np.testing.assert_array_equal(again.train[3].qpos, task.train[3].qpos)
    other = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], replace(config, seed=6))
    assert np.abs(other.train[3].qpos - task.train[3].qpos).max() > 0.01
    with pytest.raises(ValueError, match="postures must be >= 0"):
        DenoiserTrainConfig(postures=-1)
    with pytest.raises(ValueError, match="dilations must be positive"):
        DenoiserTrainConfig(dilations=(1, 0))
    with pytest.raises(ValueError, match="sole_weight must be >= 0"):
        DenoiserTrainConfig(sole_weight=-1.0)


def test_stance_copies_join_the_training_takes_seeded_within_their_range():
    """``stances=1``: every take (the mirrored copy too) once more, walked with the feet apart by a
    width drawn from ``stance_extra_m`` with the seed: the feet's median gap grows by about that much."""
    config = DenoiserTrainConfig(stances=1, stance_extra_m=(0.15, 0.3), seed=5)
    task = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], config)
    assert len(task.train) == 4 and task.train[2].name.startswith("deepmimic:walk (stance +")
    extras = [m.source["extra_stance_m"] for m in task.train[2:]]
    assert all(0.15 <= e <= 0.3 for e in extras) and extras[0] != extras[1]
    for take, copy, extra in zip(task.train[:2], task.train[2:], extras):
        grown = median_foot_gap("humanoid_1seg", copy.qpos) - median_foot_gap("humanoid_1seg", take.qpos)
        assert abs(grown - extra) < 0.05, (grown, extra)
    again = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], config)
    np.testing.assert_array_equal(again.train[3].qpos, task.train[3].qpos)
    other = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], replace(config, seed=6))
    assert other.train[2].source["extra_stance_m"] != extras[0]
    postured = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], replace(config, postures=1))
    assert [m.source["extra_stance_m"] for m in postured.train[4:]] == extras  # a stream of its own
    with pytest.raises(ValueError, match="stances must be >= 0"):
        DenoiserTrainConfig(stances=-1)
    for bad in ((0.3, 0.1), (float("nan"), 0.2), (-0.5, 0.1), (0.1,)):
        with pytest.raises(ValueError, match="DenoiserTrainConfig.stance_extra_m"):
            DenoiserTrainConfig(stance_extra_m=bad)
    with pytest.raises(SystemExit, match="--stance-extra nan 0.2: expected finite metres"):  # the CLI names the flag
        perception_main(["train-denoiser", "--run-dir", "unused", "--stance-extra", "nan", "0.2"])


def test_speeds_join_the_training_takes_played_faster_and_slower():
    """``speeds=(1.0, 0.8)``: every take (its mirror image too) as recorded and at 0.8 times its
    pace, which lasts 1/0.8 as long; a speed of 0 or none at all is refused."""
    task = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"], DenoiserTrainConfig(speeds=(1.0, 0.8)))
    assert len(task.train) == 4
    as_recorded, slower = task.train[0], task.train[1]
    assert slower.n_frames == pytest.approx(as_recorded.n_frames / 0.8, abs=2)
    for bad in ((), (1.0, 0.0)):
        with pytest.raises(ValueError, match="speeds must be one or more speeds > 0"):
            DenoiserTrainConfig(speeds=bad)


def test_sole_term_counts_errors_that_move_the_feet_and_only_those():
    """A hand-made case on the standing pose (every hinge at zero): the sole points hang below the
    pelvis, the left ones on the left; a 0.1 rad error on an elbow leaves the sole term at zero, the
    same error on a knee moves the foot's two sole points by about 0.1 rad times their distance
    from the knee (a heel ≈ 0.45 m below it: ≈ 4.5 cm), and the term scales with its weight."""
    hm = load_model("humanoid_1seg")
    kin, n = torch_kinematics("humanoid_1seg"), len(hm.hinge_names)
    standing = torch.zeros(1, 5, n)
    soles = sole_points_in_pelvis_frame(kin, standing[0])  # (5, 4, 3): left_toe, right_toe, left_heel, right_heel
    assert soles.shape == (5, 4, 3)
    assert (soles[..., 2] < -0.7).all() and (soles[:, [0, 2], 1] > 0.05).all() and (soles[:, [1, 3], 1] < -0.05).all()
    # the corrupted take stands with its left knee bent 0.3 rad; the target bends it back straight
    given = standing.clone()
    given[..., hm.hinge_names.index("l_shin_y")] = 0.3
    target = torch.zeros(1, 5, n + 1)
    target[..., hm.hinge_names.index("l_shin_y")] = -0.3
    for hinge, moves_feet in (("l_forearm_y", False), ("l_shin_y", True)):
        prediction = target.clone()
        prediction[..., hm.hinge_names.index(hinge)] += 0.1
        plain = float(correction_loss(prediction, target, given, kin, 0.0))
        assert plain == pytest.approx(0.01 / (n + 1))
        with_soles = float(correction_loss(prediction, target, given, kin, 4.0))
        sole_term = (with_soles - plain) / 4.0
        if not moves_feet:
            assert sole_term == pytest.approx(0.0, abs=1e-9)
            continue
        moved = sole_points_in_pelvis_frame(kin, (given + prediction[..., :n])[0])[0] - soles[0]
        distance = moved.norm(dim=-1)
        assert distance[[1, 3]].max() < 1e-6  # the right foot stays
        assert 0.03 < float(distance[2]) < 0.06  # left heel, ~0.45 m below the knee
        assert sole_term == pytest.approx(float((moved ** 2).sum()) / 12, rel=1e-4)
        assert float(correction_loss(prediction, target, given, kin, 8.0)) == pytest.approx(plain + 8 * sole_term,
                                                                                            rel=1e-5)


def test_height_weight_adds_the_pelvis_height_error_alone():
    """A 2 cm pelvis height error counts once among the n_hinge + 1 channels, plus ``height_weight``
    times its square; a hinge error is untouched by the weight."""
    kin, n = torch_kinematics("humanoid_1seg"), len(load_model("humanoid_1seg").hinge_names)
    given, target = torch.zeros(1, 4, n), torch.zeros(1, 4, n + 1)
    high = target.clone()
    high[..., -1] = 0.02
    assert float(correction_loss(high, target, given, kin, 0.0)) == pytest.approx(0.0004 / (n + 1))
    assert float(correction_loss(high, target, given, kin, 0.0, 10.0)) == pytest.approx(0.0004 / (n + 1) + 0.004)
    bent = target.clone()
    bent[..., 0] = 0.1
    assert float(correction_loss(bent, target, given, kin, 0.0, 10.0)) == pytest.approx(0.01 / (n + 1))
    with pytest.raises(ValueError, match="height_weight must be >= 0"):
        DenoiserTrainConfig(height_weight=-1.0)


def test_sole_points_are_those_of_the_posed_body_seen_from_its_pelvis(walk):
    """Against the world sole points of the take's own frames: moved into the pelvis's frame, they
    are what :func:`sole_points_in_pelvis_frame` gives from the hinge angles alone."""
    kin = torch_kinematics(walk.model)
    qpos = torch.from_numpy(walk.qpos[::40]).float()
    _, world = kin.points(qpos)
    local = torch.einsum("tji,tkj->tki", torch.from_numpy(rot.to_matrix(walk.qpos[::40, 3:7])).float(),
                         world - qpos[:, None, :3])
    assert torch.allclose(sole_points_in_pelvis_frame(kin, qpos[:, 7:]), local, atol=1e-5)


def test_the_task_loss_reads_the_corrupted_take_s_hinges():
    """``DenoiserTask``'s loss with the sole and height terms: an untrained network (corrections
    zero) costs what :func:`correction_loss` gives for the corrupted take's own hinge angles."""
    task = DenoiserTask(["deepmimic:walk"], ["deepmimic:run"],
                        DenoiserTrainConfig(hidden=16, sole_weight=3.0, height_weight=50.0))
    net = task.network()
    clean = task.train[0]
    given = corrupt(clean, ArtefactRecipe.imu(1.0), 3)
    features = torch.from_numpy(motion_features(given))[None]
    target = torch.from_numpy(correction_target(clean, given))[None]
    given_hinges, kin = torch.from_numpy(given.qpos[:, 7:]).float()[None], torch_kinematics(clean.model)
    expected = correction_loss(torch.zeros_like(target), target, given_hinges, kin, 3.0, 50.0)
    with torch.no_grad():
        assert float(task._loss(net, features, target)) == pytest.approx(float(expected), rel=1e-5)
    without_height = correction_loss(torch.zeros_like(target), target, given_hinges, kin, 3.0)
    assert float(expected) > float(without_height) * 1.05  # the height's term is there
    assert float(expected) > 2 * float((target ** 2).mean())  # the soles' term is there and not small


def test_cli_ships_a_network_that_loads_and_refuses_overlapping_splits(tmp_path):
    out = tmp_path / "shipped"
    perception_main(["train-denoiser", "--clips", "deepmimic:walk", "--val-clips", "deepmimic:run", "--run-dir",
                     str(tmp_path / "run"), "--out", str(out), "--epochs", "1", "--windows-per-epoch", "32",
                     "--hidden", "32", "--strength", "0.5", "1.0", "--clean-fraction", "0.1", "--postures", "1",
                     "--stances", "1", "--stance-extra", "0.1", "0.2", "--speeds", "1", "1.2", "--dilations", "1", "4",
                     "--window", "120", "--sole-weight", "2",
                     "--height-weight", "3", "--no-progress"])
    net = load_network(out, "denoiser")
    assert isinstance(net, IMUDenoiser) and net.config["hidden"] == 32 and tuple(net.config["dilations"]) == (1, 4)
    assert [conv.dilation[0] for conv in net.convs] == [1, 4]
    config = json.loads((out / "sidecar.json").read_text())["config"]
    given = (config["hidden"], config["strength"], config["clean_fraction"], config["postures"], config["dilations"],
             config["window"], config["sole_weight"], config["speeds"], config["height_weight"], config["stances"],
             config["stance_extra_m"])
    assert given == (32, [0.5, 1.0], 0.1, 1, [1, 4], 120, 2.0, [1.0, 1.2], 3.0, 1, [0.1, 0.2])
    with pytest.raises(ValueError, match="holds a 'denoiser' network, expected 'vgrf'"):
        load_network(out, "vgrf")
    with pytest.raises(ValueError, match="deepmimic:walk are in both"):
        DenoiserTask(["deepmimic:walk"], ["deepmimic:walk"], DenoiserTrainConfig())


def test_shipped_denoiser_undoes_hip_adduction_and_leaves_clean_takes_alone():
    """The default IMU denoiser (models/imu_denoiser_soles_quint_mirror) on a DeepMimic walker held
    out of its training: the 8° per hip of the adduction artefact (strength 1) mostly removed (2.8°
    left); the clean take changed by less than the artefacts' own 3.8° RMS (2.1° measured:
    DeepMimic's actor is not the library's)."""
    net = load_network(DEFAULT_DENOISER, "denoiser")
    clean = load_motion("deepmimic:walker/turn_right1")
    hm = load_model("humanoid_1seg")
    hips = [hm.qpos_index("l_thigh_x"), hm.qpos_index("r_thigh_x")]
    bad = corrupt(clean, ArtefactRecipe.only("adduction", 1.0), 0)
    before = np.degrees(np.abs((bad.qpos - clean.qpos)[:, hips].mean(0)))
    after = np.degrees(np.abs((denoise(net, bad).qpos - clean.qpos)[:, hips].mean(0)))
    np.testing.assert_allclose(before, 8.0, atol=0.1)
    assert after.max() < 3.0, after
    change = np.degrees(np.sqrt(((denoise(net, clean).qpos - clean.qpos)[:, 7:] ** 2).mean()))
    assert change < 3.5, change


def test_stance_trained_denoiser_gives_a_wide_stance_back():
    """``models/imu_denoiser_stances_quint_mirror`` (its members trained with ``--stances 1``) on a
    DeepMimic walker held out of its training, walked 0.3 m wider and IMU-corrupted (three draws): the
    suit narrows the feet's median gap by 0.28 m on average; the default denoiser leaves it 0.15 m too
    narrow, the stance-trained one 0.07 m (README, round 24)."""
    wide = wider_stance(load_motion("deepmimic:walker/0walk_forward"), 0.3)
    nets = [load_network(name, "denoiser") for name in (DEFAULT_DENOISER, "models/imu_denoiser_stances_quint_mirror")]

    def gap_error(motion):
        return median_foot_gap("humanoid_1seg", motion.qpos) - median_foot_gap("humanoid_1seg", wide.qpos)

    errors = np.array([[gap_error(m) for m in (given, *(denoise(net, given) for net in nets))]
                       for given in (corrupt(wide, ArtefactRecipe.imu(1.0), seed) for seed in range(3))]).mean(0)
    raw, default, stances = errors
    assert raw < -0.2 and default < -0.12 and stances > -0.1 and stances - default > 0.05, errors


def test_an_ensemble_averages_its_members_and_ships_and_loads(tmp_path, walk):
    """Two tiny denoisers with other weights, shipped as one by the CLI: its correction is the mean
    of theirs on a corrupted take; an ensemble of one, of ensembles, or of other humanoids is refused."""
    from perception.imu_denoiser import DenoiserEnsemble
    folders = []
    for seed in (1, 2):
        out = tmp_path / f"member{seed}"
        perception_main(["train-denoiser", "--clips", "deepmimic:walk", "--val-clips", "deepmimic:run", "--run-dir",
                         str(tmp_path / f"run{seed}"), "--out", str(out), "--epochs", "1", "--windows-per-epoch",
                         "32", "--hidden", "16", "--seed", str(seed), "--no-progress"])
        folders.append(out)
    perception_main(["ensemble-denoisers", *map(str, folders), "--out", str(tmp_path / "both")])
    both = load_network(tmp_path / "both", "denoiser")
    assert isinstance(both, DenoiserEnsemble) and len(both.members) == 2
    given = corrupt(walk, ArtefactRecipe.imu(1.0), 4)
    corrections = [denoise(load_network(f, "denoiser"), given).qpos - given.qpos for f in folders]
    assert np.abs(corrections[0] - corrections[1]).max() > 1e-4  # the members differ
    np.testing.assert_allclose(denoise(both, given).qpos - given.qpos, (corrections[0] + corrections[1]) / 2,
                               atol=1e-6)
    sidecar = json.loads((tmp_path / "both" / "sidecar.json").read_text())
    assert [m["folder"] for m in sidecar["ensemble_of"]] == [str(f) for f in folders]
    with pytest.raises(ValueError, match="at least two members"):
        DenoiserEnsemble([both.members[0].config])
    with pytest.raises(ValueError, match="one humanoid and frame rate"):
        DenoiserEnsemble([both.members[0].config, {**both.members[0].config, "fps": 30.0}])
    with pytest.raises(SystemExit):  # one member and no mirror images
        perception_main(["ensemble-denoisers", str(folders[0]), "--out", str(tmp_path / "x")])
    # an ensemble's folder gives its members; with the mirror images, each member's correction of the
    # mirrored take, mirrored back, joins the mean: exactly denoising the mirror image and mirroring back
    perception_main(["ensemble-denoisers", str(tmp_path / "both"), "--mirror-average", "--out", str(tmp_path / "m")])
    both_mirrored = load_network(tmp_path / "m", "denoiser")
    assert len(both_mirrored.members) == 2 and both_mirrored.mirror_average
    mirrored_back = mirror(denoise(both, mirror(given)))
    np.testing.assert_allclose(denoise(both_mirrored, given).qpos, (denoise(both, given).qpos + mirrored_back.qpos) / 2,
                               atol=1e-6)
    assert np.abs(mirrored_back.qpos - denoise(both, given).qpos).max() > 1e-4  # the mirror image is corrected otherwise
    assert json.loads((tmp_path / "m" / "sidecar.json").read_text())["mirror_average"] is True
    with pytest.raises(SystemExit, match="averages the mirror images too"):  # refused, not dropped
        perception_main(["ensemble-denoisers", str(tmp_path / "m"), "--out", str(tmp_path / "y")])
    with pytest.raises(SystemExit, match="given twice"):  # an ensemble and one of its own members
        perception_main(["ensemble-denoisers", str(tmp_path / "both"), str(folders[0]), "--out", str(tmp_path / "z")])


def test_features_of_the_mirror_image_are_the_features_mirrored(walk):
    """mirror_maps: the features of the mirrored take are the take's features permuted and signed
    (left and right swapped, lateral components negated), and the map is its own inverse."""
    (perm, sign), (out_perm, out_sign) = mirror_maps(walk.model)
    features = motion_features(walk)
    np.testing.assert_allclose(motion_features(mirror(walk)), features[:, perm] * sign, atol=1e-6)
    np.testing.assert_array_equal(features[:, perm][:, perm] * sign[perm] * sign, features)
    assert len(out_perm) == len(IMUDenoiser().output_names) and out_perm[-1] == len(out_perm) - 1  # height stays
    assert np.abs(features[:, perm] * sign - features).max() > 0.1  # a turning walk is not its own mirror image


def test_slow_corrections_keep_the_slow_part_of_the_hinge_corrections_and_no_height(walk):
    """SlowCorrections (--denoise-slow): the shipped denoiser's hinge corrections smoothed by a
    Gaussian of smooth_s (as scipy's gaussian_filter1d with its ends held), the pelvis height as
    given; a constant correction passes unchanged; bad settings are refused by name."""
    from scipy.ndimage import gaussian_filter1d

    from perception.imu_denoiser import SlowCorrections, slowed
    net = load_network(DEFAULT_DENOISER, "denoiser")
    take = corrupt(walk, ArtefactRecipe.imu(1.0), 7)
    full = denoise(net, take).qpos - take.qpos
    slow = denoise(SlowCorrections(net, 0.5), take).qpos - take.qpos
    np.testing.assert_allclose(slow[:, 7:], gaussian_filter1d(full[:, 7:], 0.5 * take.fps, axis=0, mode="nearest"),
                               atol=1e-5)
    assert np.abs(slow[:, :7]).max() == 0.0  # root, height included, as given
    assert np.abs(np.diff(slow[:, 7:], axis=0)).max() < 0.2 * np.abs(np.diff(full[:, 7:], axis=0)).max()

    class Constant(torch.nn.Module):  # corrects every hinge by 0.1 rad, the height by 0.1 m
        model, fps = net.model, net.fps

        def forward(self, features):
            return torch.full((*features.shape[:2], len(load_model(walk.model).hinge_names) + 1), 0.1)

    steady = denoise(SlowCorrections(Constant(), 1.0), take).qpos - take.qpos
    np.testing.assert_allclose(steady[:, 7:], 0.1, atol=1e-6)
    class Recorded(torch.nn.Module):  # corrections given in advance: a long batch of two takes
        model, fps = net.model, net.fps

        def __init__(self, corrections):
            super().__init__()
            self.corrections = corrections

        def forward(self, features):
            return self.corrections

    long = torch.from_numpy(np.random.default_rng(0).standard_normal((2, 500, 5)))
    smoothed = SlowCorrections(Recorded(long), 0.5)(torch.zeros(2, 500, 1))
    assert smoothed.dtype == long.dtype and smoothed.shape == long.shape
    np.testing.assert_allclose(smoothed[..., :-1].numpy(),
                               gaussian_filter1d(long[..., :-1].numpy(), 0.5 * net.fps, axis=1, mode="nearest"),
                               atol=1e-12)
    assert slowed(net, None) is net and SlowCorrections(net, 0.5).label == "denoiser's hinge corrections slowed to 0.5 s"
    from agents.evaluate import tracked_label
    assert tracked_label("models/x", denoiser=SlowCorrections(net, 0.5)) == \
        "models/x + denoiser's hinge corrections slowed to 0.5 s"
    assert tracked_label("models/x", denoiser=net) == "models/x"  # a denoiser used as it is is not named
    with pytest.raises(ValueError, match="SlowCorrections.smooth_s"):
        SlowCorrections(net, 0.0)
    with pytest.raises(ValueError, match="--denoise-slow 0.5 slows a denoiser's corrections: give --denoise too"):
        slowed(None, 0.5)
