"""Video front end: MediaPipe landmarks → keypoints, gap filling, and the whole video path on a
rendered MuJoCo rollout (skipped only when the ``video`` extra is not installed)."""

import json

import imageio.v2 as imageio
import numpy as np
import pytest

from perception.__main__ import main
from perception.contacts import ContactFunction, detection_scores
from perception.dataset import load_split
from perception.keypoints import KEYPOINTS
from perception.video import fill_gaps, landmarks_to_keypoints
from reference_motion.motion import Motion
from reference_motion.render import render_frames


def test_landmarks_map_to_the_13_keypoints():
    lm = np.zeros((2, 33, 3))
    lm[..., 2] = 0.9
    lm[:, 23, :2] = (0.4, 0.5)       # left hip
    lm[:, 24, :2] = (0.6, 0.5)       # right hip
    lm[:, 31, :2] = (0.45, 0.95)     # left foot index
    lm[1, 29, 2] = 0.2               # left heel barely visible in frame 1
    lm[1, 24, 2] = 0.3               # right hip barely visible: so is the mid hip
    kp = landmarks_to_keypoints(lm, 1000, 500)
    assert kp.shape == (2, 13, 3)
    k = {n: i for i, n in enumerate(KEYPOINTS)}
    assert np.allclose(kp[0, k["mid_hip"]], [500, 250, 0.9])
    assert np.allclose(kp[0, k["left_big_toe"]], [450, 475, 0.9]) and np.allclose(kp[0, k["left_small_toe"]], kp[0, k["left_big_toe"]])
    assert (kp[1, k["left_heel"]] == 0).all() and (kp[1, k["mid_hip"]] == 0).all() and (kp[1, k["right_hip"]] == 0).all()
    undetected = np.full((1, 33, 3), np.nan)
    assert (landmarks_to_keypoints(undetected, 10, 10) == 0).all()
    with pytest.raises(ValueError, match=r"shape \(frames, 33, 3\).*got \(2, 17, 3\)"):
        landmarks_to_keypoints(np.zeros((2, 17, 3)), 10, 10)


def test_gaps_of_up_to_three_frames_are_interpolated():
    kp = np.zeros((10, 13, 3))
    kp[:, :, 0] = np.arange(10)[:, None] * 10.0
    kp[:, :, 2] = 1.0
    kp[2:5, 0] = 0.0                 # a 3-frame gap: filled
    kp[6:10, 1] = 0.0                # runs to the end: stays missing
    kp[1:5, 2] = 0.0                 # 4 frames: too long
    out = fill_gaps(kp)
    assert np.allclose(out[2:5, 0, 0], [20, 30, 40]) and np.allclose(out[2:5, 0, 2], 1.0)
    assert (out[6:, 1] == 0).all() and (out[1:5, 2] == 0).all()


def test_gait_command_on_keypoints_and_3d_motion(tmp_path, walk):
    rng = np.random.default_rng(0)
    kp = np.zeros((120, 13, 3))
    kp[..., 2] = 1.0
    kp[..., :2] = rng.normal(300, 50, (120, 13, 2))
    np.savez(tmp_path / "kp.npz", keypoints=kp, fps=30.0)
    out = main(["gait", str(tmp_path / "kp.npz"), "--json", str(tmp_path / "g.json"), "--plot", str(tmp_path / "g.png")])
    assert len(out["contacts"]) == 120 and len(out["phases"]) == 120 and (tmp_path / "g.png").stat().st_size > 0
    assert json.loads((tmp_path / "g.json").read_text())["contacts_from"].startswith("keypoints")
    walk.save(tmp_path / "walk.npz")
    motion = main(["gait", str(tmp_path / "walk.npz")])
    p = motion["parameters"]
    assert motion["contacts_from"].startswith("VGRFNet") and len(motion["cycles"]) >= 3
    assert 0.5 < p["stance"] < 0.75 and p["stance"] + p["swing"] == pytest.approx(1.0)
    np.savez(tmp_path / "nofps.npz", keypoints=kp)
    with pytest.raises(SystemExit, match="nofps.npz: keypoint file has no field 'fps'"):
        main(["gait", str(tmp_path / "nofps.npz")])
    with pytest.raises(SystemExit, match="missing.mp4: no such video"):
        main(["gait", str(tmp_path / "missing.mp4")])


def test_video_of_a_rollout_gives_the_simulators_contacts(dataset, tmp_path):
    pytest.importorskip("mediapipe", reason="the `video` extra (mediapipe==0.10.14) is not installed")
    seq = load_split(dataset, "train")[0]                    # the walk policy's MuJoCo rollout, 5 s
    motion = Motion(seq.clip, seq.fps, seq.qpos[:240], seq.model)
    frames = render_frames(motion, 640, 480, fps=30, azimuth=135, elevation=-8, distance=3.5, clothed=True)
    imageio.mimsave(tmp_path / "rollout.mp4", frames, fps=30, macro_block_size=1)
    out = main(["gait", str(tmp_path / "rollout.mp4"), "--keypoints-out", str(tmp_path / "kp.npz")])
    with np.load(tmp_path / "kp.npz") as z:
        assert z["keypoints"].shape == (len(frames), 13, 3) and float(z["fps"]) == 30.0
        assert (z["keypoints"][:, 0, 2] > 0).mean() > 0.9   # MediaPipe finds the dressed character
    predicted = np.array(out["contacts"], bool)
    truth = ContactFunction()(seq.forces, seq.fps)[np.minimum(np.arange(len(predicted)) * 2, len(seq.forces) - 1)]
    scores = detection_scores(predicted, truth)
    # measured 0.83 (precision 0.84, recall 0.82); calling every frame a contact scores 0.66
    assert scores["overall"]["f1"] > 0.75, scores
    assert scores["overall"]["f1"] > detection_scores(np.ones_like(truth), truth)["overall"]["f1"] + 0.1


def test_clothed_rendering_dresses_the_character_and_leaves_the_model_as_it_was(walk):
    from reference_motion.humanoid.model import load_model

    model = load_model(walk.model).model
    before = model.geom_rgba.copy()
    short = walk.with_qpos(walk.qpos[:2], loop=False)
    grey = render_frames(short, 160, 120, azimuth=180, elevation=0, distance=3.0)[0]
    dressed = render_frames(short, 160, 120, azimuth=180, elevation=0, distance=3.0, clothed=True)[0]
    assert np.array_equal(model.geom_rgba, before)
    # the middle of the image (the torso, seen from the front) turns shirt-red
    centre = dressed[45:60, 75:85].reshape(-1, 3).mean(0)
    assert centre[0] > 2 * centre[2] and abs(int(grey[50, 80, 0]) - int(grey[50, 80, 2])) < 30


def test_a_video_without_a_person_or_a_broken_file_is_named(tmp_path):
    pytest.importorskip("mediapipe", reason="the `video` extra (mediapipe==0.10.14) is not installed")
    imageio.mimsave(tmp_path / "empty.mp4", np.full((10, 120, 160, 3), 90, np.uint8), fps=30, macro_block_size=1)
    with pytest.raises(SystemExit, match="empty.mp4: MediaPipe found no person in any of the 10 frames"):
        main(["gait", str(tmp_path / "empty.mp4")])
    (tmp_path / "broken.mp4").write_bytes(b"not a video")
    with pytest.raises(SystemExit, match="broken.mp4: not a readable video"):
        main(["gait", str(tmp_path / "broken.mp4")])


def test_without_mediapipe_the_video_path_says_how_to_get_it(tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "mediapipe", None)      # as if the `video` extra were not installed
    imageio.mimsave(tmp_path / "clip.mp4", np.zeros((3, 64, 64, 3), np.uint8), fps=30, macro_block_size=1)
    with pytest.raises(SystemExit, match=r'needs MediaPipe: pip install -e "\.\[video\]"'):
        main(["gait", str(tmp_path / "clip.mp4")])
