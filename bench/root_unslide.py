"""Probe: does taking an IMU take's stance skate out of its root before tracking help a policy?

Usage: ``python bench/root_unslide.py [--policy models/mimic_general_steered] [--clips library:data/library/val]
[--episodes 20] [--seeds 9100 9200] [--denoise models/imu_denoiser_dm] [--settings 0.1,1 0.2,1 0.1,2]
[--json [OUT]]``

An IMU suit's stance skate moves the whole body, planted feet included, out and back within a
step (:func:`reference_motion.artefacts.corrupt`, ``skate``). :func:`unslid` moves the root back
by what the supporting feet slide: per foot, the lower of its two sole points (heel or toe, so a
rolling foot is followed through heel strike and toe-off) supports it while it is within
``SUPPORT_HEIGHT_M`` of its own lowest height and slower than ``SUPPORT_MAX_SPEED_MPS``; the mean
horizontal step of the supporting points, smoothed over ``smooth_s`` (a Gaussian's σ) so that the
joint-angle noise the feet carry is not passed on, is integrated and subtracted from the pelvis,
and the correction's own drift over ``keep_path_s`` (σ) is taken out again so that the take's path
over seconds is kept. A clean take moves by millimetres.

Each row tracks the denoised IMU take (``evaluate.py --denoise``), with or without the root
unslid at one ``smooth_s,keep_path_s`` setting, judged against the take as given; the rows share
clips, artefact seeds and start frames. Not adopted: see the README ("Undoing the IMU suit's
joint-angle errors"), where the measured rows are.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.ndimage import gaussian_filter1d

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate, summarize
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import denoise
from perception.weights import load_network
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
    steps, supports = np.stack(steps, axis=1), np.stack(supports, axis=1)
    count = supports.sum(axis=1, keepdims=True)
    return np.where(count > 0, (steps * supports[..., None]).sum(axis=1) / np.maximum(count, 1), 0.0)


def unslid(motion: Motion, smooth_s: float, keep_path_s: float) -> Motion:
    """``motion`` with its pelvis moved back by what its supporting feet slide (module docstring)."""
    slide = gaussian_filter1d(support_slide(motion), smooth_s * motion.fps, axis=0, mode="nearest")
    correction = -np.concatenate([np.zeros((1, 2)), np.cumsum(slide, axis=0)])
    correction -= gaussian_filter1d(correction, keep_path_s * motion.fps, axis=0, mode="nearest")
    qpos = motion.qpos.copy()
    qpos[:, :2] += correction
    return motion.with_qpos(qpos)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general_steered")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip, row and seed")
    p.add_argument("--seeds", type=int, nargs="+", default=[9100, 9200], help="artefact seeds of the first clip")
    p.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_dm"))
    p.add_argument("--settings", nargs="+", default=["0.1,1", "0.2,1", "0.1,2"], metavar="SMOOTH_S,KEEP_PATH_S")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    net = load_network(args.denoise, "denoiser")
    settings = [tuple(float(v) for v in s.split(",")) for s in args.settings]
    rows = []
    for seed in args.seeds:
        given = reference_clips(args.clips, FOOT_MODELS[policy.foot], MimicConfig(), "imu", 1.0, seed)
        denoised = [denoise(net, c) for c in given]
        variants = {"denoised": denoised}
        variants.update({f"denoised, unslid {s},{k}": [unslid(c, s, k) for c in denoised] for s, k in settings})
        for name, tracked in variants.items():
            env = policy.make_env(tracked, artefacts=None, judged_clips=given)
            env.reset(seed=0)
            summary = summarize(evaluate(env, policy, episodes=args.episodes)[1])
            rows.append({"seed": seed, "tracked": name, "ELR": summary["ELR_mean"], "SR90": summary["SR90"]})
            print(f"seed {seed}  {name:<28} ELR {summary['ELR_mean']:.3f}  SR90 {summary['SR90']:.3f}", flush=True)
    emit_json({"policy": args.policy, "clips": args.clips, "episodes": args.episodes, "denoiser": str(args.denoise),
               "rows": rows}, args.json)


if __name__ == "__main__":
    main()
