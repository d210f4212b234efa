"""One episode of a policy on a mimic environment, recorded frame by frame: the single rollout
path of evaluation (:mod:`agents.evaluation`), cleaning (:mod:`agents.clean`) and per-clip
adaptation (:mod:`agents.adaptation`).

A policy here is any function from an observation ``(D,)`` float32 to an action ``(A,)``
(:data:`Policy`). :func:`run_episode` resets the environment with the given options (``clip``,
``start_frame``, ``corrupted``, ``state``: see :class:`envs.mimic.MimicEnv`), steps it until the
episode ends or ``max_frames`` reference frames have been simulated, and returns the simulated
``qpos`` and ``qvel`` of every 60 Hz frame from the start state on (:class:`Episode`).
:func:`sampling_policy` gives a trained policy's stochastic actions (its Gaussian exploration
noise), seeded, for retrying a stretch where the deterministic policy fails.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import gymnasium as gym
import mujoco
import numpy as np
import torch

from agents.policy import MimicPolicy

Policy = Callable[[np.ndarray], np.ndarray]
"""Observation ``(D,)`` float32 → action ``(A,)`` (rad offsets, see :class:`envs.mimic.MimicEnv`)."""

FAILURES = ("fallen", "lagging", "unstable")
"""``ended_by`` values of an episode the policy failed (the other ending is ``"time_limit"``)."""


@dataclass(frozen=True)
class Episode:
    """One recorded episode.

    Attributes:
        clip: name of the clip it mimicked.
        start_frame: reference frame of its start state.
        qpos: ``(N + 1, nq)`` simulated generalised positions, the start state then every 60 Hz
            frame simulated (``N`` = :attr:`frames`).
        qvel: ``(N + 1, nv)`` the matching generalised velocities (MuJoCo layout).
        actions: ``(N + 1, A)`` the smoothed action (rad) in effect at each of those states: the one
            the control step that simulated the frame applied, at the start state the one the reset
            gave (:attr:`envs.mimic.MimicEnv.smoothed`). With ``qpos`` and ``qvel`` it is the state
            an episode continues from (reset option ``state``).
        rewards: ``(S,)`` reward of each control step (S = N / frames per control step).
        final_obs: ``(D,)`` the raw observation after the last step (after the reset when no step
            was taken): what the policy would act on next.
        ended_by: ``"fallen"``, ``"lagging"``, ``"unstable"`` or ``"time_limit"``; ``""`` when it
            was stopped at ``max_frames`` while still running.
        episode_end: reference frame at which the environment would have truncated it.
    """

    clip: str
    start_frame: int
    qpos: np.ndarray
    qvel: np.ndarray
    actions: np.ndarray
    rewards: np.ndarray
    final_obs: np.ndarray
    ended_by: str
    episode_end: int

    @property
    def frames(self) -> int:
        """Frames simulated after the start state."""
        return len(self.qpos) - 1

    @property
    def end_frame(self) -> int:
        """Reference frame of the last recorded state."""
        return self.start_frame + self.frames

    @property
    def failed(self) -> bool:
        """Whether it ended by a fall, lagging behind the reference, or the simulation blowing up."""
        return self.ended_by in FAILURES

    def state(self, frame: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The simulated ``(qpos (nq,), qvel (nv,), action (A,))`` at reference frame ``frame``
        (copies; reset option ``state`` continues from it)."""
        k = frame - self.start_frame
        if not 0 <= k <= self.frames:
            raise IndexError(f"frame {frame} outside this episode's frames {self.start_frame}..{self.end_frame}")
        return self.qpos[k].copy(), self.qvel[k].copy(), self.actions[k].copy()


def run_episode(env: gym.Env, policy: Policy, options: dict, max_frames: int | None = None,
                seed: int | None = None) -> Episode:
    """Reset ``env`` with ``options`` and run ``policy`` until the episode ends, or until at least
    ``max_frames`` frames are simulated (whole control steps, so up to one step more; ``0``: only
    the reset). ``seed`` is passed to ``env.reset``. Any ``frame_hook`` already installed on the
    environment keeps being called."""
    if max_frames is not None and max_frames < 0:
        raise ValueError(f"max_frames must be >= 0, got {max_frames}")
    base = env.unwrapped
    obs, info = env.reset(seed=seed, options=options)
    start = info["frame"]
    qpos, qvel, actions = [base.data.qpos.copy()], [base.data.qvel.copy()], [base.smoothed]
    outer_hook = base.frame_hook

    def record(data: mujoco.MjData) -> None:
        qpos.append(data.qpos.copy())
        qvel.append(data.qvel.copy())
        actions.append(base.smoothed)
        if outer_hook is not None:
            outer_hook(data)

    base.frame_hook = record
    rewards: list[float] = []
    ended_by = ""
    try:
        while max_frames is None or len(qpos) - 1 < max_frames:
            obs, reward, term, trunc, info = env.step(policy(obs))
            rewards.append(float(reward))
            if term or trunc:
                ended_by = info["ended_by"]
                break
    finally:
        base.frame_hook = outer_hook
    return Episode(clip=info["clip"], start_frame=start, qpos=np.array(qpos), qvel=np.array(qvel),
                   actions=np.array(actions), rewards=np.array(rewards), final_obs=np.array(obs), ended_by=ended_by,
                   episode_end=base.episode_end)


def sampling_policy(policy: MimicPolicy) -> Policy:
    """``policy``'s stochastic actions: its action distribution sampled (PPO's Gaussian exploration
    noise around the deterministic action, clipped to the action space), as in training; for a
    mirror-symmetric policy (:meth:`MimicPolicy.mirror_averaged`) the same noise around its
    symmetric action, which is already inside the action space (so near a limit it differs from
    SB3's, which adds the noise to the unclipped mean). Seed it with :func:`seeded` (torch's
    random numbers draw the noise)."""
    if policy.mirror is not None:
        std = policy.model.policy.log_std.detach().exp().numpy()
        space = policy.model.action_space

        def act_symmetric(obs: np.ndarray) -> np.ndarray:
            noise = std * torch.randn(len(std)).numpy()
            return np.clip(policy(obs) + noise, space.low, space.high)

        return act_symmetric

    def act(obs: np.ndarray) -> np.ndarray:
        action, _ = policy.model.predict(policy.normalizer.normalize_obs(obs), deterministic=False)
        return action

    return act


@contextmanager
def seeded(seed: int) -> Iterator[None]:
    """Within the block, torch's CPU random numbers (which SB3 samples actions with) come from
    ``seed``; the global random state is restored afterwards."""
    with torch.random.fork_rng(devices=[]):
        torch.manual_seed(seed)
        yield


@contextmanager
def torch_threads(n: int) -> Iterator[None]:
    """Within the block torch runs ``n`` intra-op threads; the previous number is restored after.
    A rollout runs the policy on one observation at a time, where more threads only wait on each
    other: beside a training run on 2 cores, one 2-thread ``tanh`` of 256 values took 7 ms."""
    before = torch.get_num_threads()
    torch.set_num_threads(n)
    try:
        yield
    finally:
        torch.set_num_threads(before)
