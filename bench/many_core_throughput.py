"""How PPO training scales on a machine with many cores (and a GPU): the raw physics per process,
environment stepping alone, and PPO end to end, in one run.

Usage: ``python bench/many_core_throughput.py [--seconds S] [--steps N] [--envs-per-worker K] [--json [OUT]]``

Meant for the lent machine (16 cores, one GPU); it runs anywhere. Three measurements, each in
simulation frames/s (a control step is two 60 Hz frames, as in ``bench/ppo_throughput.py``):

1. **physics**: ``mj_step`` on ``humanoid_1seg`` (random controls, the character on the floor, so
   contacts are on) in 1 process, then in one process per core at once: the share of perfect
   scaling the cores give (memory bandwidth, turbo and virtual-CPU contention all show here), and
   the frames/s that every core's physics alone would make (the floor of any training run);
2. **env stepping**: ``MimicIMU-v0`` on the DeepMimic walk with random actions and no policy,
   ``K`` envs per process, with ``ShardedVecEnv`` on every core and with ``SubprocVecEnv``;
3. **PPO end to end** (``bench/ppo_throughput.py``'s settings, [256, 256]): ``ShardedVecEnv`` on
   every core with the learner on the CPU and, where there is one, on the GPU, and one
   ``SubprocVecEnv`` env per core; the time of the rollouts and of the updates is reported apart.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import time
from pathlib import Path

import mujoco
import numpy as np
import torch
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.env_util import make_vec_env

from envs import ArtefactMix
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from ppo_throughput import CLIPS, CORES, VEC_CLASSES, Setting, build, parameters

MODEL_FILE = Path(__file__).resolve().parents[1] / "assets" / "mjcf" / "humanoid_1seg.xml"


def physics_process_rate(seconds: float) -> float:
    """``mj_step`` calls/s of one process stepping ``humanoid_1seg`` with random controls for ``seconds``."""
    model = mujoco.MjModel.from_xml_path(str(MODEL_FILE))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        data.ctrl[:] = rng.uniform(-1.0, 1.0, model.nu)
        mujoco.mj_step(model, data, nstep=50)
        steps += 50
        if data.time > 5.0:
            mujoco.mj_resetData(model, data)
    return steps / (time.perf_counter() - start)


def physics_rate(processes: int, seconds: float) -> float:
    """Total ``mj_step`` calls/s of ``processes`` processes stepping at once."""
    with mp.get_context("forkserver").Pool(processes) as pool:
        return float(sum(pool.map(physics_process_rate, [seconds] * processes)))


def env_rate(vec: str, n_envs: int, workers: int, seconds: float) -> float:
    """Frames/s of ``n_envs`` ``MimicIMU-v0`` envs stepped with random actions (no policy)."""
    kwargs = {"n_workers": workers} if vec == "sharded" else {}
    venv = make_vec_env("MimicIMU-v0", n_envs=n_envs, seed=0, vec_env_cls=VEC_CLASSES[vec], vec_env_kwargs=kwargs,
                        env_kwargs={"clips": CLIPS, "artefacts": ArtefactMix(seed=0)})
    rng = np.random.default_rng(0)
    venv.reset()
    actions = rng.normal(0.0, 0.17, (n_envs, *venv.action_space.shape)).astype(np.float32)
    for _ in range(50):  # warm-up
        venv.step(actions)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        venv.step(actions)
        steps += n_envs
    elapsed = time.perf_counter() - start
    venv.close()
    return 2 * steps / elapsed


class PhaseTimer(BaseCallback):
    """Wall time spent collecting rollouts (the rest of ``learn`` is the updates)."""

    def __init__(self) -> None:
        super().__init__()
        self.collecting, self._start = 0.0, 0.0

    def _on_rollout_start(self) -> None:
        self._start = time.perf_counter()

    def _on_rollout_end(self) -> None:
        self.collecting += time.perf_counter() - self._start

    def _on_step(self) -> bool:
        return True


def ppo_rate(setting: Setting, steps: int) -> dict:
    """Frames/s of PPO training in ``setting`` and the shares of rollouts and updates."""
    model = build(setting)
    timer = PhaseTimer()
    start = time.perf_counter()
    model.learn(steps, reset_num_timesteps=False, callback=timer)
    elapsed = time.perf_counter() - start
    model.get_env().close()
    return {"net": setting.net, "n_envs": setting.n_envs, "vec": setting.vec, "workers": setting.workers,
            "device": setting.device, "parameters": parameters([int(n) for n in setting.net.split(",")]),
            "frames_per_s": round(2 * steps / elapsed), "rollout_s": round(timer.collecting, 1),
            "update_s": round(elapsed - timer.collecting, 1)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=8.0, help="timed seconds of each physics and env measurement")
    parser.add_argument("--steps", type=int, default=32768, help="timed PPO control steps per configuration")
    parser.add_argument("--envs-per-worker", type=int, default=4, help="envs per process")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    torch.set_num_threads(1)
    one = physics_rate(1, args.seconds)
    every = physics_rate(CORES, args.seconds)
    n_envs = args.envs_per_worker * CORES
    env_rows = [{"vec": "sharded", "n_envs": n_envs, "workers": CORES,
                 "frames_per_s": round(env_rate("sharded", n_envs, CORES, args.seconds))},
                {"vec": "subproc", "n_envs": CORES, "workers": CORES,
                 "frames_per_s": round(env_rate("subproc", CORES, CORES, args.seconds))}]
    devices = ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])
    ppo_rows = [ppo_rate(Setting("256,256", n_envs, "sharded", 1, CORES, device), args.steps) for device in devices]
    ppo_rows.append(ppo_rate(Setting("256,256", CORES, "subproc", 1), args.steps))
    frames_per_physics_step = mujoco.MjModel.from_xml_path(str(MODEL_FILE)).opt.timestep * 60.0
    result = {"cores": CORES, "gpu": torch.cuda.get_device_name() if torch.cuda.is_available() else None,
              "physics_steps_per_s_one_process": round(one), "physics_steps_per_s_every_core": round(every),
              "physics_scaling": round(every / (one * CORES), 3), "physics_floor_frames_per_s": round(every * frames_per_physics_step),
              "env_stepping": env_rows, "ppo": ppo_rows}
    if not emit_json(result, args.json):
        print(f"{CORES} cores, GPU: {result['gpu']}")
        print(f"physics: {one:.0f} mj_step/s in one process, {every:.0f} in {CORES} "
              f"({100 * result['physics_scaling']:.0f}% of perfect scaling): "
              f"floor {result['physics_floor_frames_per_s']} frames/s")
        for r in env_rows:
            print(f"env stepping, {r['n_envs']} envs {r['vec']}: {r['frames_per_s']} frames/s")
        for r in ppo_rows:
            print(f"PPO {r['net']} {r['n_envs']} envs {r['vec']} ({r['workers'] or r['n_envs']} processes), learner on {r['device']}: "
                  f"{r['frames_per_s']} frames/s (rollouts {r['rollout_s']} s, updates {r['update_s']} s)")


if __name__ == "__main__":
    main()
