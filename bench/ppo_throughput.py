"""PPO training throughput (environment frames/s, collection and updates included) per network size.

Usage: ``python bench/ppo_throughput.py [--steps N] [--nets 1024,1024,512 256,256 128,128] [--json [OUT]]``

Each configuration is trained for ``N`` control steps on ``MimicIMU-v0`` (walk) with the PPO
settings of ``agents/train_ppo.py`` (6 epochs, minibatch 512, 8192 steps per rollout), in the same
run so the ratios are comparable: every network with the default vectorisation (8 envs in-process,
2 torch threads), and the default network with 2 subprocess envs (1 torch thread) for contrast. A control step is two 60 Hz frames; ``frames_per_s`` counts
simulation frames (ADAPT's unit), ``steps_per_s`` policy steps.
"""

from __future__ import annotations

import argparse
import math
import time

import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecNormalize

import envs  # noqa: F401  (registers the ids)
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/


def rate(net: list[int], steps: int, n_envs: int, subproc: bool) -> float:
    """Control steps/s of PPO training with hidden layers ``net``."""
    torch.set_num_threads(1 if subproc else 2)
    venv = VecNormalize(make_vec_env("MimicIMU-v0", n_envs=n_envs, seed=0,
                                     vec_env_cls=SubprocVecEnv if subproc else DummyVecEnv,
                                     env_kwargs={"clips": ["deepmimic:walk"]}), norm_reward=False)
    model = PPO("MlpPolicy", venv, n_steps=8192 // n_envs, batch_size=512, n_epochs=6, learning_rate=5e-5,
                device="cpu", seed=0, policy_kwargs={"net_arch": {"pi": net, "vf": net}, "activation_fn": torch.nn.Tanh,
                                                     "log_std_init": 0.5 * math.log(0.03)})
    model.learn(8192)  # warm-up: one rollout and update
    start = time.perf_counter()
    model.learn(steps, reset_num_timesteps=False)
    elapsed = time.perf_counter() - start
    venv.close()
    return steps / elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=16384)
    parser.add_argument("--nets", nargs="+", default=["1024,1024,512", "256,256", "128,128"])
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    rows = []
    configs = [(spec, 8, False) for spec in args.nets] + [("256,256", 2, True)]
    for spec, n_envs, subproc in configs:
        net = [int(n) for n in spec.split(",")]
        steps_per_s = rate(net, args.steps, n_envs, subproc)
        params = sum(a * b + b for a, b in zip([273] + net, net + [20])) + sum(a * b + b for a, b in zip([273] + net, net + [1]))
        rows.append({"net": spec, "envs": f"{n_envs} {'subproc' if subproc else 'in-process'}", "parameters": params,
                     "steps_per_s": round(steps_per_s), "frames_per_s": round(2 * steps_per_s)})
    base = rows[0]["steps_per_s"]
    for r in rows:
        r["speedup_vs_first"] = round(r["steps_per_s"] / base, 2)
    if not emit_json({"steps": args.steps, "rows": rows}, args.json):
        for r in rows:
            print(f"{r['net']:>14}  {r['envs']:>12}  {r['parameters']:>9} params  {r['frames_per_s']:>6} frames/s  "
                  f"×{r['speedup_vs_first']}")


if __name__ == "__main__":
    main()
