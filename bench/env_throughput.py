"""Control steps per second of MimicIMU-v0 against its physics floor and Gymnasium's Humanoid-v5.

Usage: ``python bench/env_throughput.py [--steps N] [--rounds R] [--json [OUT]]``

Measured in one process pinned to one core, the three loops interleaved over ``R`` rounds (the
machine is noisy; the median round is reported):

* ``mimic_steps_per_s``: ``gym.make("MimicIMU-v0")`` (its defaults: 7 locomotion clips, the
  clean/IMU mix) stepped with seeded uniform random actions, resets included, as PPO sees it.
* ``physics_floor_steps_per_s``: the time of the raw ``mj_step`` calls alone (the same model,
  substeps per control step, states and contacts): the same episodes are run again with the
  same seed and actions and only the ``mj_step`` calls are timed. No environment can be faster.
* ``ratio`` = mimic / floor; ``humanoid_v5_steps_per_s`` for scale (random actions).
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import gymnasium as gym
import mujoco
import numpy as np

import envs  # noqa: F401  (registers the ids)
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from physics_timer import timing_mj_step  # bench/physics_timer.py
from reference_motion.cli import positive_int


def mimic_rate(env: gym.Env, actions: np.ndarray) -> tuple[float, float]:
    """(control steps/s, mean episode length in steps) over ``actions``."""
    env.reset(seed=0)
    episodes, length = [], 0
    start = time.perf_counter()
    for a in actions:
        _, _, term, trunc, _ = env.step(a)
        length += 1
        if term or trunc:
            episodes.append(length)
            length = 0
            env.reset()
    rate = len(actions) / (time.perf_counter() - start)
    return rate, float(np.mean(episodes)) if episodes else float(len(actions))


def floor_rate(env: gym.Env, actions: np.ndarray) -> float:
    """Control steps/s of the physics alone: the same episodes as :func:`mimic_rate` (same seed,
    same actions, so the same states and contacts), timing only the ``mj_step`` calls."""
    with timing_mj_step() as physics:
        mimic_rate(env, actions)
    return len(actions) / physics.busy_s


def humanoid_v5_rate(n_steps: int) -> float:
    env = gym.make("Humanoid-v5")
    env.reset(seed=0)
    actions = np.random.default_rng(0).uniform(-0.4, 0.4, (n_steps, env.action_space.shape[0])).astype(np.float32)
    start = time.perf_counter()
    for a in actions:
        _, _, term, trunc, _ = env.step(a)
        if term or trunc:
            env.reset()
    rate = n_steps / (time.perf_counter() - start)
    env.close()
    return rate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=10_000, help="control steps per loop and round")
    parser.add_argument("--rounds", type=positive_int, default=3, help="interleaved rounds (median reported)")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})

    env = gym.make("MimicIMU-v0")
    low, high = env.action_space.low, env.action_space.high
    actions = np.random.default_rng(0).uniform(low, high, (args.steps, low.size)).astype(np.float32)
    env.reset(seed=0)
    base = env.unwrapped
    for clip in range(len(base.clips)):  # build every reference track (clips and corrupted variants) first
        for variant in range(-1, base.artefacts.variants_per_clip):
            base.track(clip, variant)
    rounds = []
    for _ in range(args.rounds):
        mimic, episode = mimic_rate(env, actions)
        floor = floor_rate(env, actions)
        rounds.append({"mimic": mimic, "floor": floor, "ratio": mimic / floor, "v5": humanoid_v5_rate(args.steps),
                       "episode": episode})
    med = {k: statistics.median(r[k] for r in rounds) for k in rounds[0]}
    result = {
        "mimic_steps_per_s": round(med["mimic"]),
        "physics_floor_steps_per_s": round(med["floor"]),
        "ratio": round(med["ratio"], 3),
        "humanoid_v5_steps_per_s": round(med["v5"]),
        "mean_episode_steps": round(med["episode"], 1),
        "substeps_per_control_step": env.unwrapped.config.frames_per_control * env.unwrapped.substeps,
        "rounds": [{k: round(v, 3) for k, v in r.items()} for r in rounds],
        "steps_per_round": args.steps,
        "machine": f"{platform.processor() or platform.machine()}, 1 core, mujoco {mujoco.__version__}",
    }
    if not emit_json(result, args.json):
        print(f"MimicIMU-v0      {result['mimic_steps_per_s']:>7} control steps/s (random actions, resets included)")
        print(f"physics floor    {result['physics_floor_steps_per_s']:>7} control steps/s "
              f"({result['substeps_per_control_step']} raw mj_step each)")
        print(f"ratio            {result['ratio']:>7.3f}")
        print(f"Humanoid-v5      {result['humanoid_v5_steps_per_s']:>7} steps/s")


if __name__ == "__main__":
    main()
