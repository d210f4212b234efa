"""Expert iteration: the sampling search teaches the policy that guides it.

Usage::

    python agents/expert_iteration.py --policy models/mimic_general --clips library:data/library/train \\
        --mirror --corrupted-fraction 0.5 --workers 2 --out runs/exit
    python agents/expert_iteration.py --out runs/exit --resume            # after an interruption
    python agents/evaluate.py --policy runs/exit/student --clips library:data/library/val

Why: the policy-guided search (:mod:`agents.search`) carries a simulation past places where the
policy alone falls, by keeping the noisy rollouts that track the clip best. What it kept is a
demonstration, in the policy's own states, of actions that work where the policy's do not. Fitting
the policy to those actions and searching again with the fitted policy is expert iteration
(Anthony et al. 2017; with SAMCON as the expert, Liu & Hodgins 2018): the search is the expert, the
network the apprentice, and each improves the other. Unlike PPO's gradient, which weighs every
sampled action by an advantage its critic estimates, this keeps only what the search selected.

Each round runs ``episodes_per_round`` searches. Each is one training clip (uniformly at random;
IMU-corrupted with probability ``corrupted_fraction`` at a strength drawn from ``strength``), from
the reference state at a random start frame to the end of an episode (``episode_frames``), guided
by the current student. The lineage it kept is replayed to record the observation and the action
(before smoothing) of every control step; when the search failed, the window of the fall and the
``drop_windows`` windows before it are not used. The student (the policy's actor and critic, its observation
statistics frozen) is then fitted to every label so far with :func:`agents.distill.fit`; the value
labels are the guiding critic's own estimates, so the critic is held where it was (PPO refits it).

``OUT`` holds ``student/`` (a policy directory; its sidecar records the rounds), ``data.npz``
(the labelled states) and ``log.jsonl`` (one line per round), each written whole after every round:
``--resume`` continues after the last round the student's sidecar records, losing at most one
round (only ``--rounds`` and ``--workers`` may change).
"""

from __future__ import annotations

import json
import shlex
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field
from pathlib import Path

if __package__ in (None, ""):  # `python agents/expert_iteration.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gymnasium as gym
import numpy as np
import torch
from tqdm import tqdm

import envs  # noqa: F401  (registers the ids)
from agents.distill import DistillConfig, Labels, finished_rounds, fit, fit_report, split_holdout
from agents.policy import MimicPolicy, load_policy, save_policy
from agents.rollout import FAILURES, Episode, run_episode, torch_threads
from agents.search import SearchConfig, search
from agents.sidecar import PolicySidecar, TrainingRecord
from agents.train_ppo import load_training_motions
from envs import ArtefactMix
from envs.config import FOOT_MODELS
from reference_motion.atomic import write_json
from reference_motion.cli import (CliParser, fraction, non_negative_float, one_line_errors, or_none, output_dir,
                                  positive_float, positive_int, resumable_run)
from reference_motion.library import expand_clips
from reference_motion.motion import Motion


SEARCH_JUDGES = ("corrupted", "clean")
"""What a corrupted episode's search may rank against (:attr:`envs.ArtefactMix.judge`'s first two:
expert iteration prepares no reference, so ``"given"`` would be ``"corrupted"``)."""


@dataclass(frozen=True)
class ExpertIterationConfig:
    """How the search teaches the policy.

    Attributes:
        rounds: search-then-fit rounds (1: on the validation takes a second and third round
            lowered the clean ELR, 0.889 → 0.864, where the first had kept it; README).
        episodes_per_round: searches per round, one episode each (256: ~25,000 labelled steps,
            3.5 min on two cores with the default search).
        search: the search each episode runs (:class:`agents.search.SearchConfig`; default a beam
            of 8 from 32 rollouts a window, half the cleaning default's cost).
        drop_windows: windows before a failed search's fall left unlabelled (2).
        epochs, batch_size, lr: the fit (:func:`agents.distill.fit`): passes over every label so
            far after each round (5), minibatch size (512), Adam learning rate (1e-4: the student
            starts from a trained policy).
        holdout: share of the episodes held out to report the fit (0.1).
        seed: seed of the episodes, the searches and the minibatches (0).
        judge: what a corrupted episode's search ranks and fails rollouts against
            (:attr:`envs.ArtefactMix.judge`): ``"corrupted"``, the reference the policy observes (as
            ADAPT's reward does), or ``"clean"``, the take it was corrupted from, so that the
            policy learns to perform the clean motion from the corrupted reference.
    """

    rounds: int = 1
    episodes_per_round: int = 256
    search: SearchConfig = field(default_factory=lambda: SearchConfig(beam=8, samples=32))
    drop_windows: int = 2
    epochs: int = 5
    batch_size: int = 512
    lr: float = 1e-4
    holdout: float = 0.1
    seed: int = 0
    judge: str = "corrupted"

    def __post_init__(self) -> None:
        for name in ("rounds", "episodes_per_round", "epochs", "batch_size"):
            if getattr(self, name) < 1:
                raise ValueError(f"ExpertIterationConfig.{name} must be >= 1, got {getattr(self, name)}")
        if self.drop_windows < 0:
            raise ValueError(f"ExpertIterationConfig.drop_windows must be >= 0, got {self.drop_windows}")
        if not 0 <= self.holdout < 1:
            raise ValueError(f"ExpertIterationConfig.holdout must be in [0, 1), got {self.holdout}")
        if self.judge not in SEARCH_JUDGES:
            raise ValueError(f"ExpertIterationConfig.judge must be one of {SEARCH_JUDGES}, got {self.judge!r}")

    def fit_config(self, net: str) -> DistillConfig:
        """The fit's settings as :func:`agents.distill.fit` takes them."""
        return DistillConfig(net=net, epochs=self.epochs, batch_size=self.batch_size, lr=self.lr, seed=self.seed)


@dataclass(frozen=True)
class SearchTask:
    """One episode to search: clean ``motion`` from ``start_frame``, IMU-corrupted at ``strength``
    with ``seed`` (``strength`` ``None``: as it is); ``seed`` also seeds the search."""

    motion: Motion
    start_frame: int
    seed: int
    strength: float | None = None


def issued_actions(episode: Episode, smoothing: float, frames_per_control: int) -> np.ndarray:
    """``(S, A)`` the action (rad, clipped to the action limit) each control step of ``episode``
    issued, recovered from the smoothed actions it recorded: the env applies
    ``smoothing · issued + (1 − smoothing) · previous`` (:func:`envs.mimic.smoothed_action`)."""
    steps = episode.frames // frames_per_control
    applied = episode.actions[1 + frames_per_control * np.arange(steps)]
    before = episode.actions[frames_per_control * np.arange(steps)]
    return (applied - (1.0 - smoothing) * before) / smoothing


def replayed(env: gym.Env, episode: Episode, actions: np.ndarray, tolerance: float = 1e-3) -> np.ndarray:
    """``(K, D)`` the observation before each control step when ``actions (S, A)`` are replayed on
    ``env`` (clip 0) from ``episode``'s start state, for the first ``K <= S`` steps, those that
    start within ``tolerance`` of ``episode``'s state in every ``qpos`` entry (m, rad, or a
    quaternion component). Each of the
    search's windows restarted the simulation from a recorded state, which drops MuJoCo's solver
    warm start, so a replay retraces the lineage only to ~1e-5, and may part from it before a fall."""
    seen: list[np.ndarray] = []

    def act(obs: np.ndarray) -> np.ndarray:
        seen.append(obs)
        return actions[len(seen) - 1]

    fpc = env.unwrapped.config.frames_per_control
    start = episode.start_frame
    again = run_episode(env, act, {"clip": 0, "start_frame": start, "state": episode.state(start)},
                        max_frames=len(actions) * fpc)
    starts = np.arange(0, min(len(seen) * fpc, again.frames + 1), fpc)
    gap = np.abs(again.qpos[starts] - episode.qpos[starts]).max(axis=1)
    kept = int(np.argmax(gap > tolerance)) if (gap > tolerance).any() else len(starts)
    return np.asarray(seen[:kept], dtype=np.float32).reshape(kept, -1)


def search_labels(policy: MimicPolicy, task: SearchTask, config: ExpertIterationConfig) -> dict:
    """Search ``task``'s episode guided by ``policy`` and label the lineage it kept: a dict of
    ``obs (S, D)``, ``actions (S, A)`` (the issued actions), ``values (S,)`` (``policy``'s critic)
    and the search's outcome (``ended_by``, ``frames``, ``labelled``, ``rollouts``)."""
    episode_frames = policy.record.env.mimic_config().episode_frames
    stop = min(task.start_frame + episode_frames, task.motion.n_frames - 1)
    mix = None if task.strength is None else ArtefactMix(strength=(task.strength, task.strength), fraction=1.0,
                                                         variants_per_clip=1, seed=task.seed, judge=config.judge)
    env = policy.make_env([task.motion.held(episode_frames + 2)], artefacts=mix)  # each window may start anywhere
    env.reset(seed=task.seed, options={"clip": 0, "start_frame": task.start_frame})
    base = env.unwrapped
    state = (base.data.qpos.copy(), base.data.qvel.copy(), base.smoothed)
    episode, rollouts = search(env, policy, task.start_frame, state, stop, config.search, np.random.default_rng(task.seed))
    fpc = base.config.frames_per_control
    actions = issued_actions(episode, base.config.action_smoothing, fpc)
    if episode.failed:  # the failed window and the ones that led into it are no example to follow
        window = config.search.window_steps
        actions = actions[:max(0, ((len(actions) - 1) // window - config.drop_windows) * window)]
    obs = replayed(env, episode, actions) if len(actions) else np.zeros((0, env.observation_space.shape[0]), np.float32)
    actions = actions[:len(obs)]
    env.close()
    return {"obs": obs, "actions": actions.astype(np.float32),
            "values": policy.values(obs).astype(np.float32) if len(obs) else np.zeros(0, np.float32),
            "ended_by": episode.ended_by, "frames": episode.frames, "labelled": len(actions), "rollouts": rollouts,
            "clip": task.motion.name}


_worker_policy: MimicPolicy | None = None


def _load_worker(policy_dir: str) -> None:
    global _worker_policy
    torch.set_num_threads(1)
    _worker_policy = load_policy(policy_dir)


def _worker_labels(task: SearchTask, config: ExpertIterationConfig) -> dict:
    return search_labels(_worker_policy, task, config)


def held_out_rmse(student: MimicPolicy, held: Labels) -> float | None:
    """The student's action RMSE (rad) on the held-out labels, rounded to 1e-4 (``None`` when none
    is held out: a run of few episodes)."""
    return round(fit_report(student, held, ["search"])["action_rmse"], 4) if len(held) else None


def draw_tasks(motions: list[Motion], count: int, corrupted_fraction: float, strength: tuple[float, float],
               episode_frames: int, rng: np.random.Generator) -> list[SearchTask]:
    """``count`` episodes: a clip of ``motions`` each (uniformly), to be IMU-corrupted with probability
    ``corrupted_fraction`` at a strength uniform in ``strength``, from a start frame uniform over
    those that leave a whole episode of ``episode_frames`` (frame 0 for a clip shorter)."""
    tasks = []
    for _ in range(count):
        motion = motions[int(rng.integers(len(motions)))]
        seed = int(rng.integers(2**31))
        level = float(rng.uniform(*strength)) if rng.random() < corrupted_fraction else None
        last_start = max(0, motion.n_frames - 1 - episode_frames)
        tasks.append(SearchTask(motion, int(rng.integers(last_start + 1)), seed, level))
    return tasks


def collect(policy_dir: Path, tasks: list[SearchTask], config: ExpertIterationConfig, workers: int,
            first_episode: int, progress: bool = True) -> tuple[Labels, list[dict]]:
    """Search every task guided by the policy in ``policy_dir`` on ``workers`` processes; returns
    the labels (episodes numbered from ``first_episode``) and each search's outcome."""
    results = []
    if workers == 1:
        with torch_threads(1):  # _load_worker's one thread, undone after the searches
            _load_worker(str(policy_dir))
            for task in tqdm(tasks, desc="searching", unit="episode", disable=not progress, leave=False):
                results.append(_worker_labels(task, config))
    else:
        with ProcessPoolExecutor(workers, initializer=_load_worker, initargs=(str(policy_dir),)) as pool:
            jobs = [pool.submit(_worker_labels, task, config) for task in tasks]
            for job in tqdm(jobs, desc="searching", unit="episode", disable=not progress, leave=False):
                results.append(job.result())
    labels = Labels(obs=np.concatenate([r["obs"] for r in results]),
                    actions=np.concatenate([r["actions"] for r in results]),
                    values=np.concatenate([r["values"] for r in results]),
                    teacher=np.zeros(sum(r["labelled"] for r in results), dtype=int),
                    episode=np.concatenate([np.full(r["labelled"], first_episode + i) for i, r in enumerate(results)]))
    outcomes = [{k: r[k] for k in ("clip", "ended_by", "frames", "labelled", "rollouts")} for r in results]
    return labels, outcomes


def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", help="the policy directory the student starts from and the first search follows")
    p.add_argument("--clips", nargs="+", help="training clips: SOURCE strings or clip sets")
    p.add_argument("--exclude", nargs="*", default=[], help="clips to leave out")
    p.add_argument("--mirror", action="store_true", help="also every clip mirrored left/right")
    p.add_argument("--corrupted-fraction", type=fraction, default=0.5, help="share of IMU-corrupted episodes")
    p.add_argument("--strength", type=non_negative_float, nargs=2, default=(0.5, 1.0), metavar=("LOW", "HIGH"))
    defaults = ExpertIterationConfig()
    p.add_argument("--rounds", type=positive_int, default=defaults.rounds)
    p.add_argument("--episodes-per-round", type=positive_int, default=defaults.episodes_per_round)
    p.add_argument("--search-beam", type=positive_int, default=defaults.search.beam)
    p.add_argument("--search-samples", type=positive_int, default=defaults.search.samples)
    p.add_argument("--search-max-drift", type=or_none(positive_float), default=defaults.search.max_drift_m,
                   help="m; a rollout whose root ends a window further from the reference's fails ('none': no limit)")
    p.add_argument("--judge", choices=SEARCH_JUDGES, default=defaults.judge,
                   help="what a corrupted episode's search ranks rollouts against: the corrupted reference the "
                        "policy observes, or the clean take it was made from")
    p.add_argument("--epochs", type=positive_int, default=defaults.epochs)
    p.add_argument("--lr", type=positive_float, default=defaults.lr)
    p.add_argument("--seed", type=int, default=defaults.seed)
    p.add_argument("--workers", type=positive_int, default=1, help="search processes (one per core)")
    p.add_argument("--out", type=output_dir, required=True)
    p.add_argument("--resume", action="store_true", help="continue the run in --out")
    p.add_argument("--no-progress", action="store_true")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the student's directory."""
    argv = sys.argv[1:] if argv is None else argv
    args, history = resumable_run(build_parser(prog), argv, "expert iteration", changeable=("rounds", "workers"))
    out: Path = args.out
    settings = out / "args.json"
    if not args.policy or not args.clips:
        raise ValueError("--policy and --clips are needed (unless --resume)")
    config = ExpertIterationConfig(rounds=args.rounds, episodes_per_round=args.episodes_per_round,
                                   search=SearchConfig(beam=args.search_beam, samples=args.search_samples,
                                                       max_drift_m=args.search_max_drift),
                                   judge=args.judge,
                                   epochs=args.epochs, lr=args.lr, seed=args.seed)
    torch.manual_seed(config.seed)
    teacher = load_policy(args.policy)
    clips = [c for c in expand_clips(args.clips) if c not in set(args.exclude)]
    motions = load_training_motions(clips, FOOT_MODELS[teacher.record.env.foot], args.mirror)
    log_file, data_file, student_dir = out / "log.jsonl", out / "data.npz", out / "student"
    done, labels = finished_rounds(out, "expert_iteration", args.resume)
    student = load_policy(student_dir if done else args.policy)
    if done:
        print(f"resuming after round {len(done) - 1} ({len(labels)} labelled states)", flush=True)
    out.mkdir(parents=True, exist_ok=True)
    args.commands = history + [shlex.join(["python", "agents/expert_iteration.py", *argv])]
    write_json(settings, {**vars(args), "out": str(out)})
    net = teacher.record.ppo.net
    sigma = float(teacher.model.policy.log_std.detach().exp().mean())
    episode_frames = teacher.record.env.mimic_config().episode_frames
    started = time.monotonic() - (done[-1]["wall_s"] if done else 0.0)
    for round_ in range(len(done), config.rounds):
        rng = np.random.default_rng([config.seed, round_])
        tasks = draw_tasks(motions, config.episodes_per_round, args.corrupted_fraction, tuple(args.strength),
                           episode_frames, rng)
        guide = student_dir if round_ else Path(args.policy)
        first_episode = int(labels.episode.max()) + 1 if labels is not None and len(labels) else 0
        new, outcomes = collect(guide, tasks, config, args.workers, first_episode, not args.no_progress)
        labels = new if labels is None else labels + new
        train_rows, held = split_holdout(labels, config.holdout, config.seed)
        before = held_out_rmse(student, held)
        loss = fit(student, labels, config.fit_config(net), sigma, rng, not args.no_progress, rows=train_rows)
        failed = sum(o["ended_by"] in FAILURES for o in outcomes)
        record = {"round": round_, "guided_by": str(guide), "episodes": len(outcomes), "searches_failed": failed,
                  "labelled": len(new), "states": len(labels), "rollouts": sum(o["rollouts"] for o in outcomes),
                  "loss": loss, "held_out_rmse_before": before,
                  "held_out_rmse": held_out_rmse(student, held),
                  "wall_s": time.monotonic() - started}
        labels.save(data_file)
        training = TrainingRecord(clips=clips, corrupted_fraction=args.corrupted_fraction,
                                  strength=tuple(args.strength), judge=config.judge, mirror=args.mirror,
                                  init_from=str(args.policy),
                                  commands=args.commands, seed=config.seed, steps=len(labels),
                                  wall_s=record["wall_s"])
        sidecar = PolicySidecar(env=teacher.record.env, ppo=teacher.record.ppo, training=training, metrics={},
                                extra={"expert_iteration": {"config": asdict(config), "rounds": done + [record]}})
        save_policy(student_dir, student.model, teacher.stats_file, sidecar)
        with open(log_file, "a") as f:
            f.write(json.dumps(record) + "\n")
        done.append(record)
        print(f"[round {round_}] {len(outcomes)} searches ({failed} failed), {len(new)} new labels, {len(labels)} in "
              f"all; held-out action RMSE {before} -> {record['held_out_rmse']} rad; "
              f"{record['wall_s'] / 60:.1f} min", flush=True)
    return student_dir


if __name__ == "__main__":
    main()
