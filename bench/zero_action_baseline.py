"""Zero-action baseline: the reference fed open loop to the PD controllers of MimicIMU-v0.

Usage: ``python bench/zero_action_baseline.py [--clip deepmimic:walk] [--episodes 20] [--json [OUT]]``

ADAPT's protocol (adapt §3.2.6): one 300-frame segment, ``episodes`` rollouts starting at slightly
different offsets (every 3rd frame), clean reference, the action always zero. The ELR, SR90, RDE and
MRR it reaches are what a trained policy has to beat.
"""

from __future__ import annotations

import argparse
import json

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.metrics import episode_length_ratio, max_reward_ratio, root_displacement_error, survived


def rollout(env: gym.Env, start_frame: int) -> dict[str, float]:
    """One zero-action episode from ``start_frame``; its four metrics and why it ended."""
    base = env.unwrapped
    env.reset(seed=0, options={"clip": 0, "start_frame": start_frame})
    zero = np.zeros(env.action_space.shape, dtype=np.float32)
    rewards, root, ref_root = [], [], []
    while True:
        _, reward, term, trunc, info = env.step(zero)
        rewards.append(reward)
        root.append(base.data.qpos[:3].copy())
        ref_root.append(base.track(0).motion.qpos[info["frame"], :3])
        if term or trunc:
            break
    frames, total = info["episode_frame"], base.config.episode_frames
    return {"ELR": episode_length_ratio(frames, total), "SR90": survived(frames, total),
            "RDE": root_displacement_error(np.array(root), np.array(ref_root)),
            "MRR": max_reward_ratio(np.array(rewards), total // base.config.frames_per_control),
            "ended_by": info["ended_by"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clip", default="deepmimic:walk")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    env = gym.make("MimicIMU-v0", clips=[args.clip], artefacts=None)
    runs = [rollout(env, 3 * k) for k in range(args.episodes)]
    result = {"clip": args.clip, "episodes": args.episodes}
    for key in ("ELR", "SR90", "RDE", "MRR"):
        values = np.array([r[key] for r in runs])
        result[f"{key}_mean"], result[f"{key}_std"] = float(values.mean()), float(values.std())
    result["ended_by"] = {why: sum(r["ended_by"] == why for r in runs) for why in {r["ended_by"] for r in runs}}
    text = json.dumps(result, indent=1)
    if args.json and args.json != "-":
        with open(args.json, "w") as f:
            f.write(text)
    print(text if args.json else
          f"{args.clip}, zero action, {args.episodes} rollouts: ELR {result['ELR_mean']:.3f} ± {result['ELR_std']:.3f}, "
          f"SR90 {result['SR90_mean']:.2f}, RDE {result['RDE_mean']:.4f} m², MRR {result['MRR_mean']:.3f}; "
          f"ended by {result['ended_by']}")


if __name__ == "__main__":
    main()
