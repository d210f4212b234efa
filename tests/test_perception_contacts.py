"""Perception building blocks: the 23-joint skeleton, differentiable kinematics, Γ, scores, OT,
the networks and their augmentations, the UnderPressure loader."""

import numpy as np
import pytest
import torch

from perception.contacts import (ContactFunction, OptimalThresholds, detection_scores, drop_short_phases,
                                 f1_with_tolerance, transition_distance, vgrf_rmse_percent)
from perception.kinematics import torch_kinematics
from perception.skeleton import JOINTS, PARENTS, joint_map, mirror_positions, motion_joint_positions
from perception.underpressure_data import load_underpressure, underpressure_positions
from perception.vgrf import ContactMLP, VGRFNet, augment, count_parameters, msle
from reference_motion.humanoid.model import load_model
from reference_motion.transforms import mirror

FPS = 60.0


# ----------------------------------------------------------------------------- skeleton
def test_joints_sit_on_the_matching_bodies(walk):
    kin = load_model(walk.model).forward_kinematics(walk.qpos[:5])
    pos = motion_joint_positions(walk.with_qpos(walk.qpos[:5]))
    names = load_model(walk.model).body_names
    for joint, body in (("pelvis", "pelvis"), ("left_hip", "l_thigh"), ("right_knee", "r_shin"),
                        ("left_ankle", "l_foot"), ("right_wrist", "r_hand"), ("head", "head")):
        assert np.allclose(pos[:, JOINTS.index(joint)], kin.body_pos[:, names.index(body)])
    # the ball of the foot is ahead of the ankle and lower than it when standing
    ball, ankle = pos[0, JOINTS.index("left_foot")], pos[0, JOINTS.index("left_ankle")]
    assert 0.08 < np.linalg.norm(ball[:2] - ankle[:2]) < 0.2


def test_mirrored_motion_gives_mirrored_joint_positions(walk):
    clip = walk.with_qpos(walk.qpos[:30])
    assert np.allclose(motion_joint_positions(mirror(clip)), mirror_positions(motion_joint_positions(clip)), atol=1e-6)
    assert PARENTS[JOINTS.index("left_knee")] == JOINTS.index("left_hip")


def test_torch_kinematics_matches_mujoco(walk):
    for model in ("humanoid_1seg", "humanoid_2seg"):
        kin = torch_kinematics(model)
        clip = walk if model == walk.model else None
        qpos = clip.qpos[:40] if clip is not None else load_model(model).rest_qpos()[None].repeat(3, 0)
        joints, soles = kin.points(torch.tensor(qpos, dtype=torch.float32))
        ref = load_model(model).forward_kinematics(qpos)
        assert np.abs(soles.numpy() - ref.foot_points).max() < 1e-5
        assert np.abs(joints.numpy() - joint_map(model).positions(ref.body_pos, ref.body_quat)).max() < 1e-5


# ----------------------------------------------------------------------------- Γ and scores
def _forces(T: int) -> np.ndarray:
    return np.zeros((T, 2, 16))


def test_contact_function_heel_only_stance():
    f = _forces(60)
    f[10:40, 0, 0:4] = 0.15  # left heel carries 0.6 BW for 0.5 s
    c = ContactFunction(smooth_s=0.0)(f, FPS)
    assert c[10:40, 2].all() and not c[:10, 2].any() and not c[40:, 2].any()
    assert not c[:, [0, 1, 3]].any()


def test_contact_function_thresholds_and_midfoot_rescaling():
    f = _forces(30)
    f[:, 0, 0:4] = 0.08 / 4          # left foot total 0.08 BW < 10%: no contact at all
    f[:, 1, 0:4] = 0.03 / 4          # right heel 0.03 BW, but the midfoot carries 0.2 BW:
    f[:, 1, 4:8] = 0.2 / 4           # rescaled to the foot total the heel holds 0.23 BW
    c = ContactFunction(smooth_s=0.0)(f, FPS)
    assert not c[:, [0, 2]].any()
    assert c[:, 3].all() and not c[:, 1].any()


def test_short_contact_phases_are_dropped():
    f = _forces(40)
    f[5:10, 0, 8:16] = 0.1   # 5 frames = 0.083 s < 0.1 s
    f[20:30, 0, 8:16] = 0.1  # 10 frames kept
    c = ContactFunction(smooth_s=0.0)(f, FPS)
    assert not c[5:10, 0].any() and c[20:30, 0].all()
    assert drop_short_phases(np.array([[1], [1], [0], [1], [1], [1]], bool), 3)[:, 0].tolist() == [0, 0, 0, 1, 1, 1]


def test_contact_function_rejects_wrong_shape():
    with pytest.raises(ValueError, match=r"\(frames, 2, 16\)"):
        ContactFunction()(np.zeros((10, 16)), FPS)


def test_detection_scores_by_hand():
    true = np.array([[1, 0, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], [1, 1, 0, 0]], bool)
    pred = np.array([[1, 0, 0, 0], [0, 0, 0, 0], [1, 0, 0, 0], [1, 1, 0, 0]], bool)
    s = detection_scores(pred, true)
    assert s["left_toe"] == pytest.approx({"precision": 2 / 3, "recall": 2 / 3, "f1": 2 / 3})
    assert s["right_toe"]["f1"] == 1.0 and s["left_heel"]["f1"] == 0.0
    assert s["overall"]["precision"] == pytest.approx(3 / 4) and s["overall"]["recall"] == pytest.approx(3 / 4)


def test_f1_against_temporal_tolerance_by_hand():
    true = np.zeros((12, 1), bool)
    true[3:9] = True                                   # changes between frames 2|3 and 8|9
    distance = transition_distance(true)
    assert distance[:, 0].tolist() == [3, 2, 1, 1, 2, 3, 3, 2, 1, 1, 2, 3]
    assert transition_distance(np.ones((4, 1), bool))[:, 0].tolist() == [5, 5, 5, 5]   # no change
    pred = true.copy()
    pred[2] = True                                     # early onset, next to the change
    pred[10] = True                                    # a stray contact, 2 frames from it
    assert f1_with_tolerance(pred, true, distance / 10.0, 0.0) == pytest.approx(2 * 6 / (2 * 6 + 2))
    assert f1_with_tolerance(pred, true, distance / 10.0, 0.1) == pytest.approx(2 * 6 / (2 * 6 + 1))
    assert f1_with_tolerance(pred, true, distance / 10.0, 0.2) == 1.0


def test_vgrf_rmse_in_percent_body_weight():
    true, pred = _forces(10), _forces(10)
    pred[:, 0, 0] = 0.1  # left foot total off by 0.1 BW, right exact
    assert vgrf_rmse_percent(pred, true) == pytest.approx(100 * np.sqrt(0.01 / 2))


def test_ot_baseline_finds_the_thresholds_that_made_the_labels():
    rng = np.random.default_rng(0)
    pos = np.zeros((400, 23, 3))
    feet = [JOINTS.index(j) for j in ("left_foot", "right_foot", "left_ankle", "right_ankle")]
    # feet alternately planted (low, still) and swinging (high, moving)
    t = np.arange(400) / FPS
    for i, j in enumerate(feet):
        phase = np.sin(2 * np.pi * (t + 0.25 * i))
        pos[:, j, 2] = np.where(phase > 0, 0.02, 0.25) + 0.002 * rng.standard_normal(400)
        pos[:, j, 0] = np.cumsum(np.where(phase > 0, 0.0, 2.0)) / FPS
    height, speed = pos[:, feet, 2], np.linalg.norm(np.gradient(pos[:, feet], axis=0), axis=-1) * FPS
    labels = (height < 0.1) & (speed < 0.5)
    ot = OptimalThresholds.fit([(pos, labels, FPS)])
    assert detection_scores(ot.predict(pos, FPS), labels)["overall"]["f1"] > 0.99


# ----------------------------------------------------------------------------- networks
def test_vgrf_net_shape_size_and_invariance_to_placement_and_heading():
    net = VGRFNet().eval()
    assert 0.9e6 < count_parameters(net) < 1.2e6
    x = torch.randn(2, 37, 23, 3)
    out = net(x)
    assert out.shape == (2, 37, 2, 16) and (out >= 0).all()
    shifted = x + torch.tensor([3.0, -2.0, 0.0])
    assert torch.allclose(net(shifted), out, atol=1e-5)
    c, s = np.cos(2.0), np.sin(2.0)
    turned = x @ torch.tensor([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]], dtype=torch.float32)
    assert torch.allclose(net(turned), out, atol=1e-4)
    assert (net(x + torch.tensor([0.0, 0.0, 0.3])) - out).abs().max() > 1e-5  # height is seen
    assert ContactMLP()(x).shape == (2, 37, 4)


def test_msle_is_underpressure_eq1():
    f, g = torch.tensor([0.0, 1.0, 3.0]), torch.tensor([1.0, 1.0, 1.0])
    assert msle(g, f).item() == pytest.approx(np.mean([np.log(2) ** 2, 0.0, (np.log(4) - np.log(2)) ** 2]))


def test_augment_mirrors_feet_and_keeps_bone_symmetry(walk):
    pos = torch.tensor(motion_joint_positions(walk.with_qpos(walk.qpos[:20])), dtype=torch.float32)[None].repeat(64, 1, 1, 1)
    forces = torch.zeros(64, 20, 2, 16)
    forces[:, :, 0] = 1.0  # all weight on the left foot
    contacts = torch.zeros(64, 20, 4, dtype=torch.bool)
    contacts[..., 0] = True
    x, f, c = augment(pos, forces, contacts, torch.Generator().manual_seed(0), noise_m=0.0)
    flipped = f[:, 0, 1].sum(-1) > 0
    assert 10 < int(flipped.sum()) < 54
    assert (c[flipped][..., 1]).all() and not c[flipped][..., 0].any() and c[~flipped][..., 0].all()
    # left and right thighs keep equal lengths (UnderPressure's symmetric skeleton variation)
    hip, knee = JOINTS.index("left_hip"), JOINTS.index("left_knee")
    rhip, rknee = JOINTS.index("right_hip"), JOINTS.index("right_knee")
    left = (x[:, 0, knee] - x[:, 0, hip]).norm(dim=-1)
    right = (x[:, 0, rknee] - x[:, 0, rhip]).norm(dim=-1)
    original = (pos[0, 0, knee] - pos[0, 0, hip]).norm()
    ratio = torch.where(flipped, right, left) / original
    other = torch.where(flipped, left, right) / (pos[0, 0, rknee] - pos[0, 0, rhip]).norm()
    assert torch.allclose(ratio, other, atol=1e-4) and ratio.std() > 0.01
    # the artefact augmentations: noise makes the joints jitter, height offsets move the feet
    # off the floor, the labels stay as they were
    noisy, f2, c2 = augment(pos, forces, contacts, torch.Generator().manual_seed(0), noise_m=0.05)
    jerk = lambda p: (p[:, 2:] - 2 * p[:, 1:-1] + p[:, :-2]).norm(dim=-1).mean()  # noqa: E731
    assert jerk(noisy) > 5 * jerk(x)
    lowest = noisy[..., 2].amin(dim=(1, 2))
    assert lowest.std() > 0.02 and torch.equal(c2.sum(), c.sum())


# ----------------------------------------------------------------------------- UnderPressure data
def _write_pth(path, frames=50, angles=None, **overrides):
    skeleton = np.zeros((1, 23, 3))
    for j in range(1, 23):
        skeleton[0, j] = skeleton[0, PARENTS[j]] + np.array([0.0, 0.0, 0.1 * (1 if j < 15 else -1)])
    q = np.zeros((frames, 23, 4))
    q[..., 0] = 1.0
    item = {"angles": torch.tensor(q if angles is None else angles), "skeleton": torch.tensor(skeleton),
            "trajectory": torch.tensor(np.stack([np.linspace(0, 1, frames), np.zeros(frames), np.zeros(frames)], 1)[:, None]),
            "forces": torch.rand(frames, 2, 16), "contacts": torch.zeros(frames, 2, 2, dtype=torch.bool)}
    item["contacts"][:, 1, 0] = True  # heel (second index: back) of the left foot
    item.update(overrides)
    torch.save(item, path)
    return item


def test_underpressure_loader_forward_kinematics_and_resampling(tmp_path):
    item = _write_pth(tmp_path / "S1-walk.pth", frames=101)
    seq = load_underpressure(tmp_path / "S1-walk.pth")
    assert seq.fps == 60.0 and len(seq.positions) == 61  # 1 s at 100 Hz → 1 s at 60 Hz
    assert np.allclose(seq.positions[0], item["skeleton"][0].numpy(), atol=1e-6)
    assert np.allclose(seq.positions[-1, :, 0] - seq.positions[0, :, 0], 1.0, atol=1e-6)
    assert seq.contacts[:, 2].all() and not seq.contacts[:, [0, 1, 3]].any()  # → left_heel
    # a global quarter turn of the pelvis about z turns the whole body about the pelvis
    q = np.zeros((1, 23, 4))
    q[..., 0] = np.cos(np.pi / 4)
    q[..., 3] = np.sin(np.pi / 4)
    skel = item["skeleton"][0].numpy().copy()
    skel[3] += [0.1, 0.0, 0.0]
    turned = underpressure_positions(q, skel, np.zeros((1, 3)))
    assert np.allclose(turned[0, 3] - turned[0, 2], [0.0, 0.1, 0.1], atol=1e-9)
    net = VGRFNet().eval()
    assert net(torch.tensor(seq.positions)[None]).shape == (1, 61, 2, 16)


def test_underpressure_loader_errors(tmp_path):
    _write_pth(tmp_path / "short.pth", angles=np.ones((20, 19, 4)))
    with pytest.raises(ValueError, match=r"short.pth: field 'angles' has shape \(20, 19, 4\)"):
        load_underpressure(tmp_path / "short.pth")
    bad = np.zeros((50, 2, 16))
    bad[3, 0, 0] = np.nan
    _write_pth(tmp_path / "nan.pth", forces=torch.tensor(bad))
    with pytest.raises(ValueError, match="nan.pth: field 'forces' contains NaN"):
        load_underpressure(tmp_path / "nan.pth")
    (tmp_path / "junk.pth").write_bytes(b"not a pickle")
    with pytest.raises(ValueError, match="junk.pth: not a readable .pth sequence"):
        load_underpressure(tmp_path / "junk.pth")
