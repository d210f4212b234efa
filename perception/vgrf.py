"""The UnderPressure vGRF network and the 3-layer MLP contact baseline (underpressure §4, §5.2).

Both read joint positions ``(B, T, 23, 3)`` (world frame, z up, m; UnderPressure's joint order,
:mod:`perception.skeleton`) at 60 Hz. Before the first layer they re-express the positions free of
global placement and heading (:func:`canonical_input`): every joint relative to the pelvis of the
same frame in the body's heading frame, heights kept as they are, and the pelvis' own entry
replaced by its velocity in that frame. Nothing is lost but where the body is and which way it
faces, to which vGRF are invariant. UnderPressure taught its network those invariances with random
translations and rotations; building them in spares a small CPU-trained network from learning
them, and keeps clips that wander far from the origin inside the training range.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import nn

from perception.skeleton import FOOT_JOINTS, JOINTS, MIRROR, N_JOINTS, PARENTS

N_CELLS = 16


_LEFT_HIP, _RIGHT_HIP = JOINTS.index("left_hip"), JOINTS.index("right_hip")


def canonical_input(positions: torch.Tensor, fps: float) -> torch.Tensor:
    """Translation- and heading-free features ``(B, T, 69)`` of joint positions ``(B, T, 23, 3)``:
    per frame, each joint relative to the pelvis in the body's heading frame (forward, left, up;
    "left" along the line from the right hip to the left hip, levelled), heights kept absolute, and
    the pelvis entry replaced by the pelvis velocity in that frame (m/s; forward, left, up)."""
    left = positions[:, :, _LEFT_HIP, :2] - positions[:, :, _RIGHT_HIP, :2]
    left = left / left.norm(dim=-1, keepdim=True).clamp_min(1e-6)
    forward = torch.stack([left[..., 1], -left[..., 0]], dim=-1)
    rel = positions[..., :2] - positions[:, :, :1, :2]
    x = torch.stack([(rel * forward[:, :, None]).sum(-1), (rel * left[:, :, None]).sum(-1), positions[..., 2]], -1)
    vel = torch.diff(positions[:, :, 0], dim=1, prepend=positions[:, :1, 0]) * fps
    if positions.shape[1] > 1:  # first frame: the forward difference instead of zero
        vel = torch.cat([vel[:, 1:2], vel[:, 1:]], dim=1)
    x[:, :, 0] = torch.stack([(vel[..., :2] * forward).sum(-1), (vel[..., :2] * left).sum(-1), vel[..., 2]], -1)
    return x.flatten(2)


class VGRFNet(nn.Module):
    """UnderPressure's network Ψ: joint positions ``(B, T, 23, 3)`` → cell vGRF ``(B, T, 2, 16)``
    in body weights (left foot first), for any ``T``.

    Four temporal convolutions (kernel 7, replicate padding; 128, 128, 256, 256 channels, ELU),
    then three per-frame fully connected layers (256, 256, 32; dropout 0.2 before each) with
    ELU and a softplus output: 1.0 M weights (UnderPressure: "approximately 1.1 million").
    """

    def __init__(self, fps: float = 60.0, channels: tuple[int, ...] = (128, 128, 256, 256), hidden: int = 256,
                 kernel: int = 7, dropout: float = 0.2):
        super().__init__()
        self.fps = float(fps)
        self.input_names = JOINTS
        layers: list[nn.Module] = []
        width = 3 * N_JOINTS
        for c in channels:
            layers += [nn.Conv1d(width, c, kernel, padding=kernel // 2, padding_mode="replicate"), nn.ELU()]
            width = c
        self.convs = nn.Sequential(*layers)
        self.head = nn.Sequential(nn.Dropout(dropout), nn.Linear(width, hidden), nn.ELU(),
                                  nn.Dropout(dropout), nn.Linear(hidden, hidden), nn.ELU(),
                                  nn.Dropout(dropout), nn.Linear(hidden, 2 * N_CELLS), nn.Softplus())
        # Start near a typical cell load (softplus(-3) = 0.05 BW), not at softplus(0) = 0.69 BW: from
        # there the first updates drive every output deep into softplus' flat tail, where no
        # gradient brings it back.
        nn.init.constant_(self.head[-2].bias, -3.0)

    def forward(self, positions: torch.Tensor) -> torch.Tensor:
        x = canonical_input(positions, self.fps)                    # (B, T, 69)
        x = self.convs(x.transpose(1, 2)).transpose(1, 2)          # (B, T, C)
        return self.head(x).unflatten(-1, (2, N_CELLS))


class ContactMLP(nn.Module):
    """The "3-layer MLP" of underpressure Table 2 (after Smith et al.): per frame, joint positions
    and velocities → three 128-unit ReLU layers → 4 contact logits (CONTACT_CHANNELS order)."""

    def __init__(self, fps: float = 60.0, hidden: int = 128):
        super().__init__()
        self.fps = float(fps)
        self.input_names = JOINTS
        self.net = nn.Sequential(nn.Linear(6 * N_JOINTS, hidden), nn.ReLU(), nn.Linear(hidden, hidden), nn.ReLU(),
                                 nn.Linear(hidden, hidden), nn.ReLU(), nn.Linear(hidden, 4))

    def forward(self, positions: torch.Tensor) -> torch.Tensor:
        x = canonical_input(positions, self.fps)
        vel = torch.diff(positions, dim=1, prepend=positions[:, :1]).flatten(2) * self.fps
        return self.net(torch.cat([x, vel], dim=-1))


def msle(predicted: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    """Mean squared logarithmic error, underpressure eq. 1: mean of (ln(F+1) − ln(F̂+1))²."""
    return torch.mean((torch.log1p(target) - torch.log1p(predicted)) ** 2)


def count_parameters(model: nn.Module) -> int:
    return sum(p.numel() for p in model.parameters())


# ----------------------------------------------------------------------------- augmentation
_LEFT = [i for i, j in enumerate(JOINTS) if j.startswith("left")]
_RIGHT = [MIRROR[i] for i in _LEFT]
_BONE_ORDER = list(range(1, N_JOINTS))  # parents always come before their children in JOINTS


def augment(positions: torch.Tensor, forces: torch.Tensor, contacts: torch.Tensor, generator: torch.Generator,
            bone_scale_std: float = 0.05, scale_range: tuple[float, float] = (0.9, 1.1),
            translation_m: float = 2.0, noise_m: float = 0.02, drift_mps: float = 0.2,
            height_m: float = 0.05) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """Augmentations of a batch ``(B, T, 23, 3)`` with its forces ``(B, T, 2, 16)`` and contacts
    ``(B, T, 4)``.

    UnderPressure's vGRF-invariant ones (§4.3): left/right mirroring (half the batch; feet and
    contact channels swap), a random rotation about the vertical axis, a random horizontal
    translation, a global scale, and skeleton variation: each bone's length scaled by
    ``1 + N(0, bone_scale_std)`` (the same on both sides) with the joint angles kept.

    And the artefacts of the clips the network is used on (IMU mocap, blends), with the labels
    kept, since our training motion comes from a simulator and has none of them: per window, white
    noise of σ ~ U(0, ``noise_m``) on every joint, a constant horizontal drift of the whole body
    at N(0, ``drift_mps``) m/s (foot skate), and a vertical offset ~ U(±``height_m``) (floating or
    penetration)."""
    B = positions.shape[0]
    x = positions.clone()
    flip = torch.rand(B, generator=generator) < 0.5
    if flip.any():
        x[flip] = x[flip][:, :, list(MIRROR)] * torch.tensor([1.0, -1.0, 1.0])
        forces = forces.clone()
        forces[flip] = forces[flip].flip(2)
        contacts = contacts.clone()
        contacts[flip] = contacts[flip][:, :, [1, 0, 3, 2]]
    # skeleton variation: rebuild positions from parent offsets with scaled bone lengths
    bone = 1.0 + bone_scale_std * torch.randn(B, N_JOINTS, generator=generator).clamp(-3, 3)
    bone[:, _RIGHT] = bone[:, _LEFT]
    parents = torch.tensor(PARENTS)
    offsets = x[:, :, 1:] - x[:, :, parents[1:]]
    rebuilt = [x[:, :, 0]]
    for j in _BONE_ORDER:
        rebuilt.append(rebuilt[PARENTS[j]] + offsets[:, :, j - 1] * bone[:, None, j, None])
    x = torch.stack(rebuilt, dim=2)
    # keep the lowest foot joint of the clip on the floor it stood on
    feet_before = positions[:, :, list(FOOT_JOINTS), 2]
    feet_after = x[:, :, list(FOOT_JOINTS), 2]
    x[..., 2] += (feet_before.amin(dim=(1, 2)) - feet_after.amin(dim=(1, 2)))[:, None, None]
    # global scale, yaw rotation, horizontal translation
    scale = torch.empty(B).uniform_(*scale_range, generator=generator)
    yaw = torch.rand(B, generator=generator) * 2 * np.pi
    c, s = torch.cos(yaw), torch.sin(yaw)
    xy = x[..., :2]
    rotated = torch.stack([c[:, None, None] * xy[..., 0] - s[:, None, None] * xy[..., 1],
                           s[:, None, None] * xy[..., 0] + c[:, None, None] * xy[..., 1]], dim=-1)
    shift = (torch.rand(B, 2, generator=generator) * 2 - 1) * translation_m
    x = torch.cat([rotated + shift[:, None, None], x[..., 2:]], dim=-1) * scale[:, None, None, None]
    # artefacts: noise, drift, height offset
    T = x.shape[1]
    sigma = torch.rand(B, generator=generator) * noise_m
    x = x + sigma[:, None, None, None] * torch.randn(x.shape, generator=generator)
    drift = torch.randn(B, 2, generator=generator) * drift_mps
    t = torch.arange(T, dtype=x.dtype) / 60.0
    offset = torch.zeros(B, T, 1, 3)
    offset[..., :2] = (drift[:, None, :] * t[None, :, None])[:, :, None, :]
    offset[..., 2] = ((torch.rand(B, generator=generator) * 2 - 1) * height_m)[:, None, None]
    return x + offset, forces, contacts


@torch.no_grad()
def estimate(net: nn.Module, positions: np.ndarray) -> np.ndarray:
    """Run a contact network on one clip of joint positions ``(T, 23, 3)``: VGRFNet gives cell
    vGRF ``(T, 2, 16)`` (body weights), ContactMLP contact probabilities ``(T, 4)``."""
    net.eval()
    out = net(torch.as_tensor(np.asarray(positions, dtype=np.float32))[None])[0]
    return (torch.sigmoid(out) if isinstance(net, ContactMLP) else out).numpy()
