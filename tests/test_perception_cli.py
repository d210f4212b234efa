"""The shipped contact networks through the command line: vGRF and contacts of a real clip, an
UnderPressure sequence, and footskate cleanup of a skating clip."""

import json

import numpy as np
import pytest
import torch

from perception.__main__ import main
from perception.skeleton import motion_joint_positions
from perception.weights import load_network
from reference_motion.bvh import load as load_bvh
from reference_motion.library import load_motion
from reference_motion.rotations import normalize


def test_contacts_of_a_walk_look_like_walking(tmp_path):
    main(["contacts", "deepmimic:walk", "--json", str(tmp_path / "c.json"), "--plot", str(tmp_path / "c.png")])
    data = json.loads((tmp_path / "c.json").read_text())
    vgrf, contacts = np.array(data["vgrf_bw"]), np.array(data["contacts"], bool)
    assert vgrf.shape == (76, 2) and contacts.shape == (76, 4)
    assert 0.8 < vgrf.sum(axis=1).mean() < 1.2  # the feet carry the body weight
    on_ground = contacts.reshape(-1, 2, 2).any(axis=1)  # (toe or heel) of the left and right foot
    assert ((0.45 < on_ground.mean(axis=0)) & (on_ground.mean(axis=0) < 0.85)).all()  # stance ≈ 60% of a stride
    assert on_ground.any(axis=1).all()  # walking: never both feet in the air
    assert (tmp_path / "c.png").stat().st_size > 20_000


def test_contacts_of_an_underpressure_sequence(tmp_path):
    # an UnderPressure-format file at 100 Hz: the walk's first pose (identity rotations on a
    # skeleton made of that pose) carried along the walk's pelvis trajectory
    positions = motion_joint_positions(load_motion("deepmimic:walk", fps=100.0))
    n = len(positions)
    q = np.zeros((n, 23, 4))
    q[..., 0] = 1.0
    item = {"angles": torch.tensor(normalize(q)), "skeleton": torch.tensor(positions[:1]),
            "trajectory": torch.tensor((positions[:, :1] - positions[:1, :1])),
            "forces": torch.zeros(n, 2, 16), "contacts": torch.zeros(n, 2, 2, dtype=torch.bool)}
    torch.save(item, tmp_path / "S1-walk.pth")
    result = main(["contacts", str(tmp_path / "S1-walk.pth")])
    assert len(result["vgrf_bw"]) == int(np.floor((n - 1) * 0.6 + 1e-6)) + 1  # resampled 100 → 60 Hz


def test_cleanup_stills_the_planted_feet_of_an_imu_walk(tmp_path):
    out = tmp_path / "clean.npz"
    result = main(["cleanup", "deepmimic:walk", "--corrupt", "imu", "--strength", "1", "--seed", "3",
                   "--out", str(out), "--json", str(tmp_path / "r.json"), "--plot", str(tmp_path / "r.png"),
                   "--bvh", str(tmp_path / "clean.bvh")])
    assert result["foot_speed_before_mps"] > 0.3  # IMU artefacts shake and slide the planted feet
    assert result["reduction"] > 0.8
    assert result["joint_shift_m"] < 0.03
    assert out.exists() and json.loads((tmp_path / "r.json").read_text())["reduction"] == result["reduction"]
    assert (tmp_path / "r.png").stat().st_size > 20_000
    assert load_bvh(tmp_path / "clean.bvh").n_frames == 76  # readable back
    free = main(["cleanup", "deepmimic:walk", "--corrupt", "imu", "--strength", "1", "--seed", "3",
                 "--pose-weight", "0", "--out", str(out)])
    assert free["joint_shift_m"] > 1.5 * result["joint_shift_m"]  # nothing holds the body near the input
    with pytest.raises(SystemExit, match="cleanup edits a Motion"):
        main(["cleanup", str(tmp_path / "x.pth"), "--out", str(out)])


def test_shipped_networks_load():
    assert load_network("models/vgrf", "vgrf") is not None
    assert load_network("models/contact_mlp", "mlp") is not None
