"""2D keypoint synthesis: keypoints on the body, pinhole projection, camera rigs, noise and
normalisation."""

import numpy as np
import pytest

from perception.keypoints import (KEYPOINTS, Camera, canonicalize, handheld_camera, look_at, motion_keypoints,
                                  normalize_image, observe, random_camera, ring_cameras)


def _static_camera(position, target, T=1, focal=1000.0):
    p = np.tile(np.asarray(position, float), (T, 1))
    t = np.tile(np.asarray(target, float), (T, 1))
    return Camera(p, look_at(p, t), focal, 1280, 720)


def test_pinhole_projection_by_hand():
    cam = _static_camera([-4.0, 0.0, 1.0], [0.0, 0.0, 1.0])  # looking along +x from 4 m
    uv, depth = cam.project(np.array([[[0.0, 0.0, 1.0], [0.0, -1.0, 1.0], [0.0, 0.0, 2.0], [-5.0, 0.0, 1.0]]]))
    assert np.allclose(uv[0, 0], [640, 360]) and depth[0, 0] == pytest.approx(4.0)
    assert np.allclose(uv[0, 1], [640 + 250, 360])  # world -y is the camera's right when looking along +x
    assert np.allclose(uv[0, 2], [640, 360 - 250])  # up in the world is up in the image
    assert depth[0, 3] < 0


def test_keypoints_sit_on_the_feet_and_legs(walk):
    k = motion_keypoints(walk.with_qpos(walk.qpos[:5]))
    assert k.shape == (5, 13, 3)
    idx = {n: i for i, n in enumerate(KEYPOINTS)}
    stance = int(np.argmin(k[:, idx["right_heel"], 2]))
    frame = k[stance]
    assert frame[idx["right_heel"], 2] < frame[idx["right_ankle"], 2] < frame[idx["right_knee"], 2]
    assert frame[idx["right_big_toe"], 0] > frame[idx["right_heel"], 0]  # toes ahead of the heel (walking +x)
    # big toes on the inner edge: the right big toe is left of (greater y than) the right small toe
    assert frame[idx["right_big_toe"], 1] > frame[idx["right_small_toe"], 1]
    assert np.allclose(frame[idx["mid_hip"]], 0.5 * (frame[idx["left_hip"]] + frame[idx["right_hip"]]), atol=1e-9)


def test_ring_views_surround_the_subject(walk):
    k = motion_keypoints(walk)
    cams = ring_cameras(k[:, 0])
    assert len(cams) == 8
    azimuths = [np.degrees(np.arctan2(*(c.position[0, 1::-1] - k[0, 0, 1::-1]))) % 360 for c in cams]
    assert np.allclose(np.diff(sorted(azimuths)), 45.0, atol=1e-6)
    for cam in cams:  # the subject stays in view as it walks
        uv, depth = cam.project(k)
        assert (depth > 0).all() and (uv[..., 0] > 0).all() and (uv[..., 0] < 1280).all()


def test_observations_noise_drops_and_shake(walk):
    k = motion_keypoints(walk)
    rng = np.random.default_rng(0)
    cam = random_camera(k[:, 0], rng)
    clean_uv, _ = cam.project(k)
    obs = observe(k, cam, rng, noise_px=2.0, drop_prob=0.1)
    kept = obs[..., 2] > 0
    assert 0.85 < kept.mean() < 0.95
    err = np.linalg.norm(obs[..., :2][kept] - clean_uv[kept], axis=-1)
    assert 1.5 < err.mean() < 3.5  # 2 px Gaussian noise: mean error 2·sqrt(π/2) ≈ 2.5 px
    assert (obs[~kept][:, :2] == 0).all() and ((obs[kept][:, 2] >= 0.5) & (obs[kept][:, 2] <= 1)).all()
    shaky = handheld_camera(k[:, 0], np.random.default_rng(1))
    jitter = np.linalg.norm(np.diff(shaky.position, axis=0), axis=-1)
    assert jitter.max() > 0 and np.isfinite(shaky.rotation).all()


def test_normalisation_and_canonicalisation():
    cam = _static_camera([-4.0, 0.0, 1.0], [0.0, 0.0, 1.0], T=1)
    kp = np.zeros((1, 13, 3))
    kp[0, :, 2] = 1.0
    kp[0, 0, :2] = [640, 360]
    kp[0, 1, :2] = [890, 360]
    kp[0, 2] = 0.0  # dropped
    c = canonicalize(kp, cam)
    assert np.allclose(c[0, 1, :2], [0.25, 0.0]) and np.allclose(c[0, 2], 0.0)
    n = normalize_image(kp, 1280, 720)
    assert np.allclose(n[0, 1, :2], [250 / 1280, 0.0]) and n[0, 0, 2] == 1.0
