"""Per-clip adaptation: PPO fine-tunes a trained mimic policy on the one clip it is asked to clean.

A general policy (``models/mimic_imu``) often fails on a clip it never saw; a few minutes of PPO
on that clip alone, starting from its weights, specialise it to that clip. :func:`adapt_policy`
builds ``AdaptConfig.n_envs`` environments of the policy's id and foot model on the clip as given
(corrupted or not; ``artefacts=None``, episodes start where the policy fails more often), wraps
them in the policy's observation statistics, loads its PPO weights and learns in chunks of
``chunk_steps``; after each chunk the deterministic policy is evaluated on the clip
(:func:`agents.evaluation.evaluate`, ``eval_episodes`` start frames spread over the clip) and
performs the clip whole as :mod:`agents.clean` performs it. It stops when SR90 reaches
``target_sr90`` and the whole performance has no re-anchor, or when ``budget_s`` of wall time
(evaluations included) or ``max_steps`` run out, and keeps the chunk whose performance is best
(fewest re-anchors, then fewest failures recovered by a retry, then the highest reward ratio
over the whole performance; the policy as given when no chunk beats it). With
``target_sr90=None`` it does not stop at survival but trains on to the budget: once the clip is
performed whole, the reward (how closely it is tracked, and for ``MimicGait-v0`` its contacts)
decides which chunk is kept. The evaluations alone (``keep="evaluation"``, the rule before:
SR90, then ELR, then the mean reward ratio MRR, stopping at the target SR90) restart each rollout
from a reference state, so one start frame that no chunk survives pins SR90 and leaves the choice
to noise in ELR (seen on a held-out walk: the chunk kept after 82k of 695k steps), and a clip
whose evaluations pass can still re-anchor when performed whole (a validation take stopped after
42 s with one re-anchor; judged by its performance it trained on to 103 s and none).

The observation statistics stay frozen (``VecNormalize.training = False``, unless
``update_normalizer``): the policy's layers were trained on inputs normalised by them, so moving
them on one clip would shift every input of the pre-trained network at once, and with the millions
of steps they already count a few thousand more would move them by well under 1% anyway.

The adapted policy is a policy directory like any other (``model.zip``,
``model_vecnormalize.pkl``, ``sidecar.json`` with an ``adaptation`` record), cached under
``cache_dir/<key>/`` where ``key`` (:func:`adaptation_key`) hashes the clip's content, rate and
model with the policy's path, weights and gait ablation and the adaptation's training settings
(the chunk-keeping rule included), so cleaning the same clip again skips the training.
"""

from __future__ import annotations

import copy
import hashlib
import json
import os
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Callable

import gymnasium as gym
import numpy as np
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback, CallbackList
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize
from tqdm import tqdm

import envs  # noqa: F401  (registers the ids)
from agents.batched_vec_env import BatchedMimicVecEnv
from agents.evaluation import evaluate
from agents.lr_schedule import kl_following
from agents.policy import SIDECAR_FILE, MimicPolicy, load_policy, save_policy, set_action_variance
from agents.rollout import Policy, torch_threads
from agents.sidecar import PolicySidecar
from envs.config import MimicConfig
from envs.mimic import MimicEnv
from reference_motion.motion import Motion


def default_cache_dir() -> Path:
    """``$XDG_CACHE_HOME/physmimic/adapted`` (default ``~/.cache/physmimic/adapted``)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "physmimic" / "adapted"


MIN_ADAPT_FRAMES = MimicConfig().min_clip_frames + 1
"""Frames a clip needs for a mimic environment to train on it (31 at 60 Hz)."""

KEEP_RULES = ("evaluation", "performance")
"""How the chunk an adaptation keeps is chosen (:attr:`AdaptConfig.keep`)."""


@dataclass(frozen=True)
class AdaptConfig:
    """How a policy is adapted to one clip.

    Attributes:
        budget_s: wall-time budget (s) of the whole adaptation, evaluations included (300).
        target_sr90: stop once an evaluation reaches this SR90 (0.9); ``None``: never stop early,
            train to ``budget_s`` / ``max_steps`` and keep the chunk ranked best by ``keep``.
        keep: which chunk is kept (one of :data:`KEEP_RULES`): ``"performance"`` (the default)
            ranks the chunks by the clip performed whole as :mod:`agents.clean` does it (fewest
            re-anchors, then fewest recoveries, then the highest reward ratio:
            :func:`performance_rank`): what the user is given, where the evaluations start each
            rollout from a reference state and can rank on one start frame the whole clip never
            fails at; a target SR90 then ends the adaptation only once the clip is also performed
            whole with no re-anchor (:meth:`reached`). ``"evaluation"`` (the rule before; cached
            entries made before this option were made with it) ranks them by their evaluation
            (SR90, then ELR, then MRR: :func:`chunk_rank`) and stops at the target SR90 alone.
        chunk_steps: environment (control) steps between evaluations (20 000).
        max_steps: most environment steps in all (``None``: only the budget limits).
        n_envs: environments stepped together (4, in this process; see ``physics_threads``).
        n_steps: rollout length per environment per PPO update (512; 2048 steps per update).
        eval_episodes: deterministic rollouts per evaluation, start frames spread over the clip (5).
        seed: seed of the environments and of PPO's sampling (0).
        update_normalizer: let the observation statistics follow this clip (False: frozen, see
            the module's documentation).
        target_kl: follow this approximate KL per PPO update with the learning rate, starting from the
            policy's own (:mod:`agents.lr_schedule`); ``None``: the policy's rate, fixed.
        action_variance: the exploration noise σ² (rad²) while adapting, kept by the adapted policy
            (its stochastic retries in :mod:`agents.clean` sample with it); ``None``: the policy's
            own (ADAPT's 0.03).
        learning_rate: PPO's learning rate while adapting (``None``: the policy's own, as trained;
            the starting rate when ``target_kl`` is set).
        torch_threads: torch threads while adapting (1: a 256×256 network gains nothing from more,
            and where other processes use the cores, more threads wait on each other: 2 threads
            took 69 s for what 1 does in 3 s beside a training run on 2 cores).
        physics_threads: threads stepping the environments' physics (``None``: one per core, at most
            one per environment). A ``MimicEnv`` policy's environments are stepped as one batch
            (:class:`agents.batched_vec_env.BatchedMimicVecEnv`: the same transitions as one at a
            time, so a given number of steps trains the same policy whatever this is; within a
            wall-time budget, faster stepping means more steps, as a less loaded machine does);
            others one at a time in this process. Give 1 where other processes use the cores.
        cache_dir: where adapted policies are kept (:func:`default_cache_dir`).
    """

    budget_s: float = 300.0
    target_sr90: float | None = 0.9
    keep: str = "performance"
    chunk_steps: int = 20_000
    max_steps: int | None = None
    n_envs: int = 4
    n_steps: int = 512
    eval_episodes: int = 5
    seed: int = 0
    update_normalizer: bool = False
    target_kl: float | None = None
    action_variance: float | None = None
    learning_rate: float | None = None
    torch_threads: int = 1
    physics_threads: int | None = None
    cache_dir: Path = field(default_factory=default_cache_dir)

    def __post_init__(self) -> None:
        if not self.budget_s > 0:
            raise ValueError(f"budget_s must be positive, got {self.budget_s}")
        for name in ("chunk_steps", "n_envs", "n_steps", "eval_episodes", "torch_threads"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)}")
        for name in ("action_variance", "learning_rate"):
            if getattr(self, name) is not None and not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive or None, got {getattr(self, name)}")
        if self.keep not in KEEP_RULES:
            raise ValueError(f"keep must be one of {KEEP_RULES}, got {self.keep!r}")
        if self.max_steps is not None and self.max_steps < 1:
            raise ValueError(f"max_steps must be >= 1 or None, got {self.max_steps}")
        if self.physics_threads is not None and self.physics_threads < 1:
            raise ValueError(f"physics_threads must be >= 1 or None, got {self.physics_threads}")

    def reached(self, summary: dict) -> bool:
        """Whether a chunk judged ``summary`` (its ``SR90``; with ``keep="performance"`` also its
        performance's ``reanchors``) ends the adaptation: SR90 at least ``target_sr90`` and, when
        the chunks rank by their performance, the clip performed whole with no re-anchor (never
        when ``target_sr90`` is ``None``)."""
        if self.target_sr90 is None or summary["SR90"] < self.target_sr90:
            return False
        return self.keep != "performance" or summary.get("reanchors") == 0

    def training_settings(self) -> tuple:
        """What shapes the adapted policy (how it trains and which chunk it keeps, not how long it
        runs): a cached adaptation stands in for another only with the same settings."""
        return (self.n_envs, self.n_steps, self.seed, self.update_normalizer, self.target_kl, self.action_variance,
                self.learning_rate, self.keep)

    def covers(self, other: AdaptConfig) -> bool:
        """Whether a run made with these limits tried at least as hard as one with ``other``'s."""
        steps = self.max_steps or float("inf")
        polished = self.target_sr90 is None or (other.target_sr90 is not None
                                                and self.target_sr90 >= other.target_sr90)
        return polished and self.budget_s >= other.budget_s and steps >= (other.max_steps or float("inf"))


@dataclass(frozen=True)
class AdaptResult:
    """What adaptation achieved.

    Attributes:
        policy: the adapted policy (loaded from :attr:`path`).
        path: its directory in the cache.
        key: its cache key (:func:`adaptation_key`).
        cached: whether it came from the cache (no training in this call).
        sr90_before, sr90_after: SR90 on the clip of the policy as given and as adapted.
        elr_before, elr_after: the same for ELR.
        steps: environment steps trained.
        wall_s: wall time of the adaptation (s; of the run that made it, when cached).
        stopped_by: ``"target"`` (SR90 reached ``target_sr90``; :meth:`AdaptConfig.reached`), ``"already_good"`` (it had before
            any training), ``"budget"`` or ``"max_steps"``.
        chunks: one record per evaluated chunk: ``steps``, ``wall_s``, ``SR90``, ``ELR_mean``,
            ``MRR_mean``, with ``keep="performance"`` or a hook the whole performance's
            ``reanchors``, ``recoveries`` and ``reward_ratio``, and what ``on_chunk`` returned for
            it (entries made before ``MRR_mean`` was recorded lack it).
        before: the evaluation of the policy as given (``SR90``, ``ELR_mean``, ``MRR_mean``, ...)
            and what ``on_chunk`` returned for it (empty for older cache entries).
        kept_steps: the steps of the chunk kept (0: none beat the policy as given, which is kept
            with its own exploration noise; ``None`` for older cache entries).
    """

    policy: MimicPolicy
    path: Path
    key: str
    cached: bool
    sr90_before: float
    sr90_after: float
    elr_before: float
    elr_after: float
    steps: int
    wall_s: float
    stopped_by: str
    chunks: list[dict]
    before: dict = field(default_factory=dict)
    kept_steps: int | None = None

    def as_dict(self) -> dict:
        """JSON-ready record (without the policy object)."""
        return {"path": str(self.path), "key": self.key, "cached": self.cached, "SR90_before": self.sr90_before,
                "SR90_after": self.sr90_after, "ELR_before": self.elr_before, "ELR_after": self.elr_after,
                "steps": self.steps, "wall_s": self.wall_s, "stopped_by": self.stopped_by, "chunks": self.chunks,
                "before": self.before, "kept_steps": self.kept_steps}


def adaptation_key(reference: Motion, policy: MimicPolicy, config: AdaptConfig = AdaptConfig()) -> str:
    """sha1 of the clip's content (``qpos`` bytes as float64, rate, model) and of the policy (its
    resolved directory, the bytes of its model archive (:attr:`MimicPolicy.model_file`: a run's
    checkpoint where it was loaded from one) and, for the same weights in a gait-ablated task
    (:meth:`MimicPolicy.ablated`), the ablation, or observing in another frame than they were
    trained in (:meth:`MimicPolicy.observing`), that frame, or simulated at another physics rate
    (:meth:`MimicPolicy.simulating`), that rate: it adapts to another policy), and of ``config``'s
    training settings (:meth:`AdaptConfig.training_settings`, the chunk-keeping rule included)
    where they differ from those every entry was made with before they counted
    (:data:`_EARLIER_SETTINGS`: those entries keep their keys), so runs made otherwise live beside
    each other instead of replacing each other."""
    h = hashlib.sha1()
    h.update(np.ascontiguousarray(reference.qpos, dtype=np.float64).tobytes())
    h.update(f"|{reference.fps!r}|{reference.model}|{Path(policy.path).resolve()}|".encode())
    h.update(policy.model_file.read_bytes())
    ablation = policy.record.extra.get("ablation")
    if ablation is not None:  # only then: the keys of unablated policies stay those of earlier versions
        h.update(f"|ablation={ablation}".encode())
    task = policy.record.env.mimic_config()
    if policy.record.extra.get("observed_in", task.obs_frame) != task.obs_frame:  # observing in another frame than trained in
        h.update(f"|obs_frame={task.obs_frame}".encode())
    if policy.record.extra.get("simulated_at", task.physics_rate_hz) != task.physics_rate_hz:  # another physics rate
        h.update(f"|physics_rate_hz={task.physics_rate_hz!r}".encode())
    settings = config.training_settings()
    if settings != _EARLIER_SETTINGS:
        h.update(f"|training={settings!r}".encode())
    return h.hexdigest()


_EARLIER_SETTINGS = AdaptConfig(keep="evaluation").training_settings()
"""The training settings of every cached adaptation made before the settings entered the key."""

_CHUNK_EVALUATION = ("SR90", "ELR_mean", "MRR_mean")
"""The evaluation figures each chunk's record keeps (``before`` keeps them all)."""

ChunkHook = Callable[[MimicPolicy, Motion], dict]
"""Called with the policy being adapted after each chunk and the clip performed whole by it
(:func:`agents.clean.clean_motion`); returns figures to record with the chunk."""


def chunk_rank(summary: dict) -> tuple[float, float, float]:
    """How a chunk's evaluation ranks: SR90, then ELR, then the mean reward ratio."""
    return summary["SR90"], summary["ELR_mean"], summary["MRR_mean"]


def performance_rank(summary: dict) -> tuple[int, int, float]:
    """How a chunk's whole performance of the clip ranks (``summary`` holds its ``reanchors``,
    ``recoveries`` and ``reward_ratio``): fewest re-anchors, then fewest failures recovered by a
    retry, then the highest reward ratio (``None``, nothing simulated, ranks last)."""
    ratio = summary["reward_ratio"]
    return -summary["reanchors"], -summary["recoveries"], -np.inf if ratio is None else ratio


def _performance(policy: MimicPolicy, reference: Motion) -> tuple[Motion, dict]:
    """``reference`` performed whole by ``policy`` as :mod:`agents.clean` does it with the policy
    alone (``--search off``: 0.5-s rewind, 4 stochastic retries; the search would cost about 30
    times as much per chunk, whatever the clip is then cleaned with), and the performance's
    ``reanchors``, ``recoveries`` (counts) and ``reward_ratio`` (``None`` when nothing was simulated)."""
    from agents.clean import POLICY_ALONE, clean_motion  # agents.clean imports this module

    performed = clean_motion(policy, reference, POLICY_ALONE, progress=False)
    source = performed.source
    ratio = source["reward_ratio"]
    return performed, {"reanchors": len(source["reanchors"]), "recoveries": len(source["recoveries"]),
                       "reward_ratio": float(ratio) if np.isfinite(ratio) else None}


class _Budget(BaseCallback):
    """Stops ``learn`` at ``deadline`` (``time.monotonic()``) and moves the progress bar (seconds)."""

    def __init__(self, deadline: float, started: float, bar: tqdm):
        super().__init__()
        self.deadline, self.started, self.bar = deadline, started, bar

    def _on_step(self) -> bool:
        now = time.monotonic()
        elapsed = min(int(now - self.started), int(self.bar.total))
        if elapsed > self.bar.n:
            self.bar.update(elapsed - self.bar.n)
        return now < self.deadline


def evaluate_on_clip(env: gym.Env, policy: Policy, episodes: int) -> dict[str, float]:
    """SR90 and ELR (:func:`agents.evaluation.evaluate`'s summary) of ``policy`` (any actor) on
    ``env``'s one clip: ``episodes`` rollouts from start frames spread evenly over the clip, as
    adaptation scores each chunk."""
    offset_step = env.unwrapped.last_start(0) // max(episodes - 1, 1)
    summary, _ = evaluate(env, policy, episodes=episodes, offset_step=offset_step)
    return summary


def _result(path: Path, record: dict, cached: bool) -> AdaptResult:
    """The :class:`AdaptResult` of the adapted policy in ``path`` with its ``adaptation`` record."""
    return AdaptResult(policy=load_policy(path), path=path, key=record["key"], cached=cached,
                       sr90_before=record["SR90_before"], sr90_after=record["SR90_after"],
                       elr_before=record["ELR_before"], elr_after=record["ELR_after"], steps=record["steps"],
                       wall_s=record["wall_s"], stopped_by=record["stopped_by"], chunks=record["chunks"],
                       before=record.get("before", {}), kept_steps=record.get("kept_steps"))


def _load_cached(path: Path, config: AdaptConfig) -> AdaptResult | None:
    """The cached adaptation in ``path`` if there is one made with ``config``'s training settings
    (:meth:`AdaptConfig.training_settings`) that reached ``config``'s target or was made with at
    least ``config``'s budget and steps."""
    sidecar = path / SIDECAR_FILE
    if not sidecar.is_file():
        return None
    try:
        record = json.loads(sidecar.read_text())["adaptation"]
        made_with = AdaptConfig(**{"keep": "evaluation", **record["config"], "cache_dir": config.cache_dir})
    except (ValueError, KeyError, TypeError):
        return None  # an older or damaged entry: adapt again
    enough = config.reached({"SR90": record["SR90_after"], "reanchors": record.get("reanchors_after")}) \
        or made_with.covers(config)
    if made_with.training_settings() != config.training_settings() or not enough:
        return None
    return _result(path, record, cached=True)


def adapt_policy(policy: MimicPolicy, reference: Motion, config: AdaptConfig = AdaptConfig(),
                 progress: bool = True, on_chunk: ChunkHook | None = None) -> AdaptResult:
    """``policy`` fine-tuned with PPO on ``reference`` (at least :data:`MIN_ADAPT_FRAMES` frames,
    the policy's model, 60 Hz), or the cached result of an earlier call (see the module's
    documentation). ``on_chunk(policy, performed)`` is called with the policy as trained so far
    and the clip performed whole by it after each chunk's evaluation (and once before training);
    what it returns (JSON-native values; where a key is also one of the evaluation's or of the
    performance's figures, theirs is kept) is added to that chunk's record (``AdaptResult.chunks``; the call before training to
    ``AdaptResult.before``); its time counts against the budget."""
    if reference.n_frames < MIN_ADAPT_FRAMES:
        raise ValueError(f"{reference.name}: {reference.n_frames} frames; adaptation needs at least "
                         f"{MIN_ADAPT_FRAMES}")
    if policy.symmetric_network and config.update_normalizer:
        raise ValueError(f"{policy.name}: a network trained as the symmetric actor needs its mirror-symmetric "
                         "observation statistics frozen; adapt it without update_normalizer")
    if policy.mirror is not None:
        raise ValueError(f"{policy.name}: adaptation trains the network itself; adapt the policy as it is and "
                         "make the adapted one mirror-symmetric afterwards (MimicPolicy.mirror_averaged)")
    key = adaptation_key(reference, policy, config)
    path = Path(config.cache_dir) / key
    with torch_threads(config.torch_threads):
        return _load_cached(path, config) or _adapt(policy, reference, config, key, path, progress, on_chunk)


def _adapt(policy: MimicPolicy, reference: Motion, config: AdaptConfig, key: str, path: Path,
           progress: bool, on_chunk: ChunkHook | None) -> AdaptResult:
    """:func:`adapt_policy` without the cache: train, keep the best chunk, write ``path``."""
    started = time.monotonic()
    eval_env = policy.make_env([reference], artefacts=None)  # the policy's own task, on this clip as given
    eval_env.reset(seed=config.seed)
    batched = type(eval_env.unwrapped) is MimicEnv
    venv = VecNormalize.load(str(policy.stats_file),
                             make_vec_env(lambda: policy.make_env([reference], artefacts=None), n_envs=config.n_envs,
                                          seed=config.seed, vec_env_cls=BatchedMimicVecEnv if batched else DummyVecEnv,
                                          vec_env_kwargs={"n_threads": config.physics_threads} if batched else None))
    venv.training = config.update_normalizer
    batch_size = min(policy.model.batch_size, config.n_steps * config.n_envs)
    rate = {} if config.learning_rate is None else {"learning_rate": config.learning_rate}
    model = PPO.load(policy.model_file, env=venv, device="cpu", n_steps=config.n_steps,
                     batch_size=batch_size, seed=config.seed, tensorboard_log=None, verbose=0, **rate)
    model.policy.log_std.requires_grad_(False)  # the exploration noise stays fixed (train_ppo.py)
    adapted = MimicPolicy(Path(policy.path), model, venv, policy.sidecar, source=policy.source)

    def snapshot() -> tuple[dict, object]:
        return copy.deepcopy(model.policy.state_dict()), copy.deepcopy(venv.obs_rms)

    by_performance = config.keep == "performance"
    rank = performance_rank if by_performance else chunk_rank

    def judge() -> tuple[dict, dict]:
        """The current policy's judgement (its evaluation, and where needed the figures of its whole
        performance and the hook's), and those figures alone (empty when neither is needed)."""
        evaluation = evaluate_on_clip(eval_env, adapted, config.eval_episodes)
        if not (by_performance or on_chunk):
            return evaluation, {}
        performed, figures = _performance(adapted, reference)
        hooked = {k: v for k, v in (on_chunk(adapted, performed) if on_chunk else {}).items() if k not in evaluation}
        figures = {**hooked, **figures}
        return {**figures, **evaluation}, figures

    t0 = time.monotonic()
    best = before = judge()[0]
    eval_s = time.monotonic() - t0
    best_state, kept_steps = snapshot(), 0  # the policy as given, its own noise included
    if config.action_variance is not None:  # from here on, and in every chunk kept
        set_action_variance(model, config.action_variance)
    first_step, chunks = model.num_timesteps, []
    stopped_by = "already_good" if config.reached(before) else ""
    bar = tqdm(total=int(np.ceil(config.budget_s)), desc=f"adapting to {reference.name}", unit="s",
               disable=not progress)
    bar.set_postfix(SR90=f"{before['SR90']:.2f}", steps=0)
    while not stopped_by:
        trained = model.num_timesteps - first_step
        deadline = started + config.budget_s - eval_s  # leave time for the evaluation after the chunk
        if time.monotonic() >= deadline:
            stopped_by = "budget"
            break
        chunk = config.chunk_steps if config.max_steps is None else min(config.chunk_steps, config.max_steps - trained)
        callbacks = CallbackList([_Budget(deadline, started, bar), *kl_following(config.target_kl)])
        model.learn(chunk, callback=callbacks, reset_num_timesteps=False, progress_bar=False)
        t0 = time.monotonic()
        summary, figures = judge()
        trained = model.num_timesteps - first_step
        chunks.append({**figures, **{k: summary[k] for k in _CHUNK_EVALUATION},
                       "steps": trained, "wall_s": time.monotonic() - started})
        eval_s = time.monotonic() - t0
        bar.set_postfix(SR90=f"{summary['SR90']:.2f}", steps=trained)
        reached = config.reached(summary)
        if reached or rank(summary) > rank(best):  # the chunk that reaches the target ends it and is kept
            best, best_state, kept_steps = summary, snapshot(), trained
        if reached:
            stopped_by = "target"
        elif config.max_steps is not None and trained >= config.max_steps:
            stopped_by = "max_steps"
        elif time.monotonic() >= started + config.budget_s - eval_s:
            stopped_by = "budget"
    bar.close()
    model.policy.load_state_dict(best_state[0])
    venv.obs_rms = best_state[1]
    wall_s = time.monotonic() - started
    record = {"key": key, "base_policy": policy.name, "clip": reference.name, "SR90_before": before["SR90"],
              "SR90_after": best["SR90"], "ELR_before": before["ELR_mean"], "ELR_after": best["ELR_mean"],
              "reanchors_after": best.get("reanchors"),
              "steps": model.num_timesteps - first_step, "wall_s": wall_s, "stopped_by": stopped_by, "chunks": chunks,
              "before": before, "kept_steps": kept_steps,
              "config": {k: v for k, v in asdict(config).items() if k != "cache_dir"}}
    save_policy(path, model, venv, _sidecar(policy, reference, record, best))
    venv.close()
    eval_env.close()
    return _result(path, record, cached=False)


def _sidecar(policy: MimicPolicy, reference: Motion, record: dict, metrics: dict) -> PolicySidecar:
    """The adapted policy's sidecar: the base policy's task and PPO settings, its training record
    continued on ``reference`` (``init_from`` the base policy), the evaluation on the clip, and
    the ``adaptation`` record."""
    base = policy.record
    training = replace(base.training, clips=[reference.name], eval_clips=[reference.name], corrupted_fraction=0.0,
                       mirror=False, speeds=[1.0], init_from=policy.name,
                       steps=base.training.steps + record["steps"], wall_s=base.training.wall_s + record["wall_s"])
    return replace(base, training=training, metrics=metrics, score=None, extra={**base.extra, "adaptation": record})

