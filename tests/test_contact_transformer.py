"""ContactTransformer: input features by hand, architecture as SPEC, windowed inference and
resampling, and clear errors."""

import numpy as np
import pytest
import torch

from perception.contact_transformer import (ContactTransformer, _resample, contact_probabilities, keypoint_features,
                                            sinusoidal_encoding, windows_over)
from perception.keypoints import KEYPOINTS


def _standing(T=1):
    """Keypoints (T, 13, 3): mid hip at (100, 100) px, legs straight down, each 100 px long."""
    kp = np.zeros((T, 13, 3))
    kp[..., 2] = 1.0
    pos = {"mid_hip": (100, 100), "right_hip": (90, 100), "right_knee": (90, 150), "right_ankle": (90, 200),
           "left_hip": (110, 100), "left_knee": (110, 150), "left_ankle": (110, 200)}
    for name in KEYPOINTS:
        kp[:, KEYPOINTS.index(name), :2] = pos.get(name, (100, 210))
    return kp


def test_features_are_hip_relative_and_leg_scaled():
    kp = _standing(3)
    kp[1, KEYPOINTS.index("left_heel"), 2] = 0.0           # dropped point
    kp[2, 0, 2] = 0.0                                        # mid hip missing: the hips' mean stands in
    kp[2, :, :2] += 50.0
    f = keypoint_features(kp).reshape(3, 13, 3)
    knee = KEYPOINTS.index("left_knee")
    assert np.allclose(f[0, knee], [0.1, 0.5, 1.0])         # (10, 50) px over a 100 px leg
    assert np.allclose(f[0, 0], [0.0, 0.0, 1.0])
    assert np.allclose(f[1, KEYPOINTS.index("left_heel")], 0.0)
    assert np.allclose(f[2, knee], [0.1, 0.5, 1.0]) and np.allclose(f[2, 0], 0.0)
    # the same pose twice as large in the image gives the same features
    big = kp.copy()
    big[..., :2] *= 2.0
    assert np.allclose(keypoint_features(big), keypoint_features(kp), atol=1e-6)


def test_features_refuse_bad_input():
    with pytest.raises(ValueError, match=r"shape \(frames, K >= 13, 3\).*got \(4, 13\)"):
        keypoint_features(np.zeros((4, 13)))
    bad = _standing(4)
    bad[2, 3, 0] = np.nan
    with pytest.raises(ValueError, match="NaN or inf \\(first at frame 2\\)"):
        keypoint_features(bad)
    legless = _standing(2)
    legless[:, KEYPOINTS.index("left_knee"), 2] = 0
    legless[:, KEYPOINTS.index("right_ankle"), 2] = 0
    with pytest.raises(ValueError, match="no frame shows a whole leg"):
        keypoint_features(legless)


def test_architecture_as_spec():
    net = ContactTransformer()
    assert net.embed.in_features == 39 and net.embed.out_features == 128
    assert len(net.encoder.layers) == 7 and net.encoder.layers[0].self_attn.num_heads == 4
    assert net.encoder.layers[0].linear1.out_features == 512 and net.head.out_features == 4
    assert isinstance(net.position, torch.nn.Parameter) and net.position.shape == (128, 128)
    sinus = ContactTransformer(positional="sinusoidal")
    assert not isinstance(sinus.position, torch.nn.Parameter)
    assert sum(p.numel() for p in net.parameters()) - sum(p.numel() for p in sinus.parameters()) == 128 * 128
    assert ContactTransformer(keypoints="full").embed.in_features == 75
    out = net(torch.zeros(2, 50, 39))
    assert out.shape == (2, 50, 4)
    with pytest.raises(ValueError, match="exceed the network's window of 128"):
        net(torch.zeros(1, 129, 39))
    with pytest.raises(ValueError, match="unknown positional encoding 'rotary'"):
        ContactTransformer(positional="rotary")


def test_sinusoidal_encoding_values():
    pe = sinusoidal_encoding(4, 8)
    assert np.allclose(pe[0], [0, 1, 0, 1, 0, 1, 0, 1])
    assert pe[1, 0] == pytest.approx(np.sin(1.0)) and pe[1, 3] == pytest.approx(np.cos(1.0 / 10000 ** (2 / 8)))


def test_windows_cover_the_sequence():
    assert windows_over(100, 128) == [0]
    assert windows_over(128, 128) == [0]
    assert windows_over(300, 128) == [0, 64, 128, 172]


def test_resampling_interpolates_seen_points_only():
    f = np.zeros((2, 39), np.float32)
    f[:, 2] = 1.0
    f[0, 0], f[1, 0] = 0.0, 1.0
    f[0, 5] = 1.0                                           # point 1 seen in frame 0 only
    f[0, 3] = 0.4
    out = _resample(f, 30.0, 60.0, 3).reshape(3, 13, 3)
    assert np.allclose(out[:, 0, 0], [0.0, 0.5, 1.0])
    assert np.allclose(out[:, 1, 0], [0.4, 0.0, 0.0])        # nearest: frame 0 at t=0; the later frames see nothing


def test_long_and_slow_sequences_are_read_whole():
    torch.manual_seed(0)
    net = ContactTransformer(layers=1).eval()
    kp = np.tile(_standing(), (300, 1, 1))
    kp[:, KEYPOINTS.index("left_heel"), 1] += 20 * np.sin(np.arange(300) / 10)[:, None].ravel()
    p60 = contact_probabilities(net, kp, 60.0)
    assert p60.shape == (300, 4) and ((p60 >= 0) & (p60 <= 1)).all()
    first = torch.sigmoid(net(torch.from_numpy(keypoint_features(kp[:128]))[None]))[0].detach().numpy()
    assert np.allclose(p60[:64], first[:64], atol=1e-5)      # frames only the first window sees
    p30 = contact_probabilities(net, kp[::2], 30.0)
    assert p30.shape == (150, 4)
    with pytest.raises(ValueError, match="25 points per frame; this network reads 13"):
        contact_probabilities(net, np.zeros((10, 25, 3)), 60.0)
