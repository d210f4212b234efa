"""Probe: does taking an IMU take's stance skate out of its root before tracking help a policy?

Usage: ``python bench/root_unslide.py [--policy models/mimic_general_steered] [--clips library:data/library/val]
[--episodes 20] [--kind imu] [--seeds 9100 9200] [--denoise models/imu_denoiser_dm | --no-denoise]
[--settings 0.1,1 0.2,1 0.1,2] [--json [OUT]]``

An IMU suit's stance skate moves the whole body, planted feet included, out and back within a
step (:func:`reference_motion.artefacts.corrupt`, ``skate``). :func:`unslid` moves the root back
by what the supporting feet slide: per foot, the lower of its two sole points (heel or toe, so a
rolling foot is followed through heel strike and toe-off) supports it while it is within
``SUPPORT_HEIGHT_M`` of that point's 5th-percentile height over the take and slower than
``SUPPORT_MAX_SPEED_MPS``; the mean horizontal step of the supporting points, smoothed over
``smooth_s`` (a Gaussian's σ; 0: not smoothed) so that the joint-angle noise the feet carry is
not passed on, is integrated and subtracted from the pelvis,
and the correction's own drift over ``keep_path_s`` (σ) is taken out again so that the take's path
over seconds is kept. A clean take moves by millimetres.

Each row tracks the IMU take (``--kind``: every artefact kind, or one), denoised unless
``--no-denoise`` (``evaluate.py --denoise``), with or without the root unslid at one
``smooth_s,keep_path_s`` setting, judged against the take as given; the rows share clips,
artefact seeds and start frames. Not adopted: see the README ("Where the IMU loss sits"), where
the measured rows are.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.ndimage import gaussian_filter1d

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.artefacts import ARTEFACT_KINDS
from reference_motion.footskate import masked_mean
from reference_motion.humanoid.model import CONTACT_CHANNELS, load_model
from reference_motion.motion import Motion

SUPPORT_HEIGHT_M = 0.025
"""A foot supports while its lower sole point is within this of that point's 5th-percentile height."""
SUPPORT_MAX_SPEED_MPS = 1.0
"""...and moves slower than this horizontally."""
FEET = ((CONTACT_CHANNELS.index("left_toe"), CONTACT_CHANNELS.index("left_heel")),
        (CONTACT_CHANNELS.index("right_toe"), CONTACT_CHANNELS.index("right_heel")))


def support_slide(motion: Motion) -> np.ndarray:
    """``(T − 1, 2)`` mean horizontal step (m per frame) of the supporting feet's lower sole
    points between consecutive frames; zero where no foot supports."""
    points = load_model(motion.model).forward_kinematics(motion.qpos).foot_points  # (T, 4, 3)
    steps, supports = [], []
    for channels in FEET:
        height = points[:, channels, 2]
        lower = np.argmin(height, axis=1)
        low_z = height[np.arange(len(height)), lower]
        step = np.diff(points[:, channels, :2], axis=0)[np.arange(len(height) - 1), lower[:-1]]
        near = low_z < np.percentile(low_z, 5) + SUPPORT_HEIGHT_M
        supports.append(near[:-1] & near[1:] & (np.linalg.norm(step, axis=-1) * motion.fps < SUPPORT_MAX_SPEED_MPS))
        steps.append(step)
    return masked_mean(np.stack(steps, axis=1), np.stack(supports, axis=1))


def unslid(motion: Motion, smooth_s: float, keep_path_s: float) -> Motion:
    """``motion`` with its pelvis moved back by what its supporting feet slide (module docstring)."""
    slide = support_slide(motion)
    if smooth_s > 0:
        slide = gaussian_filter1d(slide, smooth_s * motion.fps, axis=0, mode="nearest")
    correction = -np.concatenate([np.zeros((1, 2)), np.cumsum(slide, axis=0)])
    correction -= gaussian_filter1d(correction, keep_path_s * motion.fps, axis=0, mode="nearest")
    qpos = motion.qpos.copy()
    qpos[:, :2] += correction
    return motion.with_qpos(qpos)


def setting(text: str) -> tuple[float, float]:
    """``"SMOOTH_S,KEEP_PATH_S"`` → ``(smooth_s, keep_path_s)``, seconds, smooth_s ≥ 0, keep_path_s > 0."""
    try:
        smooth_s, keep_path_s = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected SMOOTH_S,KEEP_PATH_S (seconds, e.g. 0.1,1), got {text!r}")
    if smooth_s < 0 or keep_path_s <= 0:
        raise argparse.ArgumentTypeError(f"need SMOOTH_S >= 0 and KEEP_PATH_S > 0, got {text!r}")
    return smooth_s, keep_path_s


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general_steered")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip, row and seed")
    p.add_argument("--seeds", type=int, nargs="+", default=[9100, 9200], help="artefact seeds of the first clip")
    p.add_argument("--kind", choices=("imu",) + ARTEFACT_KINDS, default="imu", help="artefact kinds: all, or one")
    which = p.add_mutually_exclusive_group()
    which.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_dm"))
    which.add_argument("--no-denoise", action="store_true", help="track the take as corrupted")
    p.add_argument("--settings", nargs="+", type=setting, default=[(0.1, 1.0), (0.2, 1.0), (0.1, 2.0)],
                   metavar="SMOOTH_S,KEEP_PATH_S")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    net = None if args.no_denoise else load_network(args.denoise, "denoiser")
    first = "given" if net is None else "denoised"
    rows = []
    for seed in args.seeds:
        given = reference_clips(args.clips, FOOT_MODELS[policy.foot], MimicConfig(), args.kind, 1.0, seed)
        tracked_first = given if net is None else [denoise(net, c) for c in given]
        variants = {first: tracked_first}
        variants.update({f"{first}, unslid {s:g},{k:g}": [unslid(c, s, k) for c in tracked_first]
                         for s, k in args.settings})
        for name, tracked in variants.items():
            summary = evaluate_tracking(policy, tracked, given, episodes=args.episodes)[0]
            rows.append({"seed": seed, "tracked": name, "ELR": summary["ELR_mean"], "SR90": summary["SR90"]})
            print(f"seed {seed}  {name:<28} ELR {summary['ELR_mean']:.3f}  SR90 {summary['SR90']:.3f}", flush=True)
    emit_json({"policy": args.policy, "clips": args.clips, "episodes": args.episodes, "kind": args.kind,
               "denoiser": None if net is None else str(args.denoise),
               "rows": rows}, args.json)


if __name__ == "__main__":
    main()
