"""Episodes that start from the states a policy reaches when it performs a clip whole.

PPO adapts a policy to a clip (:mod:`agents.adaptation`) on episodes that start from the
reference's states, but :mod:`agents.clean` performs the clip in one continuous simulation: by the
time the character fails there, it has drifted from the reference in ways no reference start
shows it (a clip whose evaluations from reference states pass can still re-anchor when performed
whole). Starting a share of the training episodes from the performance's own simulated states in
the second before each place it failed trains the policy where it actually gets into trouble (the
idea of DAgger: train on the states the policy visits).

:func:`performed_start_frames` picks the frames (a pure function of the failures' frames);
:class:`PerformedStarts` wraps an environment so that its resets start from them.
"""

from __future__ import annotations

from typing import Sequence

import gymnasium as gym
import numpy as np


def performed_start_frames(failures: Sequence[int], anchors: Sequence[int], n_frames: int, window: int,
                           latest: int) -> np.ndarray:
    """The frames of a performance whose simulated states episodes start from.

    Args:
        failures: frames where the performance failed (each re-anchor's longest attempt's end,
            each recovered failure's frame).
        anchors: frames restarted from the reference state (their states are reference states,
            which the environment's own resets already start from).
        n_frames: frames of the clip.
        window: frames before each failure to start from (``window`` frames, ending one before it).
        latest: the last frame an episode may start at (one control step before the clip's end).

    Returns:
        ``(K,)`` sorted distinct frames in ``0..latest``: the ``window`` frames before each
        failure; every frame but the anchors when there is no failure (the policy's own
        state distribution over the clip).
    """
    if window < 1:
        raise ValueError(f"window must be at least one frame, got {window}")
    if failures:
        frames = np.unique(np.concatenate([np.arange(f - window, f) for f in failures]))
    else:
        frames = np.arange(n_frames)
    frames = frames[(frames >= 0) & (frames <= min(latest, n_frames - 1))]
    return np.setdiff1d(frames, np.asarray(anchors, dtype=int))


class PerformedStarts(gym.Wrapper):
    """Starts a share of the wrapped mimic environment's episodes from given simulated states.

    A :meth:`reset` without options starts, with probability ``fraction``, from one of the states
    last given to :meth:`set_states` (uniformly drawn; the ``state`` reset option of
    :class:`envs.mimic.MimicEnv`), else as the environment would. Resets with options are passed on
    unchanged. The draw is seeded by the seed of the first seeded reset.

    Args:
        env: a mimic environment of one clip.
        fraction: share of resets that start from a given state (0 < fraction ≤ 1).
    """

    def __init__(self, env: gym.Env, fraction: float):
        super().__init__(env)
        if not 0 < fraction <= 1:
            raise ValueError(f"fraction must be in (0, 1], got {fraction}")
        self.fraction = fraction
        self._rng = np.random.default_rng(0)
        self._frames = np.zeros(0, dtype=int)
        self._qpos = self._qvel = np.zeros((0, 0))

    def set_states(self, frames: np.ndarray, qpos: np.ndarray, qvel: np.ndarray) -> None:
        """The states to start from: ``frames (K,)`` reference frames, ``qpos (K, nq)``, ``qvel
        (K, nv)`` (K = 0: none, every episode starts as the environment would)."""
        frames = np.asarray(frames, dtype=int)
        if not (len(frames) == len(qpos) == len(qvel)) or not (np.isfinite(qpos).all() and np.isfinite(qvel).all()):
            raise ValueError(f"set_states needs as many finite qpos and qvel rows as frames; got {len(frames)} frames, "
                             f"qpos {np.shape(qpos)}, qvel {np.shape(qvel)}")
        self._frames, self._qpos, self._qvel = frames, np.array(qpos, dtype=float), np.array(qvel, dtype=float)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        if not options and len(self._frames) and self._rng.random() < self.fraction:
            i = int(self._rng.integers(len(self._frames)))
            options = {"start_frame": int(self._frames[i]), "state": (self._qpos[i].copy(), self._qvel[i].copy())}
        return self.env.reset(seed=seed, options=options)
