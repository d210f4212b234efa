"""A vectorized mimic environment that steps all its environments as one batch, in one process.

Per control step an :class:`envs.mimic.MimicEnv` spends about as long in Python (reading the bodies,
the reward's face points, the observation, the terminations) as in ``mj_step``, and each piece is a
handful of NumPy calls on arrays of 20 bodies: the calls' overhead, not the arithmetic, is the cost.
:class:`BatchedMimicVecEnv` runs the stages of :meth:`MimicEnv.step` for ``N`` environments at once:

1. every environment takes its action (the smoothing of ``_begin_step`` as one array operation,
   each environment's frames' PD targets from ``_advance``);
2. the physics of all of them, split over threads (``mj_step`` releases the GIL, so the threads run
   on separate cores), each thread also bringing its bodies' kinematics up to date and copying
   them, the joint velocities and the contact pairs into ``(N, ...)`` arrays;
3. the instability checks, the reward terms, the observations and the floor contacts of all ``N``
   in one batch of array operations (``_tracking_terms``, ``_tracking_observation`` and the
   functions of ``_blew_up`` and ``_touch``: the same functions a single environment uses);
4. every environment's terminations, failure-sampler record and ``info`` (``_end_step``).

:class:`BatchShard` puts such a batch in each shard of :class:`agents.vec_env.ShardedVecEnv`
(``--vec sharded-batched``): one process per core, so the batches' remaining Python runs on every
core too.

The environments themselves stay ordinary :class:`MimicEnv` objects (resets, clip sampling, the
reference tracks, ``get_attr``/``env_method``), so a batch steps exactly as the same environments
would one at a time (``tests/test_batched_vec_env.py`` compares them). Only :class:`MimicEnv` itself is
batched: a subclass with its own reward or observation (``MimicGait-v0``) is refused.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import gymnasium as gym
import mujoco
import numpy as np
from stable_baselines3.common.monitor import Monitor
from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvIndices

from agents.vec_env import shard_count, vec_reset, vec_step_result
from envs.bodies import bodies_touching, body_state, geoms_touching, region_contacts, update_kinematics
from envs.mimic import MimicEnv, smoothed_action
from envs.reference import ReferenceFrame
from envs.rewards import unstable


class BatchedMimicVecEnv(VecEnv):
    """``len(env_fns)`` :class:`MimicEnv` environments stepped as one batch in this process: the
    physics on ``n_threads`` threads, the rewards and observations vectorised over environments.

    Args:
        env_fns: functions that each build one environment (as for ``DummyVecEnv``; pass this class
            as ``make_vec_env(..., vec_env_cls=BatchedMimicVecEnv)``). Each must build a
            :class:`MimicEnv` (``MimicIMU-v0`` and its ablations), wrapped at most in ``Monitor`` and
            gymnasium's checkers, which are not stepped: ``info["episode"]`` (return ``r``, length
            ``l``, time ``t``) is filled at the end of each episode as ``Monitor`` would. Hooks
            (``frame_hook``, ``substep_hook``) are not called, so an env with one is refused.
        n_threads: threads stepping the physics, this one included (default: one per core this
            process may run on, at most one per environment).

    Raises:
        ValueError: an environment is not a :class:`MimicEnv` or has another wrapper, or the
            environments differ in model, configuration, observation or action layout.
    """

    def __init__(self, env_fns: list[Callable[[], gym.Env]], n_threads: int | None = None):
        if not env_fns:
            raise ValueError("BatchedMimicVecEnv needs at least one environment")
        if n_threads is not None and n_threads < 1:
            raise ValueError(f"n_threads must be >= 1 or None, got {n_threads}")
        self.envs: list[MimicEnv] = [_unwrapped(fn(), i) for i, fn in enumerate(env_fns)]
        first = self.envs[0]
        for i, env in enumerate(self.envs):
            if type(env) is not MimicEnv:
                raise ValueError(f"BatchedMimicVecEnv batches MimicEnv's own reward and observation; env {i} is a "
                                 f"{type(env).__name__} (use agents.vec_env.ShardedVecEnv for it)")
            if (env.humanoid.name, env.config, env.observation_space, env.action_space) != (
                    first.humanoid.name, first.config, first.observation_space, first.action_space):
                raise ValueError(f"env {i} differs from env 0 in model, config, observation or action space; "
                                 "a batch needs them alike")
        n = len(self.envs)
        n_threads = shard_count(n_threads, n)
        self.shards = [list(s) for s in np.array_split(np.arange(n), n_threads)]
        self._pool = ThreadPoolExecutor(n_threads - 1) if n_threads > 1 else None
        bodies = first.model.nbody - 1
        self._xpos, self._xquat = np.zeros((n, bodies, 3)), np.zeros((n, bodies, 4))
        self._xmat, self._cvel = np.zeros((n, bodies, 9)), np.zeros((n, bodies, 6))
        self._com, self._com_vel = np.zeros((n, 3)), np.zeros((n, 3))
        self._qvel = np.zeros((n, first.model.nv))
        self._contact_pairs: list[np.ndarray] = [np.empty((0, 2), int)] * n
        self._bad_acceleration = np.zeros(n, dtype=bool)
        self._unstable = np.zeros(n, dtype=bool)
        self._controls = np.zeros((n, first.config.frames_per_control, first.model.nu))
        self._actions = np.zeros((n, *first.action_space.shape))
        self._smoothed = np.zeros((n, *first.action_space.shape))
        """The step's smoothed actions (every env's ``_action`` until the envs that finished reset)."""
        self._episode_return = np.zeros(n)
        self._episode_length = np.zeros(n, dtype=int)
        self._started = time.time()
        super().__init__(n, first.observation_space, first.action_space)

    # ------------------------------------------------------------------ stepping
    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self):
        results = self.step_results(self._actions)
        obs = np.empty((self.num_envs, *self.observation_space.shape), dtype=np.float32)
        rewards = np.empty(self.num_envs, dtype=np.float32)
        dones = np.empty(self.num_envs, dtype=bool)
        infos = []
        for i, (obs[i], rewards[i], dones[i], info, reset_info) in enumerate(results):
            if dones[i]:
                self.reset_infos[i] = reset_info
            infos.append(info)
        return obs, rewards, dones, infos

    def step_results(self, actions: np.ndarray) -> list[tuple[np.ndarray, float, bool, dict, dict]]:
        """Step every environment with its row of ``actions`` ``(N, A)``: per environment
        :func:`agents.vec_env.vec_step_result`'s ``(obs, reward, done, info, reset_info)`` (a finished
        episode reset at once), each finished episode's return, length and time in
        ``info["episode"]`` as ``Monitor`` gives them."""
        hooked = next((i for i, env in enumerate(self.envs) if env.frame_hook is not None or env.substep_hook is not None),
                      None)
        if hooked is not None:
            raise RuntimeError(f"env {hooked} has a frame_hook or substep_hook, which a batch does not call; step "
                               "it alone (agents.rollout) or in a DummyVecEnv")
        self._begin_steps(actions)
        self._step_physics()
        return self._finish(self._tracking_results())

    def _begin_steps(self, actions: np.ndarray) -> None:
        """Every environment takes its action (as :meth:`MimicEnv._begin_step`, batched): the
        smoothed actions and the control step's PD targets ``(N, frames_per_control, nu)``."""
        first = self.envs[0]
        self._smoothed = smoothed_action(actions, np.stack([env._action for env in self.envs]), first.config)
        for env in self.envs:
            env._push()
        self._controls = np.stack([env._advance() for env in self.envs])
        self._controls[:, :, first.driven] += self._smoothed[:, None, :]
        for env, action in zip(self.envs, self._smoothed):
            env._action = action

    def _simulate(self, shard: Sequence[int]) -> None:
        """Step the physics of the environments ``shard`` through the control step's frames and read
        their bodies (run on one thread per shard)."""
        for i in shard:
            env = self.envs[i]
            m, d = env.model, env.data
            for ctrl in self._controls[i]:
                d.ctrl[:] = ctrl
                mujoco.mj_step(m, d, nstep=env.substeps)
            self._bad_acceleration[i] = env._bad_acceleration()
            if self._bad_acceleration[i]:  # unstable (MimicEnv._blew_up): the step's bodies are not read
                self._contact_pairs[i] = self._contact_pairs[i][:0]
                continue
            update_kinematics(m, d)
            self._qvel[i], self._xpos[i], self._xquat[i], self._xmat[i] = d.qvel, d.xpos[1:], d.xquat[1:], d.xmat[1:]
            self._cvel[i], self._com[i], self._com_vel[i] = d.cvel[1:], d.subtree_com[1], d.subtree_linvel[1]
            self._contact_pairs[i] = d.contact.geom  # a view, read before any environment steps or resets again

    def _step_physics(self) -> None:
        """The physics of every environment, each shard on a thread (this one included)."""
        others = [self._pool.submit(self._simulate, shard) for shard in self.shards[1:]] if self._pool else []
        try:
            self._simulate(self.shards[0])
        finally:  # every thread done before anything reads the buffers (or raises)
            for future in others:
                future.result()

    def _tracking_results(self) -> list[tuple]:
        """Every environment's gymnasium step result from the bodies :meth:`_simulate` read: the reward
        terms and observations as one batch, then each environment's terminations and ``info``."""
        first, n = self.envs[0], self.num_envs
        self._unstable = self._bad_acceleration | unstable(self._qvel, first.config.max_joint_speed)
        state = body_state(self._xpos, self._xquat, self._xmat, self._cvel, self._com, self._com_vel)
        frames = [env._frame for env in self.envs]
        refs = ReferenceFrame.gather([env._track for env in self.envs], frames)
        judged = (refs if all(env._judge is env._track for env in self.envs)
                  else ReferenceFrame.gather([env._judge for env in self.envs], frames))
        terms = first._tracking_terms(state, judged)
        window = [env._window(env.current_track) for env in self.envs]
        window = None if window[0] is None else tuple(np.stack(parts) for parts in zip(*window))
        observations = first._tracking_observation(state, refs, self._smoothed, window)
        names = first.reward_info_keys
        term_values = np.stack([getattr(terms, k) for k in names], axis=1).tolist()
        # MimicEnv._touch for every environment at once: their floor contacts and spinal bodies down
        owner = np.repeat(np.arange(n), [len(p) for p in self._contact_pairs])
        touching, owner = geoms_touching(np.concatenate(self._contact_pairs), first._floor, owner)
        contacts = region_contacts(touching, first.humanoid.geom_contact_channel, owner, n)
        spinal_contacts = bodies_touching(touching, first._geom_spinal_body, owner, n).tolist()
        results = []
        for i, env in enumerate(self.envs):
            if self._unstable[i]:
                results.append(env._unstable_step())
                continue
            env._sim_contacts = contacts[i]
            step_terms = dict(zip(names, term_values[i]))
            results.append(env._end_step(step_terms["total"], step_terms, observations[i], spinal_contacts[i]))
        return results

    def _finish(self, results: list[tuple]) -> list[tuple[np.ndarray, float, bool, dict, dict]]:
        """Stable-baselines3's per-environment results from the gymnasium ones
        (:func:`agents.vec_env.vec_step_result`), with ``Monitor``'s episode record."""
        out = []
        for i, result in enumerate(results):
            obs, reward, done, info, reset_info = vec_step_result(self.envs[i], result)
            self._episode_return[i] += reward
            self._episode_length[i] += 1
            if done:
                info["episode"] = {"r": round(float(self._episode_return[i]), 6), "l": int(self._episode_length[i]),
                                   "t": round(time.time() - self._started, 6)}
                self._episode_return[i], self._episode_length[i] = 0.0, 0
            out.append((obs, reward, done, info, reset_info))
        return out

    def reset(self) -> np.ndarray:
        results = self.reset_each(self._seeds, self._options)
        self.reset_infos = [info for _, info in results]
        self._reset_seeds()
        self._reset_options()
        return np.stack([obs for obs, _ in results])

    def reset_each(self, seeds: Sequence[int | None], options: Sequence[dict]) -> list[tuple[np.ndarray, dict]]:
        """Reset every environment (:func:`agents.vec_env.vec_reset` with its seed and options):
        per environment ``(obs, reset_info)``."""
        self._episode_return[:], self._episode_length[:] = 0.0, 0
        return [vec_reset(env, seed, opts) for env, seed, opts in zip(self.envs, seeds, options)]

    # ------------------------------------------------------------------ VecEnv's other methods
    def _targets(self, indices: VecEnvIndices) -> list[MimicEnv]:
        return [self.envs[i] for i in self._get_indices(indices)]

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        return [getattr(env, attr_name) for env in self._targets(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        for env in self._targets(indices):
            setattr(env, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs) -> list[Any]:
        return [getattr(env, method_name)(*method_args, **method_kwargs) for env in self._targets(indices)]

    def env_is_wrapped(self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        return [False for _ in self._targets(indices)]  # the environments are stepped unwrapped

    def get_images(self) -> Sequence[np.ndarray | None]:
        return [env.render() for env in self.envs]

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
        for env in self.envs:
            env.close()


_PASSIVE_WRAPPERS = (Monitor, gym.wrappers.OrderEnforcing, gym.wrappers.PassiveEnvChecker)
"""Wrappers a batch may drop: ``Monitor``'s ``info["episode"]`` the batch fills itself, the other two
only check the API."""


def _unwrapped(env: gym.Env, index: int) -> gym.Env:
    """The environment inside ``env``'s wrappers, which must all be :data:`_PASSIVE_WRAPPERS` (a batch
    steps the environment itself: any other wrapper would be skipped)."""
    layer = env
    while isinstance(layer, gym.Wrapper):
        if not isinstance(layer, _PASSIVE_WRAPPERS):
            raise ValueError(f"env {index} is wrapped in {type(layer).__name__}, which BatchedMimicVecEnv would "
                             "skip; wrap the VecEnv instead, or use agents.vec_env.ShardedVecEnv")
        layer = layer.env
    return layer


class BatchShard:
    """A shard of :class:`agents.vec_env.ShardedVecEnv` (``shard=BatchShard``) whose environments are
    stepped as one :class:`BatchedMimicVecEnv` with one physics thread: each shard's process is its
    core, so the batches' Python runs in parallel too, not only their physics."""

    def __init__(self, env_fns: Sequence[Callable[[], gym.Env]]):
        self.batch = BatchedMimicVecEnv(list(env_fns), n_threads=1)
        self.envs: list[MimicEnv] = self.batch.envs

    def step(self, actions: np.ndarray) -> list[tuple[np.ndarray, float, bool, dict, dict]]:
        return self.batch.step_results(actions)

    def reset(self, seeds: Sequence[int | None], options: Sequence[dict]) -> list[tuple[np.ndarray, dict]]:
        return self.batch.reset_each(seeds, options)

    def close(self) -> None:
        self.batch.close()
