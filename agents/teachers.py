"""How a teacher policy reads a student's observation and answers it: which teachers fit a student's
environment (:func:`check_teacher_layouts`) and their mean actions and values on raw observations
(:func:`mean_actions_and_values`, :func:`mean_actions`). ``agents/distill.py`` (DAgger) and ``agents/kickstart.py``
(kickstarting PPO) label states with them."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch

from agents.policy import MimicPolicy, PolicyError
from agents.warm_start import window_slice

ANSWER_CHUNK = 16_384
"""Observations a policy answers at a time in :func:`mean_actions_and_values` (a chunk of raw
float32 observations with a ±16-step reference window, ~900 values, is ~60 MB; normalised, and
mirrored for a symmetric actor, a few times that at once)."""


def check_teacher_layouts(teachers: list[MimicPolicy], env: gym.Env) -> None:
    """Raise :class:`PolicyError` unless every teacher of ``teachers`` acts with ``env``'s actions and observes either
    the part of its observation before the student's reference window, with no window of its own, or
    (a teacher whose window is the student's, as a default teacher's is for its own student) the whole
    observation (``agents.distill.teacher_observation`` gives a teacher the first values): a teacher with another
    window would read the student's as if it were its own."""
    window = window_slice(env.unwrapped.obs_slices)
    whole = env.observation_space.shape[0]
    before = whole if window is None else window.start
    steps = env.unwrapped.config.window_steps
    for teacher in teachers:
        inputs, own_steps = teacher.model.observation_space.shape[0], teacher.record.env.mimic_config().window_steps
        if not ((inputs == before and not own_steps) or (inputs == whole and own_steps == steps)):
            either = ("" if window is None
                      else f" or, with the student's window {list(steps)}, all of it ({whole} values)")
            raise PolicyError(f"{teacher.name}: observes {inputs} values with reference window {list(own_steps)}; a "
                              f"teacher reads the student's observation before its reference window, with no window "
                              f"of its own ({before} values){either}")
        if teacher.model.action_space.shape != env.action_space.shape:
            raise PolicyError(f"{teacher.name}: acts with {teacher.model.action_space.shape[0]} values; the student's "
                              f"environment takes {env.action_space.shape[0]}")


def mean_actions_and_values(policy: MimicPolicy, obs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(N, A)`` mean actions (rad offsets) and ``(N,)`` values of ``policy`` for raw observations
    ``obs (N, D)`` (normalised by the policy's own statistics). A policy acting as its symmetric actor
    (:attr:`MimicPolicy.mirror`) answers with that actor's action (:mod:`agents.mirror`) and the mean
    of its values on the observation and its mirror image."""
    actions, values = _answers(policy, obs, with_values=True)
    return actions, values


def mean_actions(policy: MimicPolicy, obs: np.ndarray) -> np.ndarray:
    """The ``(N, A)`` mean actions of :func:`mean_actions_and_values`, without the critic's pass."""
    return _answers(policy, obs, with_values=False)[0]


def _answers(policy: MimicPolicy, obs: np.ndarray, with_values: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """:func:`mean_actions_and_values`, the values ``None`` unless ``with_values``."""
    def network(raw: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        x = torch.as_tensor(policy.normalizer.normalize_obs(raw), dtype=torch.float32)
        with torch.no_grad():
            return (policy.model.policy.get_distribution(x).distribution.mean.numpy(),
                    policy.model.policy.predict_values(x)[:, 0].numpy() if with_values else None)

    def answer(raw: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        mean, value = network(raw)
        if policy.mirror is None:
            return mean, value
        mean_mirrored, value_mirrored = network(policy.mirror.observation(raw))
        return (policy.mirror.averaged(mean, mean_mirrored),
                0.5 * (value + value_mirrored) if with_values else None)

    # a chunk at a time: a normalised (float64) and a mirrored copy of millions of labels would be several times theirs
    answers = [answer(obs[start:start + ANSWER_CHUNK]) for start in range(0, max(len(obs), 1), ANSWER_CHUNK)]
    return (np.concatenate([a for a, _ in answers]),
            np.concatenate([v for _, v in answers]) if with_values else None)


def observing_in(teacher: MimicPolicy, frame: str, whose: str) -> MimicPolicy:
    """``teacher`` observing in ``frame``, the frame of ``whose`` observation it reads (a note says so when
    it was trained in another frame of the same layout, :meth:`MimicPolicy.observing`; another layout
    raises :class:`PolicyError`)."""
    if teacher.record.env.mimic_config().obs_frame == frame:
        return teacher
    print(f"note: teacher {teacher.name} observes in the {frame!r} frame of {whose} here (MimicPolicy.observing)")
    return teacher.observing(frame)
