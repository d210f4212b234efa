"""A vectorized environment that steps its environments in a few worker processes, several per worker.

Stable-baselines3 offers two extremes: ``DummyVecEnv`` steps every environment in the learner's
process (one core does all the physics) and ``SubprocVecEnv`` gives every environment its own
process (one pipe round trip per environment and step, which on 2 cores costs more than it gains:
``bench/ppo_throughput.py``). :class:`ShardedVecEnv` sits between: ``n_envs`` environments split
into ``n_workers`` contiguous shards, the first stepped in the learner's process and each other in
a worker process, one round trip per worker and step. With one shard per core the physics of a
step runs on every core at once.

Environments in one worker share what environments of one process share (``envs.mimic``'s reference
tracks); each worker builds its own.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import time
import traceback
from collections.abc import Callable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.env_util import is_wrapped
from stable_baselines3.common.vec_env.base_vec_env import CloudpickleWrapper, VecEnv, VecEnvIndices


class WorkerError(RuntimeError):
    """An environment raised inside a worker process; the message carries the worker's traceback."""


def _step(env: gym.Env, action: np.ndarray) -> tuple[Any, float, bool, dict, dict]:
    """One step of ``env`` in stable-baselines3's VecEnv convention (:func:`vec_step_result`)."""
    return vec_step_result(env, env.step(action))


def vec_step_result(env: gym.Env, result: tuple) -> tuple[Any, float, bool, dict, dict]:
    """Stable-baselines3's VecEnv convention for ``env``'s gymnasium step ``result`` ``(obs, reward,
    terminated, truncated, info)``: ``(obs, reward, done, info, reset_info)``, a finished episode
    reset at once, its last observation kept in ``info["terminal_observation"]``."""
    obs, reward, terminated, truncated, info = result
    done = terminated or truncated
    info["TimeLimit.truncated"] = truncated and not terminated
    reset_info: dict = {}
    if done:
        info["terminal_observation"] = obs
        obs, reset_info = env.reset()
    return obs, reward, done, info, reset_info


def vec_reset(env: gym.Env, seed: int | None, options: dict) -> tuple[Any, dict]:
    """``env.reset`` with ``seed`` and, unless empty, ``options`` (as stable-baselines3's VecEnvs)."""
    return env.reset(seed=seed, **({"options": options} if options else {}))


def _call(env: gym.Env, kind: str, name: str, payload: Any) -> Any:
    if kind == "get_attr":
        return env.get_wrapper_attr(name)
    if kind == "set_attr":
        return setattr(env, name, payload)
    if kind == "env_method":
        args, kwargs = payload
        return env.get_wrapper_attr(name)(*args, **kwargs)
    if kind == "is_wrapped":
        return is_wrapped(env, payload)
    if kind == "render":
        return env.render()
    raise ValueError(f"unknown worker call {kind!r}")


def _wait(connection, spin_s: float) -> None:
    """Wait for ``connection`` to have data: poll without sleeping for ``spin_s`` seconds, then block.
    Waking a blocked process costs ~1 ms on these virtual machines, longer than a step of a shard;
    between the steps of a rollout the wait is shorter than the spin and costs no wake-up. Each poll
    yields the core, but a yield does not reliably hand it to another process: two sharded trainings
    on 2 cores, their learners spinning without end, left their workers 6% of a core each (the
    spin is therefore bounded on both sides)."""
    deadline = time.perf_counter() + spin_s
    while not connection.poll(0):
        if time.perf_counter() > deadline:
            connection.poll(None)
            return
        os.sched_yield()


class EnvShard:
    """The environments of one :class:`ShardedVecEnv` shard, stepped one after another (the default
    shard). A shard class is built from the shard's environment functions and offers ``envs`` (the
    environments, for attribute and method calls), ``step(actions)`` and ``reset(seeds, options)``
    (one result per environment: :func:`vec_step_result`'s tuple, :func:`vec_reset`'s) and
    ``close()``; :class:`agents.batched_vec_env.BatchShard` steps its environments as one batch."""

    def __init__(self, env_fns: Sequence[Callable[[], gym.Env]]):
        self.envs: list[gym.Env] = [fn() for fn in env_fns]

    def step(self, actions: np.ndarray) -> list[tuple[Any, float, bool, dict, dict]]:
        return [_step(env, a) for env, a in zip(self.envs, actions)]

    def reset(self, seeds: Sequence[int | None], options: Sequence[dict]) -> list[tuple[Any, dict]]:
        return [vec_reset(env, s, o) for env, s, o in zip(self.envs, seeds, options)]

    def close(self) -> None:
        for env in self.envs:
            env.close()


def _serve(remote, parent_remote, env_fns: CloudpickleWrapper, spin_s: float, shard_cls: type) -> None:
    """Worker loop: build the shard (``shard_cls`` of its environment functions), then answer the
    parent's commands until ``close``. Every answer is ``(ok, value)``; an exception is sent back as
    ``(False, (is it an AttributeError, traceback text))``."""
    parent_remote.close()
    shard = None
    while True:
        try:
            _wait(remote, spin_s)
            cmd, data = remote.recv()
        except (EOFError, OSError, KeyboardInterrupt):  # the parent has gone
            break
        try:
            if cmd == "build":
                shard = shard_cls(env_fns.var)
                value = None
            elif cmd == "step":
                value = shard.step(data)
            elif cmd == "reset":
                value = shard.reset(*data)
            elif cmd == "call":
                kind, name, payload, local = data
                value = [_call(shard.envs[j], kind, name, payload) for j in local]
            elif cmd == "close":
                if shard is not None:
                    shard.close()
                break
            else:
                raise ValueError(f"unknown command {cmd!r}")
            remote.send((True, value))
        except Exception as error:  # noqa: BLE001 (sent to the parent, which raises it there)
            remote.send((False, (isinstance(error, AttributeError), traceback.format_exc())))


def shard_count(workers: int | None, n_envs: int) -> int:
    """Shards (worker processes) for ``n_envs`` environments: ``workers``, by default one per core
    this process may run on, and never more than the environments."""
    return min(workers or len(os.sched_getaffinity(0)), n_envs)


class ShardedVecEnv(VecEnv):
    """``len(env_fns)`` environments in ``n_workers`` contiguous shards (sizes differing by at most
    one) stepped in parallel: shard 0 in this process, every other shard in a worker process.

    This process steps its own shard while the workers step theirs, then polls for their answers
    for ``spin_ms`` before it blocks; the workers likewise poll for the next command. On the
    project's 2-core virtual machines a blocked process takes about a millisecond to wake, as long as
    a 4-environment shard takes to step, so neither side blocks inside a rollout unless the cores
    are shared with other work, which then gets them.

    Args:
        env_fns: functions that each build one environment (as for ``SubprocVecEnv``; pass this class
            as ``make_vec_env(..., vec_env_cls=ShardedVecEnv, vec_env_kwargs={"n_workers": k})``).
        n_workers: shards, this process included (default 2: one per core of the project's
            machines; 1 is a ``DummyVecEnv``); at most ``len(env_fns)``.
        spin_ms: how long a worker polls for the next command, and this process for the workers'
            answers, before it blocks (ms).
        start_method: ``multiprocessing`` start method (default ``forkserver``, which is safe with
            torch's threads in this process, else ``spawn``).
        shard: how each shard steps its environments (default :class:`EnvShard`: one after another;
            :class:`agents.batched_vec_env.BatchShard`: as one batch).

    Raises:
        WorkerError: an environment raised in a worker (the message has its traceback).
    """

    def __init__(self, env_fns: list[Callable[[], gym.Env]], n_workers: int = 2, spin_ms: float = 5.0,
                 start_method: str | None = None, shard: type = EnvShard):
        if not env_fns:
            raise ValueError("ShardedVecEnv needs at least one environment")
        if not 1 <= n_workers <= len(env_fns):
            raise ValueError(f"n_workers must be 1..{len(env_fns)} (one environment at least per shard), "
                             f"got {n_workers}")
        if start_method is None:
            start_method = "forkserver" if "forkserver" in mp.get_all_start_methods() else "spawn"
        ctx = mp.get_context(start_method)
        self.shards = [list(s) for s in np.array_split(np.arange(len(env_fns)), n_workers)]
        self._spin_s = spin_ms / 1000
        self._where = [(w, j) for w, members in enumerate(self.shards) for j in range(len(members))]
        self.remotes, self.processes = [], []
        self._pending: list[int] = []  # answers each worker still owes
        self.closed = False
        for shard_envs in self.shards[1:]:
            remote, work_remote = ctx.Pipe()
            process = ctx.Process(target=_serve, daemon=True, args=(
                work_remote, remote, CloudpickleWrapper([env_fns[i] for i in shard_envs]), spin_ms / 1000, shard))
            process.start()
            work_remote.close()
            self.remotes.append(remote)
            self.processes.append(process)
            self._pending.append(0)
        self._send_each("build", [None] * len(self.shards))  # the workers build theirs while this process does
        self.local = shard([env_fns[i] for i in self.shards[0]])
        self.local_envs = self.local.envs
        self._gather()
        self._actions: np.ndarray | None = None
        super().__init__(len(env_fns), self.local_envs[0].observation_space, self.local_envs[0].action_space)

    def _gather(self) -> list[Any]:
        """Every worker's answer, in shard order; raises the first worker's error once every answer
        is read (so that the pipes stay in step for the next command)."""
        answers, failures = [], []
        for w, remote in enumerate(self.remotes, start=1):
            try:
                _wait(remote, self._spin_s)
                ok, value = remote.recv()
            except EOFError as error:
                self._drain()
                raise WorkerError(f"env worker {w} (pid {self.processes[w - 1].pid}) died") from error
            self._pending[w - 1] -= 1
            answers.append(value)
            if not ok:
                failures.append((w, *value))
        if failures:
            w, missing_attribute, trace = failures[0]
            if missing_attribute:  # VecEnv.has_attr relies on AttributeError
                raise AttributeError(f"env worker {w}:\n{trace}")
            raise WorkerError(f"env worker {w} failed:\n{trace}")
        return answers

    def _local_then_gather(self, local_work: Callable[[], list[Any]]) -> list[Any]:
        """``local_work()`` (this process's shard, run while the workers run theirs) followed by every
        worker's answer, as one list in env order. If the local shard raises, the workers' answers are
        still read, so that the pipes stay in step for the next command."""
        try:
            local = local_work()
        except BaseException:
            self._drain()
            raise
        return [local, *self._gather()]

    def _drain(self, timeout_s: float = 60.0) -> None:
        """Read and drop every answer the workers still owe (after an error or an interrupt here),
        waiting at most ``timeout_s`` for each."""
        for w, remote in enumerate(self.remotes):
            while self._pending[w] > 0:
                self._pending[w] -= 1
                try:
                    if not remote.poll(timeout_s):
                        break
                    remote.recv()
                except (EOFError, OSError):
                    break

    def _send_each(self, command: str, per_shard: list[Any]) -> None:
        for w, (remote, data) in enumerate(zip(self.remotes, per_shard[1:])):
            remote.send((command, data))
            self._pending[w] += 1

    def step_async(self, actions: np.ndarray) -> None:
        self._send_each("step", [actions[s[0]:s[-1] + 1] for s in self.shards])
        self._actions = actions[:len(self.shards[0])]

    def step_wait(self):
        shards = self._local_then_gather(lambda: self.local.step(self._actions))
        results = [r for shard in shards for r in shard]
        obs, rewards, dones, infos, reset_infos = zip(*results)
        for i, info in enumerate(reset_infos):
            if dones[i]:
                self.reset_infos[i] = info
        return np.stack(obs), np.array(rewards, dtype=np.float32), np.array(dones), list(infos)

    def reset(self):
        per_shard = [([self._seeds[i] for i in s], [self._options[i] for i in s]) for s in self.shards]
        self._send_each("reset", per_shard)
        seeds, options = per_shard[0]
        shards = self._local_then_gather(lambda: self.local.reset(seeds, options))
        results = [r for shard in shards for r in shard]
        obs, reset_infos = zip(*results)
        self.reset_infos = list(reset_infos)
        self._reset_seeds()
        self._reset_options()
        return np.stack(obs)

    def _call(self, kind: str, name: str, payload: Any, indices: VecEnvIndices) -> list[Any]:
        """Run ``kind`` (get_attr, set_attr, env_method, is_wrapped, render) on the envs ``indices``."""
        wanted = self._get_indices(indices)
        local = [[] for _ in self.shards]
        for i in wanted:
            w, j = self._where[i]
            local[w].append(j)
        self._send_each("call", [(kind, name, payload, js) for js in local])
        answers = self._local_then_gather(lambda: [_call(self.local_envs[j], kind, name, payload) for j in local[0]])
        position = [iter(values) for values in answers]
        return [next(position[self._where[i][0]]) for i in wanted]

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        return self._call("get_attr", attr_name, None, indices)

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        self._call("set_attr", attr_name, value, indices)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs) -> list[Any]:
        return self._call("env_method", method_name, (method_args, method_kwargs), indices)

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        return self._call("is_wrapped", "", wrapper_class, indices)

    def get_images(self) -> Sequence[np.ndarray | None]:
        return self._call("render", "", None, None)

    def close(self) -> None:
        if self.closed:
            return
        self._drain()  # a step interrupted here (Ctrl-C, kill) may have left answers unread
        for remote in self.remotes:
            try:
                remote.send(("close", None))
            except OSError:  # the worker has gone already
                pass
        for process in self.processes:
            process.join(timeout=10.0)
            if process.is_alive():
                process.terminate()
        for remote in self.remotes:
            remote.close()
        self.local.close()
        self.closed = True

