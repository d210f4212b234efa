"""Keypoint data (views relative to the subject, held-out test azimuths), training (resumable,
shippable), evaluation and gait-ratio errors, on the tiny physics dataset."""

import numpy as np
import pytest
import torch

from perception.__main__ import main
from perception.contact_transformer import ContactTransformer
from perception.contacts import ContactFunction
from perception.dataset import load_split
from perception.keypoint_data import (ViewConfig, View, body_heading, draw_train_view, film, load_keypoint_split,
                                      held_out_views)
from perception.keypoint_evaluation import evaluate_keypoint_contacts, film_split, gait_errors
from perception.keypoint_training import KeypointTask, KeypointTrainConfig, train_keypoints
from perception.keypoints import KEYPOINTS
from perception.weights import load_network, ship


def _hips(yaw, T=3):
    """Points (T, 13, 3) whose hips face world azimuth ``yaw``."""
    p = np.zeros((T, 13, 3))
    left = np.array([-np.sin(yaw), np.cos(yaw), 0.0]) * 0.1
    p[:, KEYPOINTS.index("left_hip")] = left
    p[:, KEYPOINTS.index("right_hip")] = -left
    return p


def test_heading_from_the_hips():
    assert body_heading(_hips(0.0)) == pytest.approx(0.0, abs=1e-9)
    assert body_heading(_hips(np.pi / 2)) == pytest.approx(np.pi / 2)
    assert body_heading(_hips(-2.0)) == pytest.approx(-2.0)


def test_training_views_never_come_near_the_test_azimuths():
    rng = np.random.default_rng(0)
    config = ViewConfig()
    views = [draw_train_view(rng, config) for _ in range(2000)]
    train_deg = np.degrees([v.azimuth for v in views]) % 360
    test_deg = np.array(config.test_azimuths_deg)
    gap = np.abs((train_deg[:, None] - test_deg[None] + 180) % 360 - 180).min(1)
    assert gap.min() >= 22.5 - config.azimuth_jitter_deg - 1e-9
    kinds = {v.kind for v in views}
    assert kinds == {"rig", "random", "handheld"}
    assert all(config.noise_px_range[0] <= v.noise_px <= config.noise_px_range[1] for v in views)
    assert [round(np.degrees(v.azimuth), 1) for v in held_out_views(config)] == list(config.test_azimuths_deg)
    with pytest.raises(ValueError, match="unknown test view kind 'drone'"):
        held_out_views(config, "drone")


def test_a_view_is_relative_to_the_subject(dataset):
    seq = load_keypoint_split(dataset, "val")[0]
    rng = np.random.default_rng(0)
    front = film(seq.points, View("rig", 0.0, 0.0, 0.0), rng, seq.fps, test=True)
    side = film(seq.points, View("rig", np.pi / 2, 0.0, 0.0), rng, seq.fps, test=True)
    hip_width = lambda kp: np.abs(kp[:, KEYPOINTS.index("left_hip"), 0] - kp[:, KEYPOINTS.index("right_hip"), 0]).mean()
    assert hip_width(front) > 3 * hip_width(side)       # seen from the front the hips are wide, from the side narrow
    # facing the camera, the subject's left hip is on the image's right
    assert (front[:, KEYPOINTS.index("left_hip"), 0] > front[:, KEYPOINTS.index("right_hip"), 0]).mean() > 0.9
    assert film(seq.points, View("rig", 0.0, 0.0, 0.0), rng, seq.fps, keypoints="full").shape[1] == 25


def test_labels_are_gamma_of_the_simulated_forces(dataset):
    seqs = load_keypoint_split(dataset, "train")
    raw = load_split(dataset, "train")
    assert len(seqs) == len(raw) and seqs[0].points.shape == (len(raw[0].positions), 25, 3)
    assert np.array_equal(seqs[0].labels, ContactFunction()(raw[0].forces, raw[0].fps))


def test_gait_errors_by_hand():
    # one right-foot cycle by Table 2 rows (LT, RT, LH, RH): heel strike, loading response, mid stance ×2,
    # terminal stance, pre-swing, toe-off/mid swing, terminal swing; then the next heel strike
    rows = [(1, 0, 0, 1), (1, 1, 0, 1), (0, 1, 0, 1), (0, 1, 0, 1), (0, 1, 1, 0), (1, 1, 1, 0), (1, 0, 1, 0),
            (1, 0, 0, 0)]
    walk = np.array(rows + rows + rows[:1], bool)
    zero = {"stance_mae_pp": 0.0, "swing_mae_pp": 0.0, "single_support_mae_pp": 0.0, "double_support_mae_pp": 0.0}
    assert gait_errors([walk], [walk]) == {"sequence": {**zero, "count": 1, "truth_count": 1},
                                           "cycle": {**zero, "count": 2, "truth_count": 2}}
    late = walk.copy()
    late[6] = (1, 1, 1, 0)          # toe-off one frame late in the first cycle: 7 of 8 frames in stance, not 6
    err = gait_errors([late], [walk])
    assert err["cycle"]["stance_mae_pp"] == pytest.approx(100 * (7 / 8 - 6 / 8) / 2)       # the second cycle is right
    assert err["cycle"]["double_support_mae_pp"] == pytest.approx(100 * (3 / 8 - 2 / 8) / 2)
    assert err["sequence"]["stance_mae_pp"] == pytest.approx(100 * (14 / 17 - 13 / 17))
    assert gait_errors([late], [np.zeros((17, 4), bool)])["sequence"]["truth_count"] == 0   # no gait in the truth
    missed = gait_errors([np.zeros((17, 4), bool)], [walk])["cycle"]     # nothing predicted: counted, not scored
    assert missed["count"] == 0 and missed["truth_count"] == 2 and np.isnan(missed["stance_mae_pp"])


def test_training_resumes_ships_and_evaluates(dataset, tmp_path):
    config = KeypointTrainConfig(window=32, batch_size=4, windows_per_epoch=8, max_epochs=1, val_views=1)
    run = tmp_path / "run"
    first = train_keypoints(dataset, run, config, progress=False)
    assert first["epochs"] == 1 and 0 <= first["best_val"] <= 1 and first["kind"] == "keypoints"
    second = train_keypoints(dataset, run, KeypointTrainConfig(**{**config.__dict__, "max_epochs": 2}), progress=False)
    assert [h["epoch"] for h in second["history"]] == [1, 2]
    with pytest.raises(ValueError, match="other settings"):
        train_keypoints(dataset, run, KeypointTrainConfig(**{**config.__dict__, "positional": "sinusoidal"}),
                        progress=False)
    shipped = ship(run, tmp_path / "kp")
    net = load_network(shipped, "keypoints")
    assert isinstance(net, ContactTransformer) and net.window == 32 and not net.training
    with pytest.raises(ValueError, match="holds a 'keypoints' network, expected 'vgrf'"):
        load_network(shipped, "vgrf")
    warm = KeypointTask(dataset, KeypointTrainConfig(**{**config.__dict__, "init_from": str(shipped)})).network()
    assert all(torch.equal(a, b) for a, b in zip(warm.state_dict().values(), net.state_dict().values()))
    with pytest.raises(ValueError, match="start from a network of the same shape"):
        KeypointTask(dataset, KeypointTrainConfig(**{**config.__dict__, "window": 64, "init_from": str(shipped)})).network()
    filmed = film_split(load_keypoint_split(dataset, "test"), held_out_views()[:2], test=True)
    result = evaluate_keypoint_contacts(net, filmed)
    assert result["sequences"] == 2 and set(result["f1_by_view"]) == {"rig@22.5", "rig@67.5"}
    assert 0 <= result["scores"]["overall"]["f1"] <= 1
    curve = list(result["f1_by_tolerance_s"].values())
    assert curve[0] == pytest.approx(result["scores"]["overall"]["f1"]) and curve == sorted(curve)
    out = main(["evaluate-keypoints", "--dataset", str(dataset), "--net", str(shipped), "--views", "rig",
                "--json", str(tmp_path / "kp.json")])
    assert (tmp_path / "kp.json").exists() and out["rig"]["sequences"] == 8
