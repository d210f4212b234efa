"""Distil a policy set (or one policy) into one network by DAgger, then fine-tune it with PPO.

Usage::

    python agents/distill.py --teacher models/mimic_set --clips library:data/library/train \\
        deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 \\
        --mirror --corrupted-fraction 0.5 --net 256,256 --out runs/distill_256
    python agents/distill.py --out runs/distill_256 --resume          # after an interruption
    python agents/train_ppo.py ... --init-from runs/distill_256/student  # PPO from the student

Why: the generalist (``models/mimic_general``) walks forwards and has not learned to walk
backwards in 28 M steps, while a specialist learned the backward walks it can carry
(``models/mimic_walk_back``); ``models/mimic_set`` routes between the two. Whether one network of a
given size can hold both is a supervised question, answered here without RL's trust region: the
student is fitted to the teachers' actions on the states it visits itself (DAgger, Ross et al.
2011), every hidden unit from a fresh initialisation, or (``--from-default``) from the set's default
policy, so that a specialist's takes (a policy set's ``clips`` routes) are taught to a policy that
already performs the rest.

Round 0 collects ``steps_per_round`` control steps with the teachers acting (each episode's clip
routed as the set routes it, :mod:`agents.policy_set`), later rounds with the student acting; both
add their Gaussian exploration noise (σ² of the teachers, ADAPT's 0.03), so the states cover what
PPO will visit. Every state is labelled with its teacher's mean action and value. After each round
the student (an SB3 ``MlpPolicy`` of ``net``, actor and critic, as ``train_ppo.py`` builds them)
is fitted to every label so far by minibatch Adam on

    L = Σ_i w_i (||μ_s(x_i) − μ_t(x_i)||² / (A σ²) + (V_s(x_i) − V_t(x_i))² / var(V_t)) / Σ_i w_i

(an action error of one exploration σ per dimension costs 1, as does a value error of one standard
deviation of the teachers' values; ``w_i`` is the weight of state i's teacher, 1 unless
``--teacher-weight`` says otherwise, so the logged loss is comparable only between runs of the same
weights). The student keeps the set's default policy's observation
statistics, frozen; each teacher reads its own. A tenth of the states (whole episodes) is held
out; its action RMSE per motion class (the clip's teacher) is what the log reports.

A privileged teacher (``--teacher-reads clean``): in a corrupted episode the teacher reads the clean
take the corruption was made from, at the state the episode is in, while the student reads the
corrupted take as evaluation prepares it (``--denoise [--denoise-slow] --even-legs --part-legs --ground
--swing-lift``, each optional). The student learns
to act on a corrupted take as its teacher acts on the clean one; where the take cannot show an
artefact (the stance skate, README "Round 14"), the least-squares fit is the teacher's mean over
what it could hide. With ``--mirror-average`` the labels are the teachers' symmetric actors' and
every state is also fitted mirrored, for a student evaluated as its own symmetric actor; a teacher
named in ``--plain-teachers`` labels as its plain actor (a policy set that routes one side of a take
to a policy that performs it and the other side to that policy's mirror image, README "Round 19").

A teacher behind the denoiser (``--teacher-reads denoised --denoise DIR``): in a corrupted episode the
teacher reads the same corrupted variant after the IMU denoiser (and the student's other preparation),
while the student reads it as the suit gives it, with a window of the take around now
(``--lookahead``, ``--lookbehind``): the student learns to act on the raw take as its teacher does
behind the denoiser, as far as its window shows what the denoiser sees (README "Round 20").

``OUT`` holds ``student/`` (a policy directory: ``model.zip``, ``model_vecnormalize.pkl``,
``sidecar.json`` with the distillation's record), ``data.npz`` (the labelled states) and
``log.jsonl`` (one line per round), each written whole after every round: ``--resume`` continues
after the last round the student's sidecar records (:func:`finished_rounds`), losing at most one
round.
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from pathlib import Path

if __package__ in (None, ""):  # `python agents/distill.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv
from tqdm import tqdm

import envs  # noqa: F401  (registers the ids)
from agents.mirror import MirrorMaps
from agents.policy import (MODEL_FILE, SIDECAR_FILE, MimicPolicy, PolicyError, load_policy, policy_files,
                           save_loaded_policy, with_statistics)
from agents.policy_set import is_policy_set, load_policy_set, route_clips
from agents.sidecar import EnvSpec, PolicySidecar, PPOSettings, TrainingRecord, repository_relative
from agents.teachers import ANSWER_CHUNK, check_teacher_layouts, mean_actions, mean_actions_and_values, observing_in
from agents.train_ppo import (glob_speeds, load_training_motions, policy_kwargs, posture_range, posture_ranges,
                              reposed_copies, stance_extra, warped_clips)
from agents.warm_start import widen_by_window, widen_hidden
from envs import ArtefactMix
from envs.config import FOOT_MODELS
from envs.preparation import no_preparation, preparation_of, preparation_record
from perception.imu_denoiser import add_denoise_option, add_slow_corrections_option, check_slowing
from reference_motion.artefacts import ArtefactRecipe
from reference_motion.atomic import atomic_write, write_json
from reference_motion.cli import (CliParser, fraction, non_negative_float, non_negative_int, one_line_errors, output_dir,
                                  positive_float, positive_int, resumable_run)
from reference_motion.grounding import add_grounding_option
from reference_motion.leg_gap import add_leg_gap_option
from reference_motion.leg_symmetry import add_leg_symmetry_option
from reference_motion.library import STANCE_EXTRA_M, expand_clips
from reference_motion.motion import Motion
from reference_motion.swing_lift import add_swing_lift_options


STUDENT_WINDOW_RESETS = 1024
"""Resets of the student's one environment whose observations give its reference window's inputs
their statistics (frozen, as the rest of the student's are: ~1,000 start states over the clips)."""

TEACHER_READS = ("track", "clean", "denoised")
"""What a corrupted episode's teacher observes (``--teacher-reads``, :func:`teacher_observation`)."""


@dataclass(frozen=True)
class DistillConfig:
    """How a student is distilled.

    Attributes:
        net: the student's hidden layer sizes, actor and critic ("256,256").
        rounds: DAgger rounds; round 0 is acted by the teachers, the rest by the student (4).
        steps_per_round: control steps collected per round (50 000; ~1 min on one core).
        epochs: passes over every label so far after each round (5).
        batch_size: minibatch size (512).
        lr: Adam learning rate (3e-4).
        holdout: share of the episodes held out to report the fit (0.1).
        seed: seed of the environment, the noise, the initialisation and the minibatches (0).
        teacher_weights: loss weight of each teacher's states, ``(name, weight)`` pairs by the
            teacher's directory name (e.g. ``(("mimic_walk_back", 4.0),)``); a teacher not named
            weighs 1. It separates what a student of some size can hold from how much of the data a
            motion class is.
        from_default: the student starts as the set's default policy (its weights; ``net`` must be
            the default's hidden layers or wider ones) instead of a fresh initialisation, so that specialists' takes can be
            distilled into a policy that already performs the rest (False).
        lookahead, lookbehind: control steps ahead and back whose reference the student also
            observes (:attr:`envs.config.MimicConfig.lookahead`, ``lookbehind``: a window of the
            take, after the default teacher's observation, which the teachers read without it);
            empty (default): the student observes what the default teacher does.
    """

    net: str = "256,256"
    rounds: int = 4
    steps_per_round: int = 50_000
    epochs: int = 5
    batch_size: int = 512
    lr: float = 3e-4
    holdout: float = 0.1
    seed: int = 0
    teacher_weights: tuple[tuple[str, float], ...] = ()
    from_default: bool = False
    lookahead: tuple[int, ...] = ()
    lookbehind: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        if not all(n.strip().isdigit() and int(n) > 0 for n in self.net.split(",")):
            raise ValueError(f"net must be positive layer sizes like '256,256', got {self.net!r}")
        for name in ("rounds", "steps_per_round", "epochs", "batch_size"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)}")
        if not 0 <= self.holdout < 1:
            raise ValueError(f"holdout must be in [0, 1), got {self.holdout}")
        seen = [name for name, _ in self.teacher_weights]
        if len(set(seen)) != len(seen):
            raise ValueError(f"teacher_weights names a teacher twice: {seen}")
        for name, weight in self.teacher_weights:
            if not (isinstance(weight, (int, float)) and math.isfinite(weight) and weight > 0):
                raise ValueError(f"teacher_weights[{name!r}] must be a finite number > 0, got {weight!r}")

    def weights_of(self, names: list[str]) -> np.ndarray:
        """``(T,)`` loss weight of each of the teachers ``names`` (in that order); raises on a weight
        for a teacher not among them (a misspelt name would silently weigh nothing)."""
        given = dict(self.teacher_weights)
        unknown = sorted(set(given) - set(names))
        if unknown:
            raise ValueError(f"teacher_weights (--teacher-weight) names {unknown}, which are not teachers; "
                             f"expected some of {names}")
        return np.array([given.get(n, 1.0) for n in names], dtype=np.float32)


@dataclass
class Labels:
    """Labelled states, one row per control step.

    Attributes:
        obs: ``(N, D)`` float32 raw observations (not normalised).
        actions: ``(N, A)`` float32 the teacher's mean action (rad offsets).
        values: ``(N,)`` float32 the teacher's value of the state.
        teacher: ``(N,)`` int index of the state's teacher (order of :func:`teachers_by_clip`'s list).
        episode: ``(N,)`` int episode number (unique over rounds; the holdout splits by it).
    """

    obs: np.ndarray
    actions: np.ndarray
    values: np.ndarray
    teacher: np.ndarray
    episode: np.ndarray

    def __len__(self) -> int:
        return len(self.obs)

    def __add__(self, other: Labels) -> Labels:
        return Labels(*(np.concatenate([a, b]) for a, b in zip(self.fields(), other.fields())))

    def fields(self) -> tuple[np.ndarray, ...]:
        return self.obs, self.actions, self.values, self.teacher, self.episode

    def take(self, rows: np.ndarray | slice) -> Labels:
        """The labelled states ``rows`` (a boolean mask, indices or a slice)."""
        return Labels(*(f[rows] for f in self.fields()))

    def save(self, path: Path) -> None:
        with atomic_write(path) as tmp:
            with open(tmp, "wb") as f:
                np.savez(f, **dict(zip(("obs", "actions", "values", "teacher", "episode"), self.fields())))

    @classmethod
    def load(cls, path: Path) -> Labels:
        with np.load(path) as data:
            return cls(data["obs"], data["actions"], data["values"], data["teacher"], data["episode"])


@dataclass(frozen=True)
class Teachers:
    """The policies a student learns from.

    Attributes:
        policies: one policy, or the policies of a policy set that perform some clip.
        of_clip: per clip name, the index in ``policies`` of the policy that performs it.
        default: index of the policy whose observation statistics and task the student takes (a
            set's ``default`` policy).
        motions: the clips, grouped by teacher.
    """

    policies: list[MimicPolicy]
    of_clip: dict[str, int]
    default: int
    motions: list[Motion]

    @property
    def names(self) -> list[str]:
        """Each teacher's :attr:`~agents.policy.MimicPolicy.short_name` (a run's checkpoint as ``RUN/step_N``)."""
        return [p.short_name for p in self.policies]


def check_teacher_set(teacher: str | Path, denoise: str | Path | None) -> None:
    """:class:`PolicyError` when ``teacher`` is a policy set that slows some members' denoiser corrections its own
    way (:attr:`agents.policy_set.PolicySet.denoise_slow_s`) and the episodes pass through a denoiser
    (``denoise``): they are prepared one way for every teacher. Without a denoiser the slowing changes nothing."""
    if denoise and is_policy_set(teacher) and load_policy_set(teacher).denoise_slow_s:
        raise PolicyError(f"{teacher}: the set slows some members' denoiser corrections its own way (denoise_slow_s), "
                          "but the student's episodes are prepared one way for every teacher; give a set without it "
                          "or no --denoise")


def load_teachers(teacher: str | Path, load: Callable[[str], list[Motion]]) -> Teachers:
    """The teachers in ``teacher`` (a policy or a policy-set directory) and the clips ``load(foot)``
    returns (``foot``: the teachers' foot model), each routed to its teacher as the set routes it.
    The student's environment observes as the default policy does, so a teacher trained in another
    frame of the same layout observes in that one (:meth:`MimicPolicy.observing`; another layout
    raises :class:`PolicyError`)."""
    groups = route_clips(teacher, load)
    policies = [policy for policy, _ in groups]
    default_dir = load_policy_set(teacher).default if is_policy_set(teacher) else Path(teacher)
    default_file = policy_files(default_dir)[1].resolve()
    default = next((i for i, p in enumerate(policies) if p.model_file.resolve() == default_file), None)
    if default is None:
        raise PolicyError(f"{teacher}: no clip is routed to its default policy {default_dir}, whose observation "
                          f"statistics the student takes; add clips it performs")
    frame = policies[default].record.env.mimic_config().obs_frame
    # one env observes for all: each teacher reads it in its frame
    policies = [observing_in(policy, frame, f"the default policy {policies[default].name}") for policy in policies]
    of_clip: dict[str, int] = {}
    for i, (_, clips) in enumerate(groups):
        for m in clips:
            if of_clip.setdefault(m.name, i) != i:  # episodes are routed by their clip's name
                raise ValueError(f"two clips named {m.name!r} go to different teachers; give them distinct names")
    return Teachers(policies, of_clip, default, [m for _, clips in groups for m in clips])


def symmetric_teacher(teacher: MimicPolicy, maps: MirrorMaps) -> MimicPolicy:
    """``teacher`` acting as its symmetric actor in the student's env (whose mirror maps are
    ``maps``), where it reads the first values of that env's observation (:func:`teacher_observation`):
    the maps of those (:meth:`agents.mirror.MirrorMaps.leading`; :func:`check_teacher_layouts` has
    checked that the teacher fits the env)."""
    inputs = teacher.model.observation_space.shape[0]
    return teacher if teacher.symmetric_network else replace(teacher, mirror=maps.leading(inputs))


def teacher_observation(env: gym.Env, obs: np.ndarray, info: dict, reads: str,
                        inputs: int | None = None, teacher_env: gym.Env | None = None) -> np.ndarray:
    """What an episode's teacher observes ``(inputs,)`` where the student observes ``obs (D,)``: the
    same (``reads="track"``), or in a corrupted episode, at the same state and frame
    (:meth:`envs.mimic.MimicEnv.observation_against`), the clean take as a clean episode tracks it
    (``reads="clean"``: the privileged teacher) or the same corrupted variant as ``teacher_env``
    prepares it (``reads="denoised"``: an env of the same clips and artefact seed whose references
    pass through the IMU denoiser, while the student reads the take as the suit gives it); its first
    ``inputs`` values (a student that also observes a reference window has ``D > inputs``; ``None``:
    all of them)."""
    if reads == "track" or not info["corrupted"]:
        return obs[:inputs]
    base = env.unwrapped
    if reads == "clean":
        track = base.track(base.clip_index, -1)
    elif teacher_env is None:
        raise ValueError(f"teacher_observation: reads={reads!r} needs the teacher's env (teacher_env)")
    else:
        track = teacher_env.unwrapped.track(base.clip_index, base.variant_index)
    return base.observation_against(track).astype(obs.dtype)[:inputs]


def collect(env: gym.Env, actor: MimicPolicy | None, teachers: Teachers, steps: int, sigma: float,
            rng: np.random.Generator, first_episode: int, progress: bool = True, teacher_reads: str = "track",
            maps: MirrorMaps | None = None, teacher_env: gym.Env | None = None) -> Labels:
    """``steps`` control steps on ``env``, acted by ``actor`` (``None``: each episode's teacher, on
    what it observes), mean action plus Gaussian noise of std ``sigma`` (rad), labelled by each
    episode's teacher from what it observes (:func:`teacher_observation` with ``teacher_reads``).
    With ``maps`` (:class:`agents.mirror.MirrorMaps` of ``env``) every state is also labelled
    mirrored: its mirror image, with the mirrored label (the teachers then act as their symmetric
    actors, whose labels mirror exactly), in the same episode; with ``teacher_reads="denoised"`` only
    as exactly as the denoiser commutes with the mirror. ``teacher_env``: the teachers' env for
    ``teacher_reads="denoised"`` (:func:`teacher_observation`)."""
    obs_rows, teacher_rows, who, episode_of = [], [], [], []
    episode = first_episode
    obs, info = env.reset(seed=int(rng.integers(2**31)))
    for _ in tqdm(range(steps), desc="collecting", unit="step", disable=not progress, leave=False):
        teacher = teachers.of_clip[info["clip"]]
        seen = teacher_observation(env, obs, info, teacher_reads,
                                   teachers.policies[teacher].model.observation_space.shape[0], teacher_env)
        mean = (mean_actions(actor, obs[None]) if actor is not None
                else mean_actions(teachers.policies[teacher], seen[None]))
        obs_rows.append(obs)
        teacher_rows.append(seen)
        who.append(teacher)
        episode_of.append(episode)
        obs, _, terminated, truncated, info = env.step(mean[0] + sigma * rng.standard_normal(mean.shape[1]))
        if terminated or truncated:
            episode += 1
            obs, info = env.reset()
    obs_all, who_all = np.asarray(obs_rows, np.float32), np.asarray(who)
    actions = np.zeros((len(obs_all), env.action_space.shape[0]), np.float32)
    values = np.zeros(len(obs_all), np.float32)
    for i, teacher in enumerate(teachers.policies):  # teachers may read different lengths (check_teacher_layouts)
        rows = np.flatnonzero(who_all == i)
        if len(rows):
            seen = np.asarray([teacher_rows[row] for row in rows], np.float32)
            actions[rows], values[rows] = mean_actions_and_values(teacher, seen)
    labels = Labels(obs_all, actions, values, who_all, np.asarray(episode_of))
    if maps is None:
        return labels
    return labels + Labels(maps.observation(obs_all), maps.action(actions), values, who_all, labels.episode)


def fit(student: MimicPolicy, labels: Labels, config: DistillConfig, sigma: float, rng: np.random.Generator,
        progress: bool = True, teacher_names: list[str] | None = None, rows: np.ndarray | None = None) -> float:
    """``config.epochs`` passes of minibatch Adam on the module docstring's loss over ``labels``,
    each state's term weighted by its teacher's ``config.teacher_weights`` (``teacher_names``: the
    names of ``labels.teacher``'s indices, needed when weights are given); a minibatch's loss is its
    weighted mean. ``rows``: ``(M,)`` int indices of the states to fit (:func:`label_rows`; ``None``:
    all): the minibatches, var(V_t) and ``rng``'s draws are those of a fit on ``labels.take(rows)``,
    without that copy. Returns the last epoch's weighted mean loss."""
    if config.teacher_weights and teacher_names is None:
        raise ValueError("fit: config.teacher_weights are given, so teacher_names must name labels.teacher's teachers")
    weights = config.weights_of(teacher_names) if teacher_names is not None else None
    policy = student.model.policy
    params = [p for name, p in policy.named_parameters() if name != "log_std"]
    optimizer = torch.optim.Adam(params, lr=config.lr)
    a_all, v_all = torch.as_tensor(labels.actions), torch.as_tensor(labels.values)
    w_all = torch.ones(len(labels)) if weights is None else torch.as_tensor(weights)[labels.teacher]
    rows = label_rows(labels, rows)
    value_var = max(float(v_all[rows].var()), 1e-6)
    n_actions = a_all.shape[1]
    loss_mean = float("nan")
    for _ in tqdm(range(config.epochs), desc="fitting", unit="epoch", disable=not progress, leave=False):
        total, weight_total = 0.0, 0.0
        for batch in np.array_split(rows[rng.permutation(len(rows))], max(1, len(rows) // config.batch_size)):
            # normalised a minibatch at a time: a normalised copy of every label would double the memory
            x = torch.as_tensor(student.normalizer.normalize_obs(labels.obs[batch]), dtype=torch.float32)
            a, v, w = a_all[batch], v_all[batch], w_all[batch]
            mean = policy.get_distribution(x).distribution.mean
            value = policy.predict_values(x)[:, 0]
            per_state = ((mean - a) ** 2).sum(1) / (n_actions * sigma**2) + (value - v) ** 2 / value_var
            loss = (w * per_state).sum() / w.sum()
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            total += float(loss.detach()) * float(w.sum())
            weight_total += float(w.sum())
        loss_mean = total / weight_total
    return loss_mean


def center_values(student: MimicPolicy, labels: Labels, rows: np.ndarray | None = None) -> None:
    """Shift the student's value output by the mean gap to the teachers' values on ``labels``'s
    ``rows`` (``(M,)`` int indices, :func:`label_rows`; ``None``: all): a fresh critic outputs ~0
    where the teachers' values are ~10² (returns of ~1-3 per step at γ 0.99), a gap minibatch Adam
    would close at only ~``lr`` per step."""
    rows = label_rows(labels, rows)
    gaps = [labels.values[chunk] - mean_actions_and_values(student, labels.obs[chunk])[1]
            for chunk in (rows[start:start + ANSWER_CHUNK] for start in range(0, len(rows), ANSWER_CHUNK))]
    if not gaps:
        raise ValueError("center_values: no labelled state to centre the values on")
    with torch.no_grad():
        student.model.policy.value_net.bias += float(np.mean(np.concatenate(gaps)))


def rmse_text(rmse: float | None) -> str:
    """A teacher's held-out action RMSE for the log line: ``0.000`` is a fit, ``-`` no held-out state."""
    return "-" if rmse is None else f"{rmse:.3f}"


def fit_report(student: MimicPolicy, labels: Labels, names: list[str]) -> dict:
    """Action RMSE (rad) per teacher and overall, and the value R², of ``student`` on ``labels``."""
    actions, values = mean_actions_and_values(student, labels.obs)
    error = (actions - labels.actions) ** 2
    report = {"action_rmse": float(np.sqrt(error.mean())),
              "value_r2": float(1 - ((values - labels.values) ** 2).mean() / max(labels.values.var(), 1e-12))}
    for i, name in enumerate(names):
        rows = labels.teacher == i
        report[f"action_rmse_{name}"] = float(np.sqrt(error[rows].mean())) if rows.any() else None
    return report


def label_rows(labels: Labels, rows: np.ndarray | None) -> np.ndarray:
    """``rows`` as ``(M,)`` int indices into ``labels`` (``None``: all of them); a clear
    ``ValueError`` for a boolean mask (give ``np.flatnonzero(mask)``) or an index out of range."""
    if rows is None:
        return np.arange(len(labels))
    rows = np.asarray(rows)
    if not np.issubdtype(rows.dtype, np.integer) or rows.ndim != 1:
        raise ValueError(f"rows: expected (M,) int indices into the labels, got {rows.dtype} of shape {rows.shape}"
                         + ("; give np.flatnonzero(mask)" if rows.dtype == bool else ""))
    if len(rows) and (rows.min() < 0 or rows.max() >= len(labels)):
        raise ValueError(f"rows: indices must lie in [0, {len(labels)}), got {rows.min()}..{rows.max()}")
    return rows


def split_holdout(labels: Labels, share: float, seed: int) -> tuple[np.ndarray, Labels]:
    """``(train_rows, held_out)``: the ``(M,)`` int indices of the training states (to fit in place,
    :func:`fit`'s ``rows``, rather than copy most of the labels) and a copy of the held-out states.
    Whole episodes are held out, about ``share`` of them (the same ones whatever the round: one draw
    per episode number from a generator seeded by ``seed``)."""
    held = (np.random.default_rng([seed, 7]).random(labels.episode.max() + 1) < share)[labels.episode]
    return np.flatnonzero(~held), labels.take(held)


def student_task(default: MimicPolicy, config: DistillConfig) -> EnvSpec:
    """The student's task: the default teacher's, with ``config``'s reference window added to its
    observation. :class:`PolicyError` for a default teacher that observes a window already."""
    task = default.record.env
    if not (config.lookahead or config.lookbehind):
        return task
    if task.mimic_config().window_steps:
        raise PolicyError(f"{default.name}: observes a reference window already; a student's window (--lookahead, "
                          f"--lookbehind) is added to a teacher's observation without one")
    widened = replace(task, config={**task.config, "lookahead": list(config.lookahead),
                                    "lookbehind": list(config.lookbehind)})
    widened.mimic_config()  # raises for steps the config refuses
    return widened


def student_action_variance(default: MimicPolicy, config: DistillConfig) -> float:
    """The exploration variance a student starts with and its sidecar records: the default teacher's, the mean over
    its action dimensions (rad²). Raises :class:`PolicyError` where ``config.from_default`` asks for the weights of a
    default trained as the symmetric actor (a student is a plain network)."""
    if config.from_default and default.symmetric_network:
        raise PolicyError(f"{default.name}: a network trained as the symmetric actor; a student is a plain network, "
                          "so it cannot start from this default teacher's weights")
    return float(default.model.policy.log_std.detach().exp().pow(2).mean())


def new_student(env: gym.Env, default: MimicPolicy, config: DistillConfig) -> MimicPolicy:
    """A student on ``env`` with the default teacher's observation statistics and exploration noise:
    freshly initialised, or with the default teacher's weights (``config.from_default``), embedded
    in wider hidden layers where ``config.net`` is wider (:func:`agents.warm_start.widen_hidden`: it
    acts as the default from the start; raises :class:`PolicyError` for a narrower or deeper ``net``).
    Where ``env`` also shows a reference window (:func:`student_task`), its inputs get zero weights
    and statistics sampled from :data:`STUDENT_WINDOW_RESETS` resets of ``env``
    (:func:`agents.warm_start.widen_by_window`)."""
    variance = student_action_variance(default, config)
    model = PPO("MlpPolicy", DummyVecEnv([lambda: env]), seed=config.seed, device="cpu", verbose=0,
                policy_kwargs=policy_kwargs(config.net, variance))
    weights, normalizer = default.model.policy.state_dict(), default.normalizer
    if env.observation_space.shape != default.model.observation_space.shape:
        stats = normalizer.obs_rms
        weights, mean, var = widen_by_window(weights, stats.mean, stats.var, model.get_env(), STUDENT_WINDOW_RESETS)
        normalizer = with_statistics(normalizer, mean, var)
    if config.from_default:
        try:
            weights = widen_hidden(weights, model.policy.state_dict())
        except PolicyError as err:
            raise PolicyError(f"--from-default: the default policy {default.name} does not fit a --net {config.net} "
                              f"student: {err}") from err
        model.policy.load_state_dict(weights)
    return MimicPolicy(default.path, model, normalizer, {})


def finished_rounds(out: Path, key: str, resume: bool) -> tuple[list[dict], Labels | None]:
    """The rounds a run in ``out`` finished and its labels, to resume it (``([], None)`` unless
    ``resume`` and ``out/student`` holds a student). The student's sidecar, under
    ``extra[key]["rounds"]``, is the record: each round writes the labels, then the student, then
    the log line, so a run stopped between them has labels ahead of the student (cut back to the
    states it was fitted on) or a log line short (``out/log.jsonl`` is rewritten from the record)."""
    student_dir = out / "student"
    if not (resume and (student_dir / MODEL_FILE).exists()):
        return [], None
    done = PolicySidecar.load(student_dir / SIDECAR_FILE).extra[key]["rounds"]  # written whole with the model
    labels = Labels.load(out / "data.npz").take(slice(done[-1]["states"]))
    (out / "log.jsonl").write_text("".join(json.dumps(record) + "\n" for record in done))
    return done, labels


def save_student(out: Path, student: MimicPolicy, default: MimicPolicy, record: dict, training: TrainingRecord,
                 config: DistillConfig) -> Path:
    """Write ``out/student`` whole (:func:`agents.policy.save_loaded_policy`): the model, its
    observation statistics (the default teacher's, widened by a reference window), and a sidecar
    naming its task (:func:`student_task`) and this distillation."""
    variance = student_action_variance(default, config)
    sidecar = PolicySidecar(env=student_task(default, config), ppo=PPOSettings(net=config.net, action_variance=variance),
                            training=training, metrics={}, extra={"distillation": record})
    save_loaded_policy(out / "student", student.model, student.normalizer, sidecar)
    return out / "student"


def artefact_mix(args: argparse.Namespace, seed: int) -> ArtefactMix | None:
    """The IMU-corruption mix of the distillation's episodes and how every reference the student
    tracks is prepared (``--denoise`` with ``--denoise-slow``, unless the teacher reads the denoised
    take, ``--even-legs``, ``--part-legs``, ``--ground``, ``--swing-lift``, in ``train_ppo.py``'s order);
    a prepared take's episode is judged against the take as given, as ``evaluate.py`` judges it.
    ``None`` without corruption or preparation; a clear ``ValueError`` for options that cannot act."""
    check_slowing(args.denoise, args.denoise_slow)
    steps = preparation_of(args)
    if args.teacher_reads == "denoised" and not args.denoise:
        raise ValueError("--teacher-reads denoised: the teacher reads the take after the IMU denoiser --denoise "
                         "names; give --denoise [DIR]")
    if args.corrupted_fraction <= 0 and (args.teacher_reads != "track" or args.denoise):
        raise ValueError(f"--teacher-reads {args.teacher_reads} and --denoise act on corrupted episodes; "
                         "give --corrupted-fraction > 0")
    student_denoiser = None if args.teacher_reads == "denoised" else args.denoise
    mix = ArtefactMix(recipe=ArtefactRecipe.imu(), strength=tuple(args.strength), fraction=args.corrupted_fraction,
                      variants_per_clip=args.variants_per_clip, seed=seed, denoiser=student_denoiser,
                      denoise_slow_s=args.denoise_slow if student_denoiser else None, **steps)
    if args.corrupted_fraction <= 0 and not mix.prepares(False):
        return None
    return replace(mix, judge="given") if mix.prepares(args.corrupted_fraction > 0) else mix


def teacher_mix(args: argparse.Namespace, mix: ArtefactMix | None) -> ArtefactMix | None:
    """With ``--teacher-reads denoised``, the student's ``mix`` with its corrupted variants passed
    through ``--denoise`` (with ``--denoise-slow``; the same artefact seed, so the same corruptions): what
    the teachers read; otherwise ``None`` (they read the student's env)."""
    if args.teacher_reads != "denoised" or mix is None:
        return None
    return replace(mix, denoiser=args.denoise, denoise_slow_s=args.denoise_slow)


def teacher_weight(text: str) -> tuple[str, float]:
    """argparse type of ``--teacher-weight``: ``"mimic_walk_back=4"`` → ``("mimic_walk_back", 4.0)``;
    raises ``argparse.ArgumentTypeError`` unless it is NAME=W with W a finite number > 0."""
    name, sep, value = text.partition("=")
    try:
        if sep and name:
            return name, positive_float(value)
    except argparse.ArgumentTypeError:
        pass
    raise argparse.ArgumentTypeError(f"expected NAME=W, a teacher's directory name and a finite weight > 0 "
                                     f"(e.g. mimic_walk_back=4), got {text!r}")


def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--teacher", help="a policy set directory (models/mimic_set) or a policy directory")
    p.add_argument("--clips", nargs="+", help="training clips: SOURCE strings or clip sets")
    p.add_argument("--exclude", nargs="*", default=[], help="clips to leave out")
    p.add_argument("--mirror", action="store_true", help="also every clip mirrored left/right")
    p.add_argument("--warp", type=glob_speeds, nargs="+", default=[], metavar="GLOB=S,S",
                   help="also the clips whose SOURCE matches GLOB time-warped to each speed S (train_ppo.py --warp)")
    p.add_argument("--postures", type=non_negative_int, default=0, metavar="N",
                   help="also N copies of every clip carried with a random posture, drawn with --seed (train_ppo.py "
                        "--postures: the same copies for the same seed and ranges)")
    p.add_argument("--posture-range", type=posture_range, nargs="*", default=[], metavar="NAME=LOW,HIGH",
                   help="the ranges the --postures copies are drawn from (train_ppo.py --posture-range)")
    p.add_argument("--stances", type=non_negative_int, default=0, metavar="N",
                   help="also N copies of every clip walked with the feet further apart (train_ppo.py --stances)")
    p.add_argument("--stance-extra", type=float, nargs=2, default=STANCE_EXTRA_M, metavar=("LOW", "HIGH"),
                   help="how much further apart (m; train_ppo.py --stance-extra)")
    p.add_argument("--corrupted-fraction", type=fraction, default=0.5,
                   help="share of episodes with an IMU-corrupted reference (as the teachers trained)")
    p.add_argument("--strength", type=non_negative_float, nargs=2, default=(0.5, 1.0), metavar=("LOW", "HIGH"))
    p.add_argument("--variants-per-clip", type=positive_int, default=2, help="corrupted references per clip")
    p.add_argument("--teacher-reads", choices=TEACHER_READS, default="track",
                   help="what a corrupted episode's teacher observes: the reference the student tracks ('track'), "
                        "or the clean take it was corrupted from, at the same state ('clean': a privileged "
                        "teacher, so the student learns to act on the corrupted take as the teacher does on "
                        "the clean one), or the corrupted take after --denoise while the student reads it as "
                        "given ('denoised': the student learns to act on the raw take as the teacher does "
                        "behind the denoiser; give it a window, --lookahead/--lookbehind, to see the jitter)")
    p.add_argument("--mirror-average", action="store_true",
                   help="the teachers and the acting student are their symmetric actors (agents/mirror.py), and "
                        "every state is also fitted mirrored, as evaluate.py --mirror-average acts")
    p.add_argument("--plain-teachers", nargs="+", default=[], metavar="NAME",
                   help="with --mirror-average, these teachers (a policy set's directories' names) label as their "
                        "plain actor, not their symmetric one: a teacher of the side of a take a policy performs "
                        "(its mirror image teaching the other side) would otherwise average the failing side back in")
    add_denoise_option(p, "every corrupted reference, before the student observes it, as evaluate.py --denoise does")
    add_slow_corrections_option(p)
    add_leg_symmetry_option(p, "every reference the student tracks, clean or corrupted (envs.ArtefactMix.symmetry)")
    add_leg_gap_option(p, "every reference the student tracks, clean or corrupted, after --even-legs (and after "
                          "--denoise unless the teacher reads the denoised take) (envs.ArtefactMix.legs)")
    add_grounding_option(p, "every reference the student tracks is set on the floor (after --even-legs, --part-legs "
                            "and --denoise, unless the teacher reads the denoised take)")
    add_swing_lift_options(p, "every reference the student tracks is lifted last")
    defaults = DistillConfig()
    p.add_argument("--net", default=defaults.net, help="the student's hidden layer sizes")
    p.add_argument("--rounds", type=positive_int, default=defaults.rounds)
    p.add_argument("--steps-per-round", type=positive_int, default=defaults.steps_per_round)
    p.add_argument("--epochs", type=positive_int, default=defaults.epochs)
    p.add_argument("--batch-size", type=positive_int, default=defaults.batch_size)
    p.add_argument("--lr", type=positive_float, default=defaults.lr)
    p.add_argument("--seed", type=int, default=defaults.seed)
    p.add_argument("--teacher-weight", type=teacher_weight, nargs="+", default=[], metavar="NAME=W",
                   help="loss weight of a teacher's states, by its directory name (mimic_walk_back=4); others "
                        "weigh 1 (a resumed run keeps its own)")
    p.add_argument("--from-default", action="store_true",
                   help="the student starts as the set's default policy (in wider hidden layers if --net is wider), "
                        "not from a fresh initialisation")
    p.add_argument("--lookahead", type=positive_int, nargs="+", default=[], metavar="STEPS",
                   help="the student also observes the reference this many control steps ahead, each "
                        "(MimicConfig.lookahead); the teachers read the observation without it")
    p.add_argument("--lookbehind", type=positive_int, nargs="+", default=[], metavar="STEPS",
                   help="and this many control steps back, each (MimicConfig.lookbehind): with --lookahead a "
                        "window of the take around now")
    p.add_argument("--out", type=output_dir, required=True)
    p.add_argument("--resume", action="store_true", help="continue the distillation in --out")
    p.add_argument("--no-progress", action="store_true")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the student's directory."""
    argv = sys.argv[1:] if argv is None else argv
    args, history = resumable_run(build_parser(prog), argv, "distillation")
    out: Path = args.out
    settings = out / "args.json"
    if not args.teacher or not args.clips:
        raise ValueError("--teacher and --clips are needed (unless --resume)")
    config = DistillConfig(net=args.net, rounds=args.rounds, steps_per_round=args.steps_per_round, epochs=args.epochs,
                           batch_size=args.batch_size, lr=args.lr, seed=args.seed,
                           teacher_weights=tuple((name, float(w)) for name, w in args.teacher_weight),
                           from_default=args.from_default, lookahead=tuple(args.lookahead),
                           lookbehind=tuple(args.lookbehind))
    torch.manual_seed(config.seed)
    clips = [c for c in expand_clips(args.clips) if c not in set(args.exclude)]
    warps, ranges, extra = warped_clips(clips, args.warp), posture_ranges(args), stance_extra(args)

    def motions(foot: str) -> list[Motion]:
        loaded = load_training_motions(clips, FOOT_MODELS[foot], args.mirror, warps=warps)
        return loaded + reposed_copies(loaded, args, config.seed)

    check_teacher_set(args.teacher, args.denoise)
    teachers = load_teachers(args.teacher, motions)
    names, default = teachers.names, teachers.policies[teachers.default]
    config.weights_of(names)  # a weight for a teacher that is not one fails now, not after round 0
    unknown = sorted(set(args.plain_teachers) - set(names))
    if unknown or (args.plain_teachers and not args.mirror_average):
        raise ValueError(f"--plain-teachers {' '.join(args.plain_teachers)}: "
                         + (f"{', '.join(unknown)} name no teacher (teachers: {', '.join(names)})" if unknown
                            else "it exempts teachers from --mirror-average, which is not given"))
    mix = artefact_mix(args, config.seed)
    env = student_task(default, config).make(teachers.motions, artefacts=mix)
    check_teacher_layouts(teachers.policies, env)
    readers = teacher_mix(args, mix)
    teacher_env = None if readers is None else default.record.env.make(teachers.motions, artefacts=readers)
    maps = MirrorMaps.of(env) if args.mirror_average else None
    if maps is not None:
        teachers = replace(teachers, policies=[t if name in args.plain_teachers else symmetric_teacher(t, maps)
                                               for t, name in zip(teachers.policies, names)])
    sigma = float(default.model.policy.log_std.detach().exp().mean())
    log_file, data_file = out / "log.jsonl", out / "data.npz"
    done, labels = finished_rounds(out, "distillation", args.resume)
    if done:
        student = MimicPolicy(default.path, PPO.load(out / "student" / MODEL_FILE, env=DummyVecEnv([lambda: env]),
                                                     device="cpu"), load_policy(out / "student").normalizer, {})
        print(f"resuming after round {len(done) - 1} ({len(labels)} labelled states)", flush=True)
    else:
        student = new_student(env, default, config)
    acting = student if maps is None else replace(student, mirror=maps)  # shares the weights the fit moves
    out.mkdir(parents=True, exist_ok=True)
    args.commands = history + [shlex.join(["python", "agents/distill.py", *argv])]  # every command of the run, in order
    write_json(settings, {**vars(args), "out": str(out)})
    rng = np.random.default_rng([config.seed, len(done)])
    started = time.monotonic() - (done[-1]["wall_s"] if done else 0.0)
    for round_ in range(len(done), config.rounds):
        actor = None if round_ == 0 else acting
        first_episode = int(labels.episode.max()) + 1 if labels is not None else 0
        new = collect(env, actor, teachers, config.steps_per_round, sigma, rng, first_episode, not args.no_progress,
                      args.teacher_reads, maps, teacher_env)
        labels = new if labels is None else labels + new
        train_rows, held = split_holdout(labels, config.holdout, config.seed)
        if not len(train_rows):
            raise ValueError(f"round {round_}: every labelled episode ({len(np.unique(labels.episode))}) is held out; "
                             f"collect more steps per round (--steps-per-round {config.steps_per_round})")
        if round_ == 0 and not config.from_default:
            center_values(student, labels, train_rows)
        loss = fit(student, labels, config, sigma, rng, not args.no_progress, names, rows=train_rows)
        record = {"round": round_, "acted_by": "teachers" if actor is None else "student", "states": len(labels),
                  "loss": loss, "wall_s": time.monotonic() - started,
                  "held_out": fit_report(acting, held, names),
                  "acted_episode_steps": float(len(new) / max(1, len(np.unique(new.episode))))}
        labels.save(data_file)
        training = TrainingRecord(clips=clips, corrupted_fraction=args.corrupted_fraction,
                                  strength=tuple(args.strength), judge=mix.judge if mix else ArtefactMix().judge,
                                  denoiser=repository_relative(mix.denoiser if mix else None),
                                  denoise_slow_s=mix.denoise_slow_s if mix else None,
                                  **preparation_record(mix.steps if mix else no_preparation(), lift_key="lift"),
                                  mirror=args.mirror, warps=warps,
                                  postures=args.postures, posture_seed=config.seed,
                                  posture_ranges=asdict(ranges) if args.postures else None,
                                  stances=args.stances,
                                  stance_extra_m=extra if args.stances else None,
                                  init_from=str(args.teacher),
                                  commands=args.commands, seed=config.seed,
                                  steps=len(labels), wall_s=record["wall_s"])
        save_student(out, student, default, {"config": asdict(config), "teachers": names, "rounds": done + [record],
                                             "teacher_reads": args.teacher_reads,
                                             "teacher_denoiser": repository_relative(readers.denoiser) if readers
                                             else None}, training, config)
        with open(log_file, "a") as f:
            f.write(json.dumps(record) + "\n")
        done.append(record)
        report = record["held_out"]
        print(f"[round {round_}] {record['states']} states, loss {loss:.3f}, held-out action RMSE "
              f"{report['action_rmse']:.3f} rad (" + ", ".join(f"{n} {rmse_text(report[f'action_rmse_{n}'])}"
                                                            for n in names)
              + f"), value R² {report['value_r2']:.3f}, {record['acted_episode_steps']:.0f} steps per episode acted",
              flush=True)
    env.close()
    if teacher_env is not None:
        teacher_env.close()
    return out / "student"


if __name__ == "__main__":
    main()
