"""PPO training throughput (environment frames/s, collection and updates included) per network size and
vectorisation, against the raw-physics floor measured in the same run.

Usage: ``python bench/ppo_throughput.py [--steps N] [--rounds R] [--json [OUT]]``

Each configuration is trained for ``N`` control steps on ``MimicIMU-v0`` (walk, half the episodes
IMU-corrupted) with the PPO settings of ``agents/train_ppo.py`` (6 epochs, minibatch 512, 8192
steps per rollout), after a warm-up rollout. Configurations (``R`` rounds, interleaved, the median
reported; the machine is noisy):

* networks [1024, 1024, 512] (ADAPT), [256, 256] (ours), [128, 128] with 8 envs in the learner's
  process (``--vec dummy``, 2 torch threads);
* [256, 256] with 8 envs, one subprocess each (``--vec subproc``, 1 torch thread);
* [256, 256] with 8 or 16 envs in one shard per core (2 on the project's machines: this process
  and one worker; ``--vec sharded``, 1 torch thread: ``agents/vec_env.py``);
* [256, 256] with 16 or 32 envs stepped as one batch in the learner's process, their physics on one
  thread per core (``--vec batched``, the default: ``agents/batched_vec_env.py``), the learner on 1 torch thread
  while collecting and one per core while updating (``train_ppo.UpdateThreads``);
* [256, 256] with 32 or 64 envs in one shard per core, each shard stepped as one batch (``--vec
  sharded-batched``; 64: ``--n-envs 64``, 128 steps per env and rollout), the learner's threads as with
  ``batched``;
* the 64-env row again with 3 PPO epochs per rollout instead of 6 (``--epochs 3``): half the update's
  arithmetic. It needs more frames to learn; ``bench/time_to_sr90.py --epochs 3`` measures how many
  (at twice the learning rate, walk reaches SR90 sooner in wall time: docs/results.md, stop 96).

A control step is two 60 Hz frames; ``frames_per_s`` counts simulation frames (ADAPT's unit).
The physics floor is the rate at which the cores would produce those frames doing nothing but
``mj_step``: the ``mj_step`` calls of one in-process run (the same states and contacts PPO sees)
are timed, and the floor is frames / that time × the cores (2: the physics of separate
environments is independent). No training run on these cores can be faster.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import statistics
import time
from dataclasses import dataclass

import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecNormalize

import envs  # noqa: F401  (registers the ids)
from agents.batched_vec_env import BatchedMimicVecEnv, BatchShard
from agents.train_ppo import UpdateThreads
from agents.vec_env import ShardedVecEnv, shard_count
from envs import ArtefactMix
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from physics_timer import timing_mj_step  # bench/physics_timer.py

CORES = len(os.sched_getaffinity(0))
CLIPS = ["deepmimic:walk"]


@dataclass(frozen=True)
class Setting:
    """One row: the hidden layers, the envs and how they are stepped, the learner's torch threads; with
    ``--vec sharded`` the worker processes (``None``: one per core, at most one per env); the
    learner's torch device; PPO's optimisation epochs per rollout."""

    net: str
    n_envs: int
    vec: str
    torch_threads: int
    workers: int | None = None
    device: str = "cpu"
    update_threads: int | None = None
    epochs: int = 6

    @property
    def label(self) -> str:
        workers = f" on {self.workers} processes" if self.workers else ""
        epochs = f" / {self.epochs} epochs" if self.epochs != 6 else ""
        return (f"{self.net} / {self.n_envs} {self.vec}{workers} / {self.threads_label} thread(s) / "
                f"{self.device}{epochs}")

    @property
    def threads_label(self) -> str:
        """The learner's torch threads: ``"1"``, or ``"1+2"`` (collecting + updating) where they differ."""
        update = self.update_threads or self.torch_threads
        return str(self.torch_threads) if update == self.torch_threads else f"{self.torch_threads}+{update}"

    def callbacks(self) -> list:
        """``train_ppo.py``'s thread switch between rollouts and updates, where the setting has one."""
        return [UpdateThreads(self.torch_threads, self.update_threads)] if self.update_threads else []


SETTINGS = [Setting("1024,1024,512", 8, "dummy", 2), Setting("256,256", 8, "dummy", 2),
            Setting("128,128", 8, "dummy", 2), Setting("256,256", 8, "subproc", 1),
            Setting("256,256", 8, "sharded", 1), Setting("256,256", 16, "sharded", 1),
            Setting("256,256", 16, "batched", 1, update_threads=CORES),
            Setting("256,256", 32, "batched", 1, update_threads=CORES),
            Setting("256,256", 32, "sharded-batched", 1, update_threads=CORES),
            Setting("256,256", 64, "sharded-batched", 1, update_threads=CORES),
            Setting("256,256", 64, "sharded-batched", 1, update_threads=CORES, epochs=3)]
VEC_CLASSES = {"dummy": DummyVecEnv, "subproc": SubprocVecEnv, "sharded": ShardedVecEnv, "batched": BatchedMimicVecEnv,
               "sharded-batched": functools.partial(ShardedVecEnv, shard=BatchShard)}


def build(setting: Setting) -> PPO:
    """A fresh PPO learner of ``setting`` (train_ppo.py's settings, seed 0)."""
    torch.set_num_threads(setting.torch_threads)
    vec_kwargs = ({"n_workers": shard_count(setting.workers, setting.n_envs)} if setting.vec.startswith("sharded")
                  else {"n_threads": shard_count(setting.workers, setting.n_envs)} if setting.vec == "batched" else {})
    venv = VecNormalize(make_vec_env("MimicIMU-v0", n_envs=setting.n_envs, seed=0,
                                     vec_env_cls=VEC_CLASSES[setting.vec], vec_env_kwargs=vec_kwargs,
                                     env_kwargs={"clips": CLIPS, "artefacts": ArtefactMix(seed=0)}), norm_reward=False)
    net = [int(n) for n in setting.net.split(",")]
    model = PPO("MlpPolicy", venv, n_steps=8192 // setting.n_envs, batch_size=512, n_epochs=setting.epochs,
                learning_rate=5e-5, device=setting.device, seed=0,
                policy_kwargs={"net_arch": {"pi": net, "vf": net}, "activation_fn": torch.nn.Tanh,
                               "log_std_init": 0.5 * math.log(0.03)})
    model.learn(8192, callback=setting.callbacks())  # warm-up: one rollout and update
    return model


def rate(setting: Setting, steps: int) -> tuple[float, float, float]:
    """Control steps/s of PPO training in ``setting``, and the wall time (µs per control step) spent
    collecting rollouts and updating."""
    model = build(setting)
    spent = {"collect": 0.0, "update": 0.0}

    def timed(name: str, method):
        def run(*args, **kwargs):
            start = time.perf_counter()
            try:
                return method(*args, **kwargs)
            finally:
                spent[name] += time.perf_counter() - start
        return run

    model.collect_rollouts = timed("collect", model.collect_rollouts)
    model.train = timed("update", model.train)
    start = time.perf_counter()
    model.learn(steps, reset_num_timesteps=False, callback=setting.callbacks())
    elapsed = time.perf_counter() - start
    model.get_env().close()
    return steps / elapsed, 1e6 * spent["collect"] / steps, 1e6 * spent["update"] / steps


def physics_floor(steps: int) -> float:
    """Control steps/s of the ``mj_step`` calls alone on one core, timed inside an in-process run."""
    model = build(Setting("256,256", 8, "dummy", 2))
    with timing_mj_step() as physics:
        model.learn(steps, reset_num_timesteps=False)
    model.get_env().close()
    return steps / physics.busy_s


def parameters(net: list[int], n_obs: int = 273, n_act: int = 20) -> int:
    """Weights and biases of actor and critic MLPs with hidden layers ``net``."""
    return sum(a * b + b for a, b in zip([n_obs] + net, net + [n_act])) + sum(
        a * b + b for a, b in zip([n_obs] + net, net + [1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=16384, help="timed control steps per configuration")
    parser.add_argument("--rounds", type=int, default=2, help="interleaved rounds (the median is reported)")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    measured: dict[str, list[tuple[float, float, float]]] = {s.label: [] for s in SETTINGS}
    floors = []
    for _ in range(args.rounds):
        floors.append(physics_floor(args.steps))
        for setting in SETTINGS:
            measured[setting.label].append(rate(setting, args.steps))
    floor_frames = 2 * statistics.median(floors) * CORES
    rows = []
    for setting in SETTINGS:
        rounds = measured[setting.label]
        steps_per_s = statistics.median(r[0] for r in rounds)
        rows.append({"net": setting.net, "n_envs": setting.n_envs, "vec": setting.vec, "epochs": setting.epochs,
                     "torch_threads": setting.threads_label,
                     "parameters": parameters([int(n) for n in setting.net.split(",")]),
                     "frames_per_s": round(2 * steps_per_s), "rounds_frames_per_s": [round(2 * r[0]) for r in rounds],
                     "collect_us_per_step": round(statistics.median(r[1] for r in rounds)),
                     "update_us_per_step": round(statistics.median(r[2] for r in rounds)),
                     "share_of_floor": round(2 * steps_per_s / floor_frames, 3)})
    base = rows[0]["frames_per_s"]
    for r in rows:
        r["speedup_vs_first"] = round(r["frames_per_s"] / base, 2)
    result = {"steps": args.steps, "rounds": args.rounds, "cores": CORES, "clips": CLIPS,
              "physics_floor_frames_per_s": round(floor_frames),
              "physics_floor_frames_per_s_one_core": round(2 * statistics.median(floors)), "rows": rows}
    if not emit_json(result, args.json):
        print(f"physics floor: {result['physics_floor_frames_per_s']} frames/s on {CORES} cores")
        for r in rows:
            print(f"{r['net']:>14}  {r['n_envs']:>2} {r['vec']:>15}  {r['torch_threads']} thr  {r['epochs']} ep  "
                  f"{r['parameters']:>9} "
                  f"params  {r['frames_per_s']:>6} frames/s  ×{r['speedup_vs_first']}  "
                  f"{100 * r['share_of_floor']:.0f}% of floor  (collect {r['collect_us_per_step']} µs, update "
                  f"{r['update_us_per_step']} µs a step)")


if __name__ == "__main__":
    main()
