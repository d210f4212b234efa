"""ADAPT's evaluation protocol (adapt §3.2.6, §4.1) for any policy on a mimic environment.

A policy here is any function from an observation ``(D,)`` float32 to an action ``(A,)``
(:data:`agents.rollout.Policy`); episodes run through :func:`agents.rollout.run_episode`. Each
clip is evaluated as one ``episode_frames`` segment (or up to its end, for a clip shorter than
that), rolled out ``episodes`` times from start offsets ``0, offset_step, 2·offset_step, ...``
frames (at most the clip's last start frame); the metrics of :mod:`agents.metrics` are
averaged over all rollouts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import gymnasium as gym
import numpy as np

from agents.metrics import episode_length_ratio, max_reward_ratio, root_displacement_error, survived
from agents.mirror import MirrorAveraged, MirrorMaps
from agents.rollout import Policy, run_episode
from reference_motion.motion import Motion

if TYPE_CHECKING:
    from agents.policy import MimicPolicy

__all__ = ["Policy", "Rollout", "evaluate", "evaluate_tracking", "per_clip", "rollout", "summarize", "zero_policy"]


@dataclass(frozen=True)
class Rollout:
    """One evaluated episode.

    Attributes:
        clip: clip name; start_frame: its first reference frame.
        elr, sr90, rde, mrr: the four metrics of the rollout.
        ended_by: why it ended (see :class:`envs.mimic.MimicEnv`).
        simulated: the simulated motion, every 60 Hz frame from the start state on.
        reference: the reference frames it was judged against (same length and rate): those it
            mimicked, unless the environment judges against other ones
            (``MimicEnv.judging_track``: the clean take, or the take as given when it mimicked a
            denoised copy).
    """

    clip: str
    start_frame: int
    elr: float
    sr90: float
    rde: float
    mrr: float
    ended_by: str
    simulated: Motion
    reference: Motion


def zero_policy(action_size: int) -> Policy:
    """The policy that always outputs zero: the reference fed open loop to the PD controllers."""
    zero = np.zeros(action_size, dtype=np.float32)
    return lambda obs: zero


def rollout(env: gym.Env, policy: Policy, clip: int | str, start_frame: int, corrupted: bool = False) -> Rollout:
    """Run ``policy`` on ``env`` from ``start_frame`` of ``clip`` until the episode ends
    (:func:`agents.rollout.run_episode`), and score it."""
    episode = run_episode(env, policy, {"clip": clip, "start_frame": start_frame, "corrupted": corrupted})
    frames = episode.qpos
    ref = env.unwrapped.judging_track.motion
    reference = ref.with_qpos(ref.qpos[start_frame:start_frame + len(frames)], loop=False)
    simulated = reference.with_qpos(frames, source={**ref.source, "simulated_by": "policy"})
    total = episode.episode_end - start_frame
    steps = total // env.unwrapped.config.frames_per_control
    return Rollout(clip=episode.clip, start_frame=start_frame, elr=episode_length_ratio(episode.frames, total),
                   sr90=survived(episode.frames, total),
                   rde=root_displacement_error(frames[:, :3], reference.qpos[:, :3]),
                   mrr=max_reward_ratio(episode.rewards, steps, env.unwrapped.max_step_reward), ended_by=episode.ended_by, simulated=simulated,
                   reference=reference)


def evaluate(env: gym.Env, policy: Policy, clips: list[int | str] | None = None, episodes: int = 20,
             offset_step: int = 3, corrupted: bool = False) -> tuple[dict[str, float], list[Rollout]]:
    """ADAPT's protocol over ``clips`` (default: all of ``env``'s clips).

    Returns ``(summary, rollouts)``; the summary has ``ELR_mean``, ``ELR_std``, ``SR90``,
    ``RDE_mean``, ``RDE_std``, ``MRR_mean``, ``MRR_std`` and ``rollouts``.
    """
    base = env.unwrapped
    clips = list(range(len(base.clips))) if clips is None else clips
    runs = [rollout(env, policy, clip, min(k * offset_step, base.last_start(clip)), corrupted)
            for clip in clips for k in range(episodes)]
    return summarize(runs), runs


def evaluate_tracking(policy: MimicPolicy, tracked: list[Motion], judged: list[Motion] | None = None,
                      episodes: int = 20, offset_step: int = 3, actor: Policy | None = None,
                      mirror_average: bool = False, prepare_env: Callable[[gym.Env], None] | None = None
                      ) -> tuple[dict[str, float], list[Rollout]]:
    """:func:`evaluate` of ``policy`` in the environment it was trained in, tracking the clips
    ``tracked`` (no artefacts added) and judged, rewarded and terminated, against ``judged`` (the
    same clips in the same order, e.g. the IMU takes as given, which a denoiser cleaned; default:
    ``tracked``). ``actor`` acts instead of ``policy`` in that environment (e.g. an ensemble with
    ``policy`` among its members); default: ``policy``. ``mirror_average``: that actor made mirror
    symmetric (:class:`agents.mirror.MirrorAveraged`). ``prepare_env`` is called on the environment
    before its first reset (e.g. to change its MuJoCo model for a probe; that model may be the one
    every environment of the humanoid shares, :func:`reference_motion.humanoid.model.load_model`, so
    the caller undoes such a change afterwards)."""
    env = policy.make_env(tracked, artefacts=None, judged_clips=judged)
    if prepare_env is not None:
        prepare_env(env)
    env.reset(seed=0)
    actor = policy if actor is None else actor
    if mirror_average:
        actor = MirrorAveraged(actor, MirrorMaps.of(env))
    return evaluate(env, actor, episodes=episodes, offset_step=offset_step)


def summarize(runs: list[Rollout]) -> dict[str, float]:
    """ADAPT's summary of ``runs``: ``ELR_mean``, ``ELR_std``, ``SR90``, ``RDE_mean``, ``RDE_std``,
    ``MRR_mean``, ``MRR_std`` and ``rollouts``."""
    summary: dict[str, float] = {"rollouts": len(runs), "SR90": float(np.mean([r.sr90 for r in runs]))}
    for name, key in (("ELR", "elr"), ("RDE", "rde"), ("MRR", "mrr")):
        values = np.array([getattr(r, key) for r in runs])
        summary[f"{name}_mean"], summary[f"{name}_std"] = float(values.mean()), float(values.std())
    return summary


def per_clip(runs: list[Rollout]) -> list[dict]:
    """Mean ELR and SR90 of each clip's rollouts, worst ELR first: ``[{"clip", "rollouts", "ELR",
    "SR90"}, ...]`` (clips in the order of first appearance break ties)."""
    by_clip: dict[str, list[Rollout]] = {}
    for r in runs:
        by_clip.setdefault(r.clip, []).append(r)
    rows = [{"clip": clip, "rollouts": len(rs), "ELR": float(np.mean([r.elr for r in rs])),
             "SR90": float(np.mean([r.sr90 for r in rs]))} for clip, rs in by_clip.items()]
    return sorted(rows, key=lambda row: row["ELR"])
