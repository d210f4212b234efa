"""A trained policy's deterministic action for one observation: NumPy on the actor's weights
(``MimicPolicy.__call__``) against stable-baselines3's ``predict``, alone and inside rollouts
(evaluation, cleaning and adaptation's evaluations run one observation at a time).

Usage: ``python bench/policy_call_speed.py [--policy DIR] [--rounds R] [--json [OUT]]``

Interleaved rounds (the median is reported): the time of one call on observations of a rollout,
and the frames/s of 4 rollouts of at most 300 frames (walk and run, one torch thread), each way.
The two give the same actions (the largest difference is reported).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.policy import MimicPolicy, load_policy
from agents.rollout import run_episode, torch_threads
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/

CLIPS = ["deepmimic:walk", "deepmimic:run"]


def sb3_predict(policy: MimicPolicy):
    """``policy``'s deterministic action through stable-baselines3's ``predict``."""
    def act(obs: np.ndarray) -> np.ndarray:
        action, _ = policy.model.predict(policy.normalizer.normalize_obs(obs), deterministic=True)
        return action
    return act


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--policy", default="models/mimic_general")
    parser.add_argument("--rounds", type=int, default=5, help="interleaved rounds (the median is reported)")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    policy = load_policy(args.policy)
    env = policy.make_env(CLIPS)
    ways = {"numpy (MimicPolicy.__call__)": policy, "stable-baselines3 predict": sb3_predict(policy)}
    observations = [env.reset(seed=0)[0]]
    for _ in range(199):
        obs, _, terminated, truncated, _ = env.step(policy(observations[-1]))
        observations.append(env.reset()[0] if terminated or truncated else obs)
    largest_difference = max(float(np.abs(policy(o) - ways["stable-baselines3 predict"](o)).max()) for o in observations)
    call_us: dict[str, list[float]] = {w: [] for w in ways}
    rollout_fps: dict[str, list[float]] = {w: [] for w in ways}
    with torch_threads(1):
        for _ in range(args.rounds):
            for way, act in ways.items():
                start = time.perf_counter()
                for obs in observations:
                    act(obs)
                call_us[way].append(1e6 * (time.perf_counter() - start) / len(observations))
                start, frames = time.perf_counter(), 0
                for k in range(4):
                    frames += run_episode(env, act, {"clip": k % 2, "start_frame": 3 * k}, max_frames=300).frames
                rollout_fps[way].append(frames / (time.perf_counter() - start))
    env.close()
    rows = [{"way": w, "call_us": round(statistics.median(call_us[w]), 1),
             "rollout_frames_per_s": round(statistics.median(rollout_fps[w])),
             "rounds_call_us": [round(t, 1) for t in call_us[w]], "rounds_rollout_frames_per_s": [round(f) for f in rollout_fps[w]]}
            for w in ways]
    result = {"policy": args.policy, "clips": CLIPS, "rounds": args.rounds, "largest_action_difference": largest_difference,
              "call_speedup": round(rows[1]["call_us"] / rows[0]["call_us"], 2),
              "rollout_speedup": round(rows[0]["rollout_frames_per_s"] / rows[1]["rollout_frames_per_s"], 2), "rows": rows}
    if not emit_json(result, args.json):
        for r in rows:
            print(f"{r['way']:30s} {r['call_us']:7.1f} µs per call   rollouts {r['rollout_frames_per_s']:6d} frames/s")
        print(f"×{result['call_speedup']} per call, ×{result['rollout_speedup']} in rollouts; "
              f"largest action difference {largest_difference:.1e} rad")


if __name__ == "__main__":
    main()
