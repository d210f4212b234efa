"""Undoing an IMU suit's joint-angle and height errors before a policy tracks the take.

The generalist falls most on IMU-corrupted takes through their joint-angle errors: the hip
adduction offset alone takes its validation ELR from 0.88 to 0.65, the per-hinge calibration bias
to 0.76 (README, "what the IMU artefacts cost"). Those errors are constant or slow over a take,
and a take shows them in ways a single frame does not: legs that swing across the midline while
the pelvis sways beyond the stance foot, feet that sink or float by the same few centimetres at
every step. :class:`IMUDenoiser` learns that from the library's training takes corrupted by
:func:`reference_motion.artefacts.corrupt` (:mod:`perception.denoiser_training`) and returns the
correction of every hinge angle and of the pelvis height; :func:`denoise` applies it to a
:class:`~reference_motion.motion.Motion`. The root's horizontal path (heading drift, root drift,
skate) is left as it is: footskate cleanup and the simulation handle those.

Input per frame (:func:`motion_features`, ``(T, n_hinge + 18)``): the hinge angles (rad), the
pelvis height (m), the world up axis in the pelvis frame, the pelvis velocity in its heading frame
(forward, left; m/s), and where the four sole points are relative to the pelvis in that frame and
above the floor (m): nothing that depends on where the take is or which way it faces. The network
is fully convolutional in time (any number of frames): dilated residual convolutions see ±1 s
around a frame, and a branch that averages over the whole input carries what is constant over the
take (a calibration offset) to every frame.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch
from torch import nn

from reference_motion import rotations as rot
from reference_motion.cli import positive_float
from reference_motion.humanoid.model import CONTACT_CHANNELS, load_model
from reference_motion.motion import Motion
from reference_motion.transforms import mirror_map, mirror_twin

DEFAULT_DENOISER = Path(__file__).resolve().parents[1] / "models" / "imu_denoiser_soles_quint_mirror"
"""The IMU denoiser a bare ``--denoise`` uses (validation's choice until stop 75, kept so that earlier
commands reproduce): five networks trained with ``python -m perception train-denoiser --sole-weight 4``
and averaged with their mirror images (``ensemble-denoisers --mirror-average``; docs/results.md,
"Undoing the IMU suit's joint-angle errors")."""
STANCES_DENOISER = DEFAULT_DENOISER.parent / "imu_denoiser_stances_quint_mirror"
"""Validation's choice since stop 75 (docs/results.md, "Round 32"), the denoiser of ``clean.py --preset imu``:
the same five commands, each also trained on every take walked up to 0.35 m wider (``train-denoiser
--stances 1``), so it gives a wide stance back where :data:`DEFAULT_DENOISER` narrows it."""
BODY_FEATURES = (("root_z", "up_x", "up_y", "up_z", "vel_forward", "vel_left")
                 + tuple(f"{point}_{axis}" for point in CONTACT_CHANNELS for axis in ("forward", "left"))
                 + tuple(f"{point}_z" for point in CONTACT_CHANNELS))
"""Per-frame inputs after the hinge angles (:func:`motion_features`)."""
MIN_STD = 0.05
"""Floor of the input standardisation's std (rad, m, m/s: a few degrees, centimetres)."""


def add_denoise_option(parser: argparse.ArgumentParser, what: str) -> None:
    """``--denoise [DIR]`` (a path string, ``None`` when absent; the bare flag gives
    :data:`DEFAULT_DENOISER`); ``what`` ends its help: what passes through the denoiser, and how."""
    parser.add_argument("--denoise", nargs="?", const=str(DEFAULT_DENOISER), default=None, metavar="DIR",
                        help="pass corrupted takes through the IMU denoiser in DIR (default: "
                             f"models/{DEFAULT_DENOISER.name}, validation's choice until stop 75; since then "
                             f"models/{STANCES_DENOISER.name}): {what}")


def motion_features(motion: Motion) -> np.ndarray:
    """Placement- and heading-free features ``(T, n_hinge + 18)`` (float32) of ``motion``: hinge
    angles (rad), pelvis height (m), the world up axis in the pelvis frame (unit vector), the
    pelvis velocity in its heading frame (forward, left; m/s, central differences), and each sole
    point's (:data:`~reference_motion.humanoid.model.CONTACT_CHANNELS`) place relative to the
    pelvis in that frame (forward, left; m) and height (m), by forward kinematics: how wide the
    feet stand and whether they meet the floor, the clearest signs of an adduction offset and of
    a body floating or sunk."""
    q = motion.qpos
    up = rot.rotate(rot.conjugate(q[:, 3:7]), np.array([0.0, 0.0, 1.0]))
    yaw = rot.yaw(q[:, 3:7])
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]

    def heading_frame(xy: np.ndarray) -> np.ndarray:  # (T, K, 2) world → (T, K, 2) forward, left
        return np.stack([c * xy[..., 0] + s * xy[..., 1], -s * xy[..., 0] + c * xy[..., 1]], axis=-1)

    vel = heading_frame((np.gradient(q[:, :2], axis=0) * motion.fps)[:, None])[:, 0]
    feet = load_model(motion.model).forward_kinematics(q).foot_points  # (T, 4, 3)
    feet_xy = heading_frame(feet[..., :2] - q[:, None, :2]).reshape(len(q), -1)
    return np.concatenate([q[:, 7:], q[:, 2:3], up, vel, feet_xy, feet[..., 2]], axis=1).astype(np.float32)


class IMUDenoiser(nn.Module):
    """Features ``(B, T, n_hinge + 18)`` (:func:`motion_features`) → corrections ``(B, T, n_hinge + 1)``:
    what to add to each hinge angle (rad) and to the pelvis height (m), for any ``T``.

    The input is standardised with statistics of the training data (buffers ``mean``, ``std``, set
    by the trainer). A per-frame linear layer to ``hidden`` channels, residual ReLU convolutions
    (kernel 3) with the given dilations (1…32: ±63 frames, ±1 s at 60 Hz), and a take-level branch
    (the mean over time of those channels through a linear layer, added back to every frame) feed
    a per-frame linear output layer, initialised to zero (an untrained denoiser changes nothing).

    Args:
        model: the humanoid whose hinges are read (``humanoid_1seg`` or ``humanoid_2seg``).
        fps: frame rate the network was trained at (Hz); inputs must have it.
        hidden: channels of every layer.
        dilations: dilation of each residual convolution.
    """

    def __init__(self, model: str = "humanoid_1seg", fps: float = 60.0, hidden: int = 128,
                 dilations: tuple[int, ...] = (1, 2, 4, 8, 16, 32)):
        super().__init__()
        self.model, self.fps, self.config = model, float(fps), {"model": model, "fps": float(fps), "hidden": hidden,
                                                                 "dilations": tuple(dilations)}
        hinges = tuple(load_model(model).hinge_names)
        self.input_names = hinges + BODY_FEATURES
        self.output_names = hinges + ("root_z",)
        n_in = len(self.input_names)
        self.register_buffer("mean", torch.zeros(n_in))
        self.register_buffer("std", torch.ones(n_in))
        self.inp = nn.Conv1d(n_in, hidden, 1)
        self.convs = nn.ModuleList([nn.Conv1d(hidden, hidden, 3, padding=d, dilation=d) for d in dilations])
        self.take = nn.Linear(hidden, hidden)
        self.out = nn.Conv1d(hidden, len(self.output_names), 1)
        nn.init.zeros_(self.out.weight)  # untrained, it changes nothing: training starts from the take as given
        nn.init.zeros_(self.out.bias)

    def set_statistics(self, features: np.ndarray) -> None:
        """Standardise inputs with the mean and std of ``features (N, n_in)``; the std is floored
        at :data:`MIN_STD`, so a hinge the training takes hardly move (a wrist) is not blown up
        where a corrupted take moves it."""
        self.mean.copy_(torch.as_tensor(features.mean(0)))
        self.std.copy_(torch.as_tensor(np.maximum(features.std(0), MIN_STD)))

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        z = torch.relu(self.inp(((features - self.mean) / self.std).transpose(1, 2)))
        for conv in self.convs:
            z = z + torch.relu(conv(z))
        z = z + torch.relu(self.take(z.mean(dim=2)))[:, :, None]
        return self.out(z).transpose(1, 2)


def mirror_maps(model: str) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """Index permutation and sign, ``(perm, sign)``, of the features ``(n_hinge + 18,)``
    (:func:`motion_features`) and of the corrections ``(n_hinge + 1,)`` under the left/right
    mirror (:func:`reference_motion.transforms.mirror`): ``features(mirror(m)) ==
    features(m)[..., perm] * sign``, and likewise for corrections. Each map is its own inverse."""
    qpos_perm, qpos_sign = mirror_map(model)
    hinge_perm, hinge_sign = qpos_perm[7:] - 7, qpos_sign[7:]
    n = len(hinge_perm)
    points = list(CONTACT_CHANNELS)
    twin = [points.index(mirror_twin(p)) for p in points]
    # after the hinges: root_z, up (x, y, z), velocity (forward, left), sole points (forward, left) each, heights
    body_perm = np.concatenate([[0, 1, 2, 3, 4, 5], [6 + 2 * twin[k] + a for k in range(4) for a in (0, 1)],
                                [14 + twin[k] for k in range(4)]])
    body_sign = np.concatenate([[1, 1, -1, 1, 1, -1], [1, -1] * 4, [1] * 4]).astype(float)
    features = (np.concatenate([hinge_perm, n + body_perm]), np.concatenate([hinge_sign, body_sign]))
    corrections = (np.append(hinge_perm, n), np.append(hinge_sign, 1.0))
    return features, corrections


class DenoiserEnsemble(nn.Module):
    """The mean correction ``(B, T, n_hinge + 1)`` of several :class:`IMUDenoiser` s trained apart
    (other seeds, other settings) for the same humanoid and frame rate: each network's own errors
    partly average out. With ``mirror_average``, each member also corrects the take's mirror image
    (left and right swapped, :func:`mirror_maps`) and that correction, mirrored back, joins the
    mean (test-time augmentation: the members trained on mirrored takes too, so both images are
    ones they know); an ensemble of one member is then allowed. Built from the members' constructor
    arguments (``members``, one dict each, as :attr:`IMUDenoiser.config`); reads and returns what
    :class:`IMUDenoiser` does."""

    def __init__(self, members: list[dict], mirror_average: bool = False):
        super().__init__()
        nets = [IMUDenoiser(**config) for config in members]
        if len(nets) < (1 if mirror_average else 2):
            raise ValueError(f"an ensemble of IMU denoisers needs at least two members (one with mirror_average), "
                             f"got {len(nets)}")
        if len({(net.model, net.fps) for net in nets}) > 1:
            raise ValueError("the members of an ensemble of IMU denoisers must be for one humanoid and frame rate, "
                             f"got {sorted({(net.model, net.fps) for net in nets})}")
        self.members = nn.ModuleList(nets)
        self.model, self.fps = nets[0].model, nets[0].fps
        self.input_names, self.output_names = nets[0].input_names, nets[0].output_names
        self.mirror_average = bool(mirror_average)
        self.config = {"members": [dict(net.config) for net in nets]} | (
            {"mirror_average": True} if mirror_average else {})
        (feature_perm, feature_sign), (out_perm, out_sign) = mirror_maps(self.model)
        for name, value in (("feature_perm", feature_perm), ("out_perm", out_perm)):
            self.register_buffer(name, torch.as_tensor(value, dtype=torch.long), persistent=False)
        for name, value in (("feature_sign", feature_sign), ("out_sign", out_sign)):
            self.register_buffer(name, torch.as_tensor(value, dtype=torch.float32), persistent=False)

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        corrections = [net(features) for net in self.members]
        if self.mirror_average:
            mirrored = features[..., self.feature_perm] * self.feature_sign
            corrections += [net(mirrored)[..., self.out_perm] * self.out_sign for net in self.members]
        return torch.stack(corrections).mean(dim=0)


def denoiser_network(**config) -> nn.Module:
    """The IMU denoiser a shipped file's ``network`` field describes: a :class:`DenoiserEnsemble`
    when it lists ``members``, else an :class:`IMUDenoiser`."""
    return DenoiserEnsemble(**config) if "members" in config else IMUDenoiser(**config)


class SlowCorrections(nn.Module):
    """An IMU denoiser's corrections kept only where they are slow: its corrections of the hinge
    angles smoothed by a Gaussian of ``smooth_s`` seconds (the ends held), its correction of the
    pelvis height dropped. Reads and returns what the denoiser does, ``(B, T, n_hinge + 1)``.

    What it is for: a policy trained on raw IMU takes (``mimic_general_legs``) copes with the suit's
    noise and jitter, but not with its slow hinge drift, which the take alone cannot show and the
    denoiser reads (README, round 23); the height is left to ``--ground``. On validation's IMU takes
    the smoothing itself matters little (0.25 to 2 s, and the unsmoothed hinge corrections of
    ``runs/r23/slowden_probe.py``: ELR 0.965–0.970 behind it, 0.942 without the denoiser); 0.5 s
    drops the frame-to-frame corrections that the raw policy does not need.
    """

    def __init__(self, denoiser: IMUDenoiser | DenoiserEnsemble, smooth_s: float):
        super().__init__()
        if not (np.isfinite(smooth_s) and smooth_s > 0):
            raise ValueError(f"SlowCorrections.smooth_s must be a finite number of seconds > 0, got {smooth_s}")
        self.denoiser, self.smooth_s = denoiser, float(smooth_s)
        self.model, self.fps = denoiser.model, denoiser.fps
        sigma = self.smooth_s * self.fps
        self.radius = int(4.0 * sigma + 0.5)  # scipy's gaussian_filter1d truncates there too
        taps = torch.arange(-self.radius, self.radius + 1, dtype=torch.float64)
        kernel = torch.exp(-0.5 * (taps / sigma) ** 2)
        self.register_buffer("kernel", kernel / kernel.sum(), persistent=False)

    @property
    def label(self) -> str:
        """How results name what a policy tracks behind it."""
        return f"denoiser's hinge corrections slowed to {self.smooth_s:g} s"

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        correction = self.denoiser(features)
        hinges = correction[..., :-1].transpose(1, 2)  # (B, n_hinge, T)
        n = hinges.shape[1]
        padded = nn.functional.pad(hinges, (self.radius, self.radius), mode="replicate")
        slow = nn.functional.conv1d(padded, self.kernel.to(hinges).expand(n, 1, -1), groups=n)
        return torch.cat([slow.transpose(1, 2), torch.zeros_like(correction[..., -1:])], dim=-1)


def add_slow_corrections_option(parser: argparse.ArgumentParser) -> None:
    """``--denoise-slow [S]`` (read back by :func:`slowed`)."""
    parser.add_argument("--denoise-slow", type=positive_float, nargs="?", const=0.5, default=None, metavar="S",
                        help="with --denoise DIR: keep only the slow part of the denoiser's corrections of the hinge "
                             "angles (a Gaussian of S seconds, default 0.5) and none of its pelvis height, so a "
                             "policy trained on raw IMU takes gets their drift read and their noise as it knows it "
                             "(perception/imu_denoiser.py SlowCorrections)")


def slowing_of(denoiser: object) -> float | None:
    """The seconds ``denoiser``'s corrections are slowed to (a :class:`SlowCorrections`); ``None``
    for a denoiser used whole or none."""
    return denoiser.smooth_s if isinstance(denoiser, SlowCorrections) else None


def check_slowing(denoiser: object, smooth_s: float | None) -> None:
    """Refuse ``--denoise-slow`` (``smooth_s``) without a denoiser (``denoiser``: its path, or the
    network; ``None`` without), before any work."""
    if smooth_s is not None and denoiser is None:
        raise ValueError(f"--denoise-slow {smooth_s:g} slows a denoiser's corrections: give --denoise too")


def slowed(net: IMUDenoiser | DenoiserEnsemble | None, smooth_s: float | None,
           ) -> IMUDenoiser | DenoiserEnsemble | SlowCorrections | None:
    """``net`` as :func:`add_slow_corrections_option` asks for it: itself without ``smooth_s``,
    :class:`SlowCorrections` of it with; :func:`check_slowing`'s error for ``smooth_s`` without a
    denoiser."""
    check_slowing(net, smooth_s)
    return net if smooth_s is None else SlowCorrections(net, smooth_s)


@torch.no_grad()
def denoise(net: IMUDenoiser | DenoiserEnsemble | SlowCorrections, motion: Motion) -> Motion:
    """``motion`` with ``net``'s corrections added to its hinge angles and pelvis height; its
    ``source`` records ``denoised: True``. A clear ``ValueError`` when the motion is for another
    humanoid or at another frame rate than the network."""
    if motion.model != net.model:
        raise ValueError(f"motion {motion.name!r} is for {motion.model}, the IMU denoiser for {net.model}")
    if abs(motion.fps - net.fps) > 1e-6:
        raise ValueError(f"motion {motion.name!r} is at {motion.fps:g} Hz, the IMU denoiser reads {net.fps:g} Hz; "
                         "resample it first (reference_motion.transforms.resample)")
    correction = net(torch.from_numpy(motion_features(motion))[None])[0].numpy().astype(float)
    qpos = motion.qpos.copy()
    qpos[:, 7:] += correction[:, :-1]
    qpos[:, 2] += correction[:, -1]
    return motion.with_qpos(qpos, source={**motion.source, "denoised": True})
