"""ContactVision's keypoint transformer (contactvision §5, §6.1; SPEC "Perception").

2D keypoints ``(T, K, 3)`` = (u px, v px, confidence) become per-frame features
(:func:`keypoint_features`): relative to the mid hip, divided by the subject's leg length in the
image, confidence kept, dropped points zero. A linear embedding to 128, a positional encoding
(learnable, or sinusoidal for the ablation), 7 encoder layers of 4 heads with 512-wide
feed-forward blocks, and a linear head give 4 contact logits per frame in CONTACT_CHANNELS order
(left_toe, right_toe, left_heel, right_heel). Sequences longer than the positional encoding are
read in half-overlapping windows (:func:`contact_probabilities`).
"""

from __future__ import annotations

import math

import numpy as np
import torch
from torch import nn

from perception.keypoints import KEYPOINT_SETS, KEYPOINTS

WINDOW = 128
"""Frames the network reads at once (ContactVision's L)."""

_LEG = {side: tuple(KEYPOINTS.index(f"{side}_{j}") for j in ("hip", "knee", "ankle")) for side in ("left", "right")}


def keypoint_features(keypoints: np.ndarray) -> np.ndarray:
    """Network inputs ``(T, 3K)`` float32 from keypoints ``(T, K, 3)`` (u, v in pixels,
    confidence; a point with confidence 0 is missing).

    Positions are taken relative to the mid hip (the mean of the two hips when the mid hip is
    missing) and divided by the subject's leg length in pixels (the median over frames of the
    longer hip–knee–ankle chain), so the features do not depend on image size, focal length or
    distance. Points missing, or in a frame whose mid hip is unknown, become (0, 0, 0).
    """
    kp = np.asarray(keypoints, dtype=np.float64)
    if kp.ndim != 3 or kp.shape[2] != 3 or kp.shape[1] < len(KEYPOINTS):
        raise ValueError(f"keypoints must have shape (frames, K >= {len(KEYPOINTS)}, 3) = (u, v, confidence) in "
                         f"KEYPOINTS order, got {kp.shape}")
    if not np.isfinite(kp).all():
        raise ValueError(f"keypoints contain NaN or inf (first at frame {int(np.argwhere(~np.isfinite(kp))[0, 0])})")
    seen = kp[..., 2] > 0
    hips = seen[:, _LEG["left"][0]] & seen[:, _LEG["right"][0]]
    root = np.where(seen[:, 0, None], kp[:, 0, :2],
                    0.5 * (kp[:, _LEG["left"][0], :2] + kp[:, _LEG["right"][0], :2]))
    has_root = seen[:, 0] | hips
    legs = []
    for chain in _LEG.values():
        ok = seen[:, list(chain)].all(1)
        length = np.linalg.norm(np.diff(kp[:, list(chain), :2], axis=1), axis=-1).sum(1)
        legs.append(np.where(ok, length, np.nan))
    per_frame = np.fmax(*legs)
    scale = float(np.nanmedian(per_frame)) if np.isfinite(per_frame).any() else np.nan
    if not np.isfinite(scale) or scale <= 1e-6:
        raise ValueError("keypoints: no frame shows a whole leg (hip, knee and ankle), so the subject's size in the "
                         "image is unknown")
    keep = seen & has_root[:, None]
    out = np.zeros_like(kp)
    out[..., :2] = np.where(keep[..., None], (kp[..., :2] - root[:, None]) / scale, 0.0)
    out[..., 2] = np.where(keep, kp[..., 2], 0.0)
    return out.reshape(len(kp), -1).astype(np.float32)


def sinusoidal_encoding(length: int, d_model: int) -> torch.Tensor:
    """The fixed positional encoding of Vaswani et al. ``(length, d_model)``."""
    position = torch.arange(length, dtype=torch.float32)[:, None]
    rate = torch.exp(torch.arange(0, d_model, 2, dtype=torch.float32) * (-math.log(10000.0) / d_model))
    pe = torch.zeros(length, d_model)
    pe[:, 0::2] = torch.sin(position * rate)
    pe[:, 1::2] = torch.cos(position * rate)
    return pe


class ContactTransformer(nn.Module):
    """Per-frame heel and toe contact logits from 2D keypoint features.

    Args:
        keypoints: ``"lower"`` (the 13 of ContactVision) or ``"full"`` (all 25 of BODY_25; ablation).
        positional: ``"learnable"`` (ContactVision) or ``"sinusoidal"`` (ablation).
        d_model, layers, heads, feedforward: 128, 7, 4, 512 (contactvision §6.1).
        dropout: 0.009 (ContactVision's Optuna choice).
        window: frames of positional encoding (L = 128).
        fps: frame rate the network was trained at; other rates are resampled by
            :func:`contact_probabilities`.

    ``forward(features (B, T, 3K), padding (B, T) bool | None) -> logits (B, T, 4)`` with T ≤ window;
    ``padding`` marks frames that are not part of the sequence.
    """

    def __init__(self, keypoints: str = "lower", positional: str = "learnable", d_model: int = 128,
                 layers: int = 7, heads: int = 4, feedforward: int = 512, dropout: float = 0.009,
                 window: int = WINDOW, fps: float = 60.0):
        super().__init__()
        if keypoints not in KEYPOINT_SETS:
            raise ValueError(f"unknown keypoint set {keypoints!r}; expected one of {', '.join(KEYPOINT_SETS)}")
        if positional not in ("learnable", "sinusoidal"):
            raise ValueError(f"unknown positional encoding {positional!r}; expected 'learnable' or 'sinusoidal'")
        self.config = {"keypoints": keypoints, "positional": positional, "d_model": d_model, "layers": layers,
                       "heads": heads, "feedforward": feedforward, "dropout": dropout, "window": window, "fps": fps}
        self.input_names = KEYPOINT_SETS[keypoints]
        self.window, self.fps = window, float(fps)
        self.embed = nn.Linear(3 * len(self.input_names), d_model)
        if positional == "learnable":
            self.position = nn.Parameter(0.02 * torch.randn(window, d_model))
        else:
            self.register_buffer("position", sinusoidal_encoding(window, d_model))
        layer = nn.TransformerEncoderLayer(d_model, heads, feedforward, dropout, batch_first=True)
        self.encoder = nn.TransformerEncoder(layer, layers, enable_nested_tensor=False)
        self.head = nn.Linear(d_model, 4)

    def forward(self, features: torch.Tensor, padding: torch.Tensor | None = None) -> torch.Tensor:
        T = features.shape[1]
        if T > self.window:
            raise ValueError(f"{T} frames exceed the network's window of {self.window}; use contact_probabilities()")
        x = self.embed(features) + self.position[:T]
        return self.head(self.encoder(x, src_key_padding_mask=padding))


def windows_over(n_frames: int, window: int) -> list[int]:
    """Start frames of half-overlapping windows covering ``n_frames`` (the last one ends at the end)."""
    if n_frames <= window:
        return [0]
    starts = list(range(0, n_frames - window + 1, window // 2))
    return starts if starts[-1] == n_frames - window else starts + [n_frames - window]


def _resample(features: np.ndarray, fps: float, new_fps: float, n: int) -> np.ndarray:
    """``n`` frames at ``new_fps`` of ``features (T, 3K)`` at ``fps``: linear between two frames
    where the point is seen in both, else the nearest frame (a missing point stays missing)."""
    t = np.arange(n) * fps / new_fps
    lo = np.clip(np.floor(t).astype(int), 0, len(features) - 1)
    hi = np.minimum(lo + 1, len(features) - 1)
    w = (t - lo)[:, None]
    a, b = features[lo].reshape(n, -1, 3), features[hi].reshape(n, -1, 3)
    both = (a[..., 2] > 0) & (b[..., 2] > 0)
    nearest = np.where((w >= 0.5)[:, :, None], b, a)
    linear = (1 - w)[:, :, None] * a + w[:, :, None] * b
    return np.where(both[..., None], linear, nearest).reshape(n, -1).astype(np.float32)


@torch.no_grad()
def contact_probabilities(net: ContactTransformer, keypoints: np.ndarray, fps: float,
                          batch_size: int = 64) -> np.ndarray:
    """Contact probabilities ``(T, 4)`` of a whole sequence of keypoints ``(T, K, 3)`` (pixels,
    confidence) filmed at ``fps``: resampled to the network's rate, read in half-overlapping
    windows (``batch_size`` at a time; overlaps averaged), and sampled back at the input frames."""
    if fps <= 0:
        raise ValueError(f"fps must be positive, got {fps}")
    kp = np.asarray(keypoints)
    if kp.ndim == 3 and kp.shape[1] != len(net.input_names):
        raise ValueError(f"keypoints have {kp.shape[1]} points per frame; this network reads {len(net.input_names)} "
                         f"({', '.join(net.input_names[:3])}, ...)")
    features = keypoint_features(kp)
    T = len(features)
    times = np.arange(T) / fps
    n = max(1, int(round(times[-1] * net.fps)) + 1)
    x = torch.from_numpy(_resample(features, fps, net.fps, n))
    total, count = torch.zeros(n, 4), torch.zeros(n, 1)
    net.eval()
    starts = windows_over(n, net.window)
    length = min(n, net.window)
    for batch in torch.split(torch.tensor(starts), batch_size):   # equal-length windows, read in batches
        windows = torch.stack([x[s:s + length] for s in batch.tolist()])
        for s, p in zip(batch.tolist(), torch.sigmoid(net(windows))):
            total[s:s + length] += p
            count[s:s + length] += 1
    probs = (total / count).numpy()
    back = np.clip(np.round(times * net.fps).astype(int), 0, n - 1)
    return probs[back]


CONTACT_THRESHOLD = 0.5
"""Probability above which a frame is called a contact (contactvision §5.1)."""


def detect_contacts(net: ContactTransformer, keypoints: np.ndarray, fps: float) -> np.ndarray:
    """Contacts ``(T, 4)`` bool of keypoints ``(T, K, 3)`` filmed at ``fps``:
    :func:`contact_probabilities` above :data:`CONTACT_THRESHOLD`."""
    return contact_probabilities(net, keypoints, fps) > CONTACT_THRESHOLD
