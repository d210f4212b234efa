"""Perception end to end on a tiny physics-labelled dataset made with the shipped walk policy:
generation (seeded, resumable, split by clip), training (resumable), shipping and loading
weights, evaluation, the CLI, cleanup, and clear errors for bad input."""

import json

import numpy as np
import pytest
import torch

from perception.__main__ import main
from perception.cleanup import CleanupConfig, CleanupObjective, cleanup, contact_speed, contact_targets, contact_weights, foot_targets
from perception.contacts import ContactFunction
from perception.kinematics import torch_kinematics
from agents.physics_dataset import DatasetConfig, generate
from perception.dataset import load_split
from perception.evaluation import ContactModels, evaluate_contacts, fit_ot
from perception.training import TrainConfig, train
from perception.vgrf import VGRFNet
from perception.weights import load_network, ship
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.quality import jitter, range_excursion



def test_dataset_records_physics_per_frame(dataset):
    train_seqs = load_split(dataset, "train")
    assert len(train_seqs) == 1 and train_seqs[0].clip == "deepmimic:walk"
    seq = train_seqs[0]
    assert seq.positions.shape == (300, 23, 3) and seq.forces.shape == (300, 2, 16) and seq.fps == 60.0
    totals = seq.forces.sum(axis=(1, 2))
    assert 0.85 < totals[30:].mean() < 1.15  # walking: on average the feet carry the body weight
    assert (seq.forces >= 0).all()
    gamma = ContactFunction()(seq.forces, seq.fps)
    assert 0.9 < (gamma == seq.contacts).mean()  # Γ agrees with the raw physics contact states
    single_or_double = gamma[:, :].reshape(-1, 2, 2).any(axis=1)  # (toe or heel) per foot
    assert single_or_double.any(axis=1).mean() > 0.95  # some foot is down nearly always
    assert {s.clip for s in load_split(dataset, "test")} == {"deepmimic:walker/turn_left0"}
    manifest = json.loads((dataset / "manifest.json").read_text())
    assert manifest["summary"]["train"]["frames"] == 300


def test_dataset_generation_resumes_and_refuses_other_settings(dataset, tiny_config):
    shard = next((dataset / "train").glob("*.npz"))
    stamp = shard.stat().st_mtime_ns
    generate(dataset, tiny_config, progress=False)  # nothing left to do
    assert shard.stat().st_mtime_ns == stamp
    with pytest.raises(ValueError, match="other settings"):
        generate(dataset, DatasetConfig(**{**tiny_config.__dict__, "seed": 1}), progress=False)


def test_dataset_generation_bad_input(tmp_path, walk):
    with pytest.raises(FileNotFoundError, match="policy models/none: no such directory"):
        generate(tmp_path / "a", DatasetConfig(policies=("models/none",), clips=("deepmimic:walk",)), progress=False)
    with pytest.raises(KeyError, match="unknown DeepMimic clip 'nonesuch'"):
        generate(tmp_path / "b", DatasetConfig(policies=("models/mimic_walk",), clips=("deepmimic:nonesuch",),
                                               variants=1, episodes=1), progress=False)
    with pytest.raises(FileNotFoundError, match="no shards"):
        load_split(tmp_path / "empty", "train")
    short = walk.with_qpos(walk.qpos[:40], loop=False)
    short.save(tmp_path / "short.npz")
    with pytest.raises(ValueError, match="short.npz' has 43 frames at 60 Hz after a 0.91x time warp.*no episode could be kept"):
        generate(tmp_path / "c", DatasetConfig(policies=("models/mimic_walk",), clips=(str(tmp_path / "short.npz"),),
                                               variants=1, episodes=1), progress=False)
    bad = walk.qpos.copy()
    bad[5, 10] = np.nan
    np.savez(tmp_path / "nan.npz", format="physmimic.motion/1", qpos=bad, fps=60.0, model="humanoid_1seg",
             name="nan", loop=False, source="{}")
    with pytest.raises(ValueError, match="nan.npz"):
        generate(tmp_path / "d", DatasetConfig(policies=("models/mimic_walk",), clips=(str(tmp_path / "nan.npz"),),
                                               variants=1, episodes=1), progress=False)


def test_bad_shards_are_named(tmp_path):
    (tmp_path / "train").mkdir()
    np.savez(tmp_path / "train" / "x.npz", positions=np.zeros((5, 17, 3)), forces=np.zeros((5, 2, 16)),
             contacts=np.zeros((5, 4), bool), qpos=np.zeros((5, 50)), episode=np.zeros(5, int),
             meta=json.dumps({"fps": 60.0, "clip": "x"}))
    with pytest.raises(ValueError, match=r"x.npz: joint positions must have shape \(frames, 23, 3\).*got \(5, 17, 3\)"):
        load_split(tmp_path, "train")
    bad = np.zeros((5, 23, 3))
    bad[2, 4, 1] = np.nan
    np.savez(tmp_path / "train" / "x.npz", positions=bad, forces=np.zeros((5, 2, 16)),
             contacts=np.zeros((5, 4), bool), qpos=np.zeros((5, 50)), episode=np.zeros(5, int),
             meta=json.dumps({"fps": 60.0, "clip": "x"}))
    with pytest.raises(ValueError, match="x.npz: joint positions contain NaN or inf \\(first at frame 2\\)"):
        load_split(tmp_path, "train")


def test_training_resumes_ships_and_loads(dataset, tmp_path):
    config = TrainConfig(window=48, windows_per_epoch=64, batch_size=32, max_epochs=1)
    run = tmp_path / "run"
    first = train(dataset, run, config, progress=False)
    assert first["epochs"] == 1 and first["best_val"] > 0 and first["kind"] == "vgrf"
    second = train(dataset, run, TrainConfig(**{**config.__dict__, "max_epochs": 2}), progress=False)
    assert second["epochs"] == 2 and [h["epoch"] for h in second["history"]] == [1, 2]
    with pytest.raises(ValueError, match="other settings"):
        train(dataset, run, TrainConfig(**{**config.__dict__, "lr": 0.1}), progress=False)
    # a run recorded before a setting existed resumes if the setting is at its default, not otherwise
    recorded = json.loads((run / "config.json").read_text())
    (run / "config.json").write_text(json.dumps({k: v for k, v in recorded.items() if k not in ("seed", "windows_per_epoch")}))
    with pytest.raises(ValueError, match="other settings"):  # 64 windows per epoch is not the default
        train(dataset, run, TrainConfig(**{**config.__dict__, "max_epochs": 3}), progress=False)
    (run / "config.json").write_text(json.dumps({k: v for k, v in recorded.items() if k != "seed"}))
    assert train(dataset, run, TrainConfig(**{**config.__dict__, "max_epochs": 3}), progress=False)["epochs"] == 3
    shipped = ship(run, tmp_path / "vgrf")
    net = load_network(shipped, "vgrf")
    assert isinstance(net, VGRFNet) and not net.training
    with pytest.raises(ValueError, match="holds a 'vgrf' network, expected 'mlp'"):
        load_network(shipped, "mlp")
    result = main(["evaluate-contacts", "--dataset", str(dataset), "--split", "val", "--vgrf", str(shipped),
                   "--mlp", str(tmp_path / "none"), "--json", str(tmp_path / "c.json"), "--plot", str(tmp_path / "c.png")])
    assert set(result["f1_by_tolerance_s"]) == {"vgrf", "ot"} and (tmp_path / "c.png").stat().st_size > 10_000


def test_weights_for_another_skeleton_or_garbage_are_refused(tmp_path):
    torch.save({"kind": "vgrf", "joints": ["hip", "knee"], "state_dict": {}}, tmp_path / "other.pt")
    with pytest.raises(ValueError, match="weights are for 2 input points"):
        load_network(tmp_path / "other.pt")
    (tmp_path / "junk.pt").write_bytes(b"\x00garbage")
    with pytest.raises(ValueError, match="junk.pt: not a readable weights file"):
        load_network(tmp_path / "junk.pt")
    with pytest.raises(FileNotFoundError, match="no such weights file"):
        load_network(tmp_path / "missing")


def test_evaluation_scores_all_three_models(dataset):
    test = load_split(dataset, "test")
    ot = fit_ot(load_split(dataset, "train"))
    assert 0.0 < ot.height_m < 0.4 and 0.0 < ot.speed_mps < 4.0
    result = evaluate_contacts(test, ContactModels(vgrf=VGRFNet().eval(), ot=ot))
    assert result["frames"] == sum(len(s.positions) for s in test)
    assert result["ot"]["overall"]["f1"] > 0.7  # thresholds fitted on walking work on another walk
    assert result["vgrf_rmse_percent_bw"] > 0
    curve = list(result["f1_by_tolerance_s"]["ot"].values())
    assert curve[0] == pytest.approx(result["ot"]["overall"]["f1"]) and curve == sorted(curve) and curve[-1] > curve[0]


def test_contact_weights_and_targets_by_hand():
    contacts = np.zeros((12, 4), bool)
    contacts[2:10, 0] = True
    w = contact_weights(contacts, edge_frames=2)
    assert w[2, 0] == pytest.approx(0.5) and np.allclose(w[3:9, 0], 1.0) and w[9, 0] == pytest.approx(0.5)
    assert not w[:, 1:].any() and w[0, 0] == 0
    soles = np.zeros((12, 4, 3))
    soles[:, 0, 0] = np.arange(12) * 0.01  # the toe slides 1 cm per frame
    soles[:, 0, 2] = 0.01
    pins = contact_targets(soles, contacts)
    assert np.allclose(pins[2:10, 0], [0.055, 0.0, 0.01]) and np.isnan(pins[0, 0]).all()


def test_heel_and_toe_pins_of_a_sliding_foot_sit_one_foot_length_apart():
    soles = np.zeros((14, 4, 3))
    soles[:, 2, 0] = np.arange(14) * 0.01        # the left heel slides 1 cm per frame...
    soles[:, 0, 0] = soles[:, 2, 0] + 0.2        # ...and the toe with it, 20 cm ahead
    contacts = np.zeros((14, 4), bool)
    contacts[1:9, 2] = True                      # heel strike to heel off
    contacts[4:13, 0] = True                     # foot flat to toe off: the longest phase
    pins = contact_targets(soles, contacts)
    assert np.allclose(pins[4:13, 0], [0.28, 0.0, 0.0])   # the toe's mean
    assert np.allclose(pins[1:9, 2], [0.08, 0.0, 0.0])    # 20 cm behind it, not the heel's own mean 0.045
    assert np.isnan(pins[0]).all() and np.isnan(pins[:, [1, 3]]).all()


def test_foot_targets_carry_the_correction_between_contacts():
    soles = np.zeros((10, 4, 3))
    soles[:, 0, 0] = np.arange(10) * 0.1         # the left toe moves 10 cm per frame; the heel stays
    pins = np.full((10, 4, 3), np.nan)
    pins[0:2, 0] = [0.0, 0.0, 0.0]               # corrections 0 and -0.1 m
    pins[6:8, 0] = [1.0, 0.0, 0.0]               # corrections +0.4 and +0.3 m
    targets = foot_targets(soles, pins)
    assert np.allclose(targets[[0, 1, 6, 7], 0, 0], [0.0, 0.0, 1.0, 1.0])
    assert targets[4, 0, 0] == pytest.approx(0.4 + 0.2)   # correction interpolated from -0.1 (frame 1) to 0.4 (frame 6)
    assert targets[4, 2, 0] == pytest.approx(0.2)         # the heel is carried along with its foot
    assert targets[9, 0, 0] == pytest.approx(0.9 + 0.3)   # the last correction held to the end
    assert np.array_equal(targets[:, [1, 3]], soles[:, [1, 3]])  # the right foot never touches: unchanged


def test_cleanup_objective_terms_by_hand(walk):
    q0 = torch.tensor(walk.qpos[:60], dtype=torch.float32)
    config = CleanupConfig()
    objective = CleanupObjective(q0, walk.fps, torch_kinematics(walk.model), load_network("models/vgrf", "vgrf"),
                                 ContactFunction(), config)
    at_input = objective.terms(q0)
    assert all(at_input[k].item() == 0.0 for k in ("traj", "vgrf", "pose", "smooth"))
    hm = load_model(walk.model)
    columns, ranges = hm.hinge_ranges
    angles = walk.qpos[:60, columns]
    excess = np.clip(angles - ranges[:, 1], 0, None) + np.clip(ranges[:, 0] - angles, 0, None)
    assert at_input["limit"].item() == pytest.approx((excess ** 2).sum(axis=1).mean(), abs=1e-7)
    spine = hm.qpos_index("spine_mid_x")
    q = q0.clone()
    q[10, spine] += 0.1                                   # one frame of one spine hinge edited by 0.1 rad
    edited = objective.terms(q)
    # second differences 0.1, -0.2, 0.1 at frames 9, 10, 11: (0.01 + 0.04 + 0.01) · w_smooth over 58 frames
    assert edited["smooth"].item() == pytest.approx(0.06 * config.w_smooth / 58, rel=1e-4)
    assert edited["pose"].item() > 0 and edited["traj"].item() == 0.0
    knee = hm.qpos_index("l_shin_y")
    q = q0.clone()
    q[:, knee] = float(ranges[list(columns).index(knee), 1]) + 0.1   # every frame 0.1 rad past the knee's limit
    assert objective.terms(q)["limit"].item() == pytest.approx(at_input["limit"].item() + 0.01, abs=1e-4)


def test_cleanup_lets_the_legs_absorb_a_drifting_root(walk):
    """The stance-skate artefact slides the whole body to and fro; the cleanup plants the feet by
    bending the legs, within the hinge ranges, without moving the body far or adding jitter."""
    net = load_network("models/vgrf", "vgrf")
    bad = corrupt(walk, ArtefactRecipe.only("skate"), 1)
    result = cleanup(bad, net)
    assert result.foot_speed_before > 0.15                              # measured: 0.20 m/s
    assert result.foot_speed_after < 0.35 * result.foot_speed_before   # measured: -86%
    assert result.joint_shift_m < 0.03                                  # measured: 0.6 cm
    columns, ranges = load_model(walk.model).hinge_ranges
    assert range_excursion(result.motion.qpos[:, columns], ranges) < 0.005   # rad; 0.2 without L_limit
    jitters = [jitter(m.qpos[:, 7:], m.fps) for m in (bad, result.motion)]
    assert jitters[1] < 1.1 * jitters[0]                                       # measured ×1.02; ×2.2 without L_smooth


def test_cleanup_rejects_bad_motion(walk):
    with pytest.raises(ValueError, match="cleanup setting w_pose must be a finite number >= 0, got -1"):
        CleanupConfig(w_pose=-1.0)
    with pytest.raises(ValueError, match="swing_weight must be in"):
        CleanupConfig(swing_weight=2.0)
    net = VGRFNet()
    with pytest.raises(ValueError, match="needs at least 3 frames"):
        cleanup(walk.with_qpos(walk.qpos[:2]), net)
    bad = walk.qpos[:10].copy()
    bad[4, 9] = np.nan
    with pytest.raises(ValueError, match=r"qpos has NaN/inf \(first at frame 4, column 9\)"):
        cleanup(walk.with_qpos(bad), net)  # a Motion never holds NaN: the error comes before cleanup


def test_cli_errors_are_one_line(tmp_path, capsys):
    with pytest.raises(SystemExit, match="error: .*no such weights file"):
        main(["contacts", "deepmimic:walk", "--vgrf", str(tmp_path / "none")])
    with pytest.raises(SystemExit, match="unknown DeepMimic clip"):
        main(["contacts", "deepmimic:nonesuch", "--vgrf", str(tmp_path / "none")])


def test_corrupted_clip_skates_more_for_the_cleanup_measure(walk):
    from perception.kinematics import torch_kinematics
    kin = torch_kinematics(walk.model)
    bad = corrupt(walk, ArtefactRecipe.only("skate"), 1)
    contacts = np.ones((walk.n_frames, 4), bool)
    speeds = [contact_speed(kin.points(torch.tensor(m.qpos, dtype=torch.float32))[1].numpy(), contacts, 60.0)
              for m in (walk, bad)]
    assert speeds[1] > speeds[0]
