"""Does a policy perform a clip as well whichever way it walks? World axes against the reference's.

Usage: ``python bench/heading_frames.py [--policy models/mimic_general] [--clips deepmimic:walk ...]
[--turns 0 90 180 270] [--starts 15] [--frames 150] [--json [OUT]]``

Physics on a flat floor does not care which way a clip walks, but a policy that observes in world
axes (ADAPT's frame, ``MimicConfig.obs_frame="world"``) does: every clip of the library starts
facing +x, so such a policy has seen most of its states facing about +x. Each clip (looped or cut to
10 s) is turned about z by each of ``--turns`` degrees (:func:`reference_motion.transforms.turned`:
the same motion walked another way), and the policy rolls out ``--frames`` frames from each of
``--starts`` start frames spread over its first 5 s (reference state initialisation, no noise),
observing in world axes and in the reference's (``"reference"``: axes turned with the reference's
heading, :mod:`envs.observations`), side by side in one run. Reported per clip, frame and turn: the
share of the frames survived (ELR of those windows), and its mean over the turns.
"""

from __future__ import annotations

import argparse

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.policy import load_policy
from agents.rollout import run_episode
from envs.config import FOOT_MODELS
from envs.observations import SAME_LAYOUT_FRAMES
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.library import load_motion
from reference_motion.transforms import turned

CLIP_FRAMES = 601
"""Frames of each clip (10 s at 60 Hz)."""


def survival(policy, clip, starts: np.ndarray, frames: int) -> float:
    """Mean share of ``frames`` frames that ``policy`` survives from each of ``starts`` on ``clip``."""
    env = policy.make_env([clip], artefacts=None, episode_frames=frames)
    survived = [run_episode(env, policy, {"clip": 0, "start_frame": int(s)}, max_frames=frames).frames
                for s in starts]
    env.close()
    return float(np.mean(np.minimum(survived, frames)) / frames)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general")
    p.add_argument("--clips", nargs="+", default=["deepmimic:walk", "deepmimic:walker/turn_left0",
                                                  "deepmimic:walker/turn_right0"],
                   help="clips (default: DeepMimic's training walks; held-out clips only for a final measurement)")
    p.add_argument("--turns", nargs="+", type=float, default=[0.0, 90.0, 180.0, 270.0], help="degrees")
    p.add_argument("--starts", type=int, default=15)
    p.add_argument("--frames", type=int, default=150)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    base = load_policy(args.policy)
    model = FOOT_MODELS[base.foot]
    starts = np.linspace(0, CLIP_FRAMES - 1 - 2 * args.frames, args.starts).round()
    result = {"policy": args.policy, "frames": args.frames, "starts": starts.tolist(), "clips": {}}
    print(f"{args.policy}: share of {args.frames} frames survived from {args.starts} starts, clip turned by")
    print(f"{'clip':<34}{'frame':<11}" + "".join(f"{t:>7g}°" for t in args.turns) + f"{'mean':>8}")
    for source in args.clips:
        clip = load_motion(source, model, min_frames=CLIP_FRAMES)
        clip = clip.with_qpos(clip.qpos[:CLIP_FRAMES], loop=False)
        rows = {}
        for frame in SAME_LAYOUT_FRAMES:
            policy = base.observing(frame)
            row = [survival(policy, turned(clip, np.radians(t)), starts, args.frames) for t in args.turns]
            rows[frame] = {"by_turn": dict(zip(map(str, args.turns), row)), "mean": float(np.mean(row))}
            print(f"{source:<34}{frame:<11}" + "".join(f"{v:>8.2f}" for v in row) + f"{np.mean(row):>8.2f}", flush=True)
        result["clips"][source] = rows
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
