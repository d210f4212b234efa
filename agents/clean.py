"""Clean a clip with a trained mimic policy: the physically simulated re-performance of it.

Usage::

    python agents/clean.py --policy models/mimic_imu deepmimic:walker/turn_left1 --out out/clean.npz \\
        [--corrupt imu --strength 1 --seed 7] [--bvh out/clean.bvh] [--video out/clean.mp4] [--no-adapt]
    python agents/clean.py --method diffpd --policy models/diffpd deepmimic:run --out out/clean.npz [...]
    python agents/clean.py TAKE.bvh --preset imu --out out/clean.npz    # the validated way for an IMU-suit take

``--preset imu`` / ``--preset optical`` stand for the policy and preparation flags validation chose
for an IMU-suit take and for a marker take (:data:`PRESETS`); a value given as well wins, what a
preset turns on cannot be turned off.

``--method diffpd`` tracks the clip with the trained differentiable PD cycle instead
(:mod:`agents.diffpd_clean`: no adaptation, no retries; the same outputs and report).

First the policy is adapted to the clip (PPO fine-tuning on it, :mod:`agents.adaptation`; cached,
so cleaning the same clip again skips it; ``--no-adapt`` re-performs zero-shot). Then the clip
(any length) is simulated in stretches of at most the policy's episode length, each continuing from
the simulated state where the previous one ended, so the result is one continuous motion. Where
the character fails (falls, lags behind the reference, or the simulation blows up), the
simulation rewinds ``--rewind-s`` before the failure to the last good simulated state and tries
that stretch again; only if that fails too does it re-anchor: the simulation restarts from the
reference state at a frame just before where the longest try failed. By default
(``--search all``) every stretch, and every second try, is a policy-guided beam search
(:mod:`agents.search`: per 1/6 s window, ``--search-samples`` rollouts of the policy with seeded
Gaussian action noise, one draw held over the window; rollouts that fall or whose root strays
``--search-max-drift`` from the reference's dropped; the ``--search-beam`` best simulated states
kept, ranked by the reward so far plus the policy's critic's estimate of the return to come; a
search that fails is tried once more without the drift limit before the re-anchor),
which gets through half of the places where the policy alone falls, zero-shot, while keeping
closer to the take's path than the policy alone (``bench/retry_strategies.py``);
``--search retries`` searches only after a failure, ``--search off`` runs the policy alone and
retries with up to ``--retries`` stochastic rollouts of it, keeping the first that gets past. Every output frame is simulated; the re-anchors (frame, reason, retries)
are listed in the output's ``source["reanchors"]``, printed, written with ``--json`` and marked by
a red border in the video, which shows the reference (left) and the result (right).
``--denoise`` first undoes an IMU take's joint-angle and height errors (:mod:`perception.imu_denoiser`),
``--even-legs`` takes out the left-right difference of the legs that the suit's per-hinge offsets most
likely added (:mod:`reference_motion.leg_symmetry`),
``--part-legs`` parts legs that the suit's hip adduction crossed (:mod:`reference_motion.leg_gap`),
``--ground`` then sets the take on the floor (:mod:`reference_motion.grounding`) and ``--swing-lift``
bends its backward steps' knees more in swing (:mod:`reference_motion.swing_lift`); the policy is
adapted to and re-performs the take so prepared (:func:`envs.preparation.prepared`).
``--touch-up`` then removes what the soft contact model leaves (feet sunk into the floor, creeping
contact points) kinematically (:mod:`reference_motion.touch_up`), reporting how far it moved the
body and the simulation's own metrics beside the result's. Before/after artefact metrics are printed.
"""

from __future__ import annotations

import argparse
import sys
from collections import deque
from dataclasses import asdict, dataclass, replace
from pathlib import Path

if __package__ in (None, ""):  # `python agents/clean.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
from tqdm import tqdm

import envs  # noqa: F401  (registers the ids)
from agents.adaptation import KEEP_RULES, MIN_ADAPT_FRAMES, AdaptConfig, AdaptResult, adapt_policy, default_cache_dir
from agents.mirror import actor_label
from agents.policy import MimicPolicy
from agents.policy_set import member_denoiser, route_clips, slowed_members
from agents.rollout import Episode, Policy, run_episode, sampling_policy, seeded, torch_threads
from agents.search import SearchConfig, search
from agents.sidecar import repository_relative
from envs.config import FOOT_MODELS, MODELS_DIR
from envs.preparation import prepared, preparation_of, preparation_record
from perception.imu_denoiser import (DEFAULT_DENOISER, STANCES_DENOISER, SlowCorrections, add_slow_corrections_option,
                                     check_slowing, slowed, slowing_of)
from perception.weights import load_network
from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.atomic import write_json
from reference_motion.bvh_export import write_bvh
from reference_motion.cli import (CliParser, add_mocap_options, fraction, mocap_options, non_negative_float,
                                  non_negative_int, one_line_errors, or_none, output_dir, output_file, positive_float,
                                  positive_int, require_frames)
from reference_motion.grounding import add_grounding_option
from reference_motion.leg_gap import LegGap, add_leg_gap_option
from reference_motion.leg_symmetry import add_leg_symmetry_option
from reference_motion.library import load_motion
from reference_motion.motion import Motion
from reference_motion.quality import ARTEFACT_METRICS, motion_quality
from reference_motion.render import SUPPORTED as VIDEO_SUFFIXES, render
from reference_motion.swing_lift import SwingLift, add_swing_lift_options
from reference_motion.touch_up import TouchUpReport, touch_up

MIN_FRAMES = 3
"""Frames a clip needs to be cleaned (a first frame to start from and two to simulate)."""

METHODS = ("ppo", "diffpd")
"""Cleaning methods of the command line (``--method``)."""

REANCHOR_MARK_S = 0.5
"""How long (s) the video marks the result after each re-anchor."""


SEARCH_MODES = ("all", "retries", "off")
"""``--search``: where :class:`CleanConfig`'s search runs."""


@dataclass(frozen=True)
class CleanConfig:
    """How a clip is re-performed.

    Attributes:
        episode_frames: longest stretch simulated from one reset, in 60 Hz frames (``None``: the
            policy's episode length, 300 for the shipped ones).
        rewind_s: how far before a failure (s) the second try restarts (1.0; chosen on the
            validation takes with ``bench/retry_strategies.py``).
        retries: with ``search=None``: stochastic rollouts of the policy tried from there before
            re-anchoring (4).
        seed: seed of the first stochastic retry, each further retry of the clip taking the next
            one; and of the search's action noise (0).
        search: the policy-guided search (:func:`agents.search.search`, these settings) that
            performs every stretch and, from the rewound state to ``rewind_s`` past a failure,
            the second try (default :class:`~agents.search.SearchConfig`); ``None``: the policy's
            deterministic action, then ``retries`` stochastic retries.
        search_retries_only: perform the stretches with the policy alone and search only after a
            failure (False).
    """

    episode_frames: int | None = None
    rewind_s: float = 1.0
    retries: int = 4
    seed: int = 0
    search: SearchConfig | None = SearchConfig()
    search_retries_only: bool = False

    @property
    def searches_everywhere(self) -> bool:
        """Whether every stretch is performed by the search."""
        return self.search is not None and not self.search_retries_only

    def rewind_frames(self, fps: float, frames_per_control: int, episode_frames: int) -> int:
        """:attr:`rewind_s` in frames at ``fps``: at least one control step, less than an episode
        of ``episode_frames``."""
        frames = max(frames_per_control, int(round(self.rewind_s * fps)))
        if frames >= episode_frames:
            raise ValueError(f"--rewind-s {self.rewind_s} is {frames} frames, not less than an episode "
                             f"({episode_frames} frames)")
        return frames


POLICY_ALONE = CleanConfig(rewind_s=0.5, search=None)
"""``clean.py --search off --rewind-s 0.5``: the policy's own action, then 4 stochastic retries
after a failure (the default before the search; about 1/30 of its cost). The adaptation ranks
its chunks with it, and the benchmarks measured before the search use it."""


@dataclass(frozen=True)
class Reanchor:
    """A place where the simulation restarted from the reference state.

    Attributes:
        frame: the frame restarted from the reference state.
        reason: how the policy failed: ``"fallen"``, ``"lagging"`` or ``"unstable"``.
        retries: stochastic retries (or search rollouts) tried (all failed).
        failed_at: frame where the deterministic policy failed.
        best_reached: frame where the longest-surviving attempt failed.
        jump_m: distance (m) the root jumped from the simulated to the reference state (``None``
            when the simulated state was not finite).
    """

    frame: int
    reason: str
    retries: int
    failed_at: int
    best_reached: int
    jump_m: float | None


@dataclass(frozen=True)
class Recovery:
    """A failure a stochastic retry got past.

    Attributes:
        frame: the frame rewound to; failed_at: where the policy had failed; reason: how.
        retries: retries (or search rollouts) it took.
    """

    frame: int
    failed_at: int
    reason: str
    retries: int


class StateRing:
    """The simulated states of the last ``capacity`` committed frames, by reference frame: where a
    retry can rewind to."""

    def __init__(self, capacity: int):
        self._states: deque[tuple[int, tuple[np.ndarray, ...]]] = deque(maxlen=capacity)

    def push(self, frame: int, *state: np.ndarray) -> None:
        """Append the state of ``frame``, the frame after the newest: ``qpos (nq,), qvel (nv,)`` and
        optionally the smoothed action in effect ``(A,)`` (reset option ``state``)."""
        if self._states and frame != self._states[-1][0] + 1:
            raise ValueError(f"frame {frame} does not follow the newest frame {self._states[-1][0]}")
        self._states.append((frame, state))

    def drop_after(self, frame: int) -> None:
        """Forget the states of the frames after ``frame``."""
        while self._states and self._states[-1][0] > frame:
            self._states.pop()

    def state(self, frame: int) -> tuple[np.ndarray, ...]:
        """The state of ``frame`` as pushed (copies); ``KeyError`` when it is not (or no longer) held."""
        for f, state in reversed(self._states):
            if f == frame:
                return tuple(x.copy() for x in state)
        raise KeyError(f"frame {frame} is not in the state ring")


class _Performance:
    """One re-performance of ``reference`` by ``policy`` (:func:`clean_motion`): the committed
    simulated frames, the ring of their recent states, the re-anchors and the recoveries."""

    def __init__(self, policy: MimicPolicy, reference: Motion, config: CleanConfig):
        task = policy.record.env.mimic_config()
        self.episode_frames = config.episode_frames or task.episode_frames
        self.config = config
        self.last = reference.n_frames - 1
        # hold the last frame for one more episode so any stretch can start at any frame of the clip
        self.env = policy.make_env([reference.held(self.episode_frames + 2)], artefacts=None,
                                   episode_frames=self.episode_frames)
        self.policy = policy
        self.sample: Policy = sampling_policy(policy)
        self.rewind = config.rewind_frames(reference.fps, task.frames_per_control, self.episode_frames)
        self.qpos = np.full_like(reference.qpos, np.nan)
        """``(T, nq)`` the committed simulated frames."""
        self.frames_per_control = task.frames_per_control
        self.rewards = np.full(reference.n_frames, np.nan)
        """``(T,)`` the reward of the control step that simulated each committed frame (NaN: a frame
        started from the reference state)."""
        self.max_step_reward = float(self.env.unwrapped.max_step_reward)
        self.ring = StateRing(self.rewind + 1)
        self.anchor = 0
        """The latest frame started from the reference state: retries never rewind past it."""
        self.reanchors: list[Reanchor] = []
        self.recoveries: list[Recovery] = []
        self.tries = 0
        self.rng = np.random.default_rng(config.seed)
        """The search's action noise."""

    # ------------------------------------------------------------ pieces
    def _commit(self, episode: Episode, first: int, last: int) -> None:
        """Keep ``episode``'s frames ``first..last`` (clamped to the episode) as the result, replacing
        any later ones."""
        first = max(first, episode.start_frame)
        if last < first:
            return
        self.ring.drop_after(first - 1)
        for f in range(first, last + 1):
            state = episode.state(f)
            self.qpos[f] = state[0]
            self.ring.push(f, *state)
            if f > episode.start_frame:  # the start state keeps the reward of the step that reached it
                self.rewards[f] = episode.rewards[(f - episode.start_frame - 1) // self.frames_per_control]

    def _run(self, start: int, stop: int, policy: Policy) -> Episode:
        """``policy`` from the committed simulated state of ``start`` until ``stop`` or a failure."""
        return run_episode(self.env, policy, {"clip": 0, "start_frame": start, "state": self.ring.state(start)},
                           max_frames=stop - start)

    @staticmethod
    def _survived(episode: Episode, stop: int) -> bool:
        """Whether ``episode`` reached ``stop`` (a failure in the step that passes it counts as reached)."""
        return not episode.failed or episode.end_frame > stop

    def _anchor_at(self, frame: int) -> None:
        """Restart from the reference state of ``frame`` (lifted above the floor if it reaches into it)."""
        self._commit(run_episode(self.env, self.policy, {"clip": 0, "start_frame": frame}, max_frames=0), frame, frame)
        self.rewards[frame] = np.nan
        self.anchor = frame

    def reward_ratio(self) -> float:
        """The mean over the committed frames simulated by a control step of that step's reward,
        over the most a step can earn (like ADAPT's MRR, but over the frames simulated, not the
        reference's length; NaN when no frame was simulated)."""
        simulated = self.rewards[np.isfinite(self.rewards)]
        return float(simulated.mean() / self.max_step_reward) if simulated.size else float("nan")

    # ------------------------------------------------------------ the algorithm
    def perform(self, progress: bool) -> None:
        """Simulate the whole clip into :attr:`qpos`."""
        bar = tqdm(total=self.last, desc="cleaning", unit="frame", disable=not progress)
        self._anchor_at(0)
        done = 0  # frames 0..done are committed
        while done < self.last:
            stop = min(done + self.episode_frames, self.last)
            if self.config.searches_everywhere:
                episode, _ = self._search_from(done, stop)
            else:
                episode = self._run(done, stop, self.policy)
            if self._survived(episode, stop):
                self._commit(episode, done, stop)
                done = stop
            else:
                done = self._retry(episode)
            bar.update(max(0, done - bar.n))
            bar.set_postfix(reanchors=len(self.reanchors), recoveries=len(self.recoveries))
        bar.close()
        self.env.close()

    def _retry(self, failed: Episode) -> int:
        """After ``failed`` (the deterministic policy from the last committed frame) failed: rewind,
        retry, else re-anchor. Returns the new last committed frame."""
        fail, reason = failed.end_frame, failed.ended_by
        rewound = max(self.anchor, fail - self.rewind)
        self._commit(failed, failed.start_frame, rewound)  # the good part, when it reaches that far
        goal = min(fail + self.rewind, self.last)
        if self.config.search is not None:
            return self._search(failed, rewound, goal)
        best = failed
        for k in range(1, self.config.retries + 1):
            with seeded(self.config.seed + self.tries):
                attempt = self._run(rewound, goal, self.sample)
            self.tries += 1
            if self._survived(attempt, goal):
                return self._recovered(attempt, rewound, goal, failed, k)
            if attempt.end_frame > best.end_frame:
                best = attempt
        return self._reanchor(best, rewound, fail, reason, self.config.retries)

    def _search(self, failed: Episode, rewound: int, goal: int) -> int:
        """After ``failed`` failed: search from the committed state of ``rewound`` to ``goal``, else
        re-anchor. Returns the new last committed frame."""
        attempt, rollouts = self._search_from(rewound, goal)
        if not self._survived(attempt, goal) and self.config.search.max_drift_m is not None:
            # the drift limit is the search's own (the task ends an episode further off): before
            # re-anchoring, search again without it
            unlimited, more = self._search_from(rewound, goal, replace(self.config.search, max_drift_m=None))
            rollouts += more
            if unlimited.end_frame > attempt.end_frame:
                attempt = unlimited
        if self._survived(attempt, goal):
            return self._recovered(attempt, rewound, goal, failed, rollouts)
        best = attempt if attempt.end_frame > failed.end_frame else failed
        return self._reanchor(best, rewound, failed.end_frame, failed.ended_by, rollouts)

    def _search_from(self, frame: int, stop: int, config: SearchConfig | None = None) -> tuple[Episode, int]:
        """The search's simulation (``config``, default the cleaning's) from the committed state of
        ``frame`` towards ``stop`` and the rollouts it took (counted in :attr:`tries`)."""
        episode, rollouts = search(self.env, self.policy, frame, self.ring.state(frame), stop,
                                   config or self.config.search, self.rng)
        self.tries += rollouts
        return episode, rollouts

    def _recovered(self, attempt: Episode, rewound: int, goal: int, failed: Episode, tries: int) -> int:
        """Commit ``attempt`` (from ``rewound``, past the failure of ``failed``) up to ``goal`` and
        record the recovery, which took ``tries``. Returns the new last committed frame."""
        end = min(attempt.end_frame, goal)
        self._commit(attempt, rewound, end)
        self.recoveries.append(Recovery(frame=rewound, failed_at=failed.end_frame, reason=failed.ended_by,
                                        retries=tries))
        return end

    def _reanchor(self, best: Episode, rewound: int, fail: int, reason: str, retries: int) -> int:
        """Keep ``best`` (the longest-surviving attempt) up to ``rewind`` frames before its failure
        (but at least that far past the last anchor, so the clip advances), then restart there
        from the reference state. Returns the re-anchored frame."""
        frame = min(max(best.end_frame - self.rewind, self.anchor + self.rewind), best.end_frame, self.last)
        finite = np.isfinite(best.qpos).all(axis=1) & np.isfinite(best.qvel).all(axis=1)
        if not finite.all():  # "unstable": keep only the frames before the simulation blew up
            frame = min(frame, best.start_frame + int(np.argmin(finite)))
        self._commit(best, rewound, frame - 1)
        simulated = best.qpos[frame - best.start_frame] if frame >= best.start_frame else self.qpos[frame]
        self._anchor_at(frame)
        jump = float(np.linalg.norm(simulated[:3] - self.qpos[frame, :3]))
        self.reanchors.append(Reanchor(frame=frame, reason=reason, retries=retries, failed_at=fail,
                                       best_reached=best.end_frame, jump_m=jump if np.isfinite(jump) else None))
        return frame


def clean_motion(policy: MimicPolicy, reference: Motion, config: CleanConfig = CleanConfig(),
                 progress: bool = True) -> Motion:
    """The simulated re-performance of ``reference`` (60 Hz, same length, at least
    :data:`MIN_FRAMES`) by ``policy`` (see the module's documentation).

    The result's ``source`` adds ``cleaned_by`` (:attr:`~agents.policy.MimicPolicy.name`: the policy's
    directory, or a run's checkpoint by its file; marked when it acts as its mirror-symmetric
    actor: :func:`agents.mirror.actor_label`), ``reanchors`` and
    ``recoveries`` (lists of :class:`Reanchor` / :class:`Recovery` as dicts) and
    ``simulated_fraction``: the share of frame-to-frame transitions that are physics steps, i.e.
    ``1 − re-anchors / (frames − 1)`` (1.0: one continuous simulation from the first frame), and
    ``reward_ratio``: the policy's task reward over the whole performance, as a share of the most a
    control step can earn (each simulated frame counts the reward of the step that simulated it),
    and ``clean_config``: ``config`` as a dict.
    """
    require_frames(reference, MIN_FRAMES, reference.name, "cleaning")
    performance = _Performance(policy, reference, config)
    with torch_threads(1):  # one observation at a time: more threads only wait on each other
        performance.perform(progress)
    out = performance.qpos
    if not np.isfinite(out).all():  # every frame is committed from a finite simulated state
        raise RuntimeError(f"cleaning {reference.name}: frames {np.flatnonzero(~np.isfinite(out).all(axis=1))} "
                           "were left without a simulated state")
    source = {**reference.source, "cleaned_by": actor_label(policy.name, policy.mirror is not None),
              "reanchors": [asdict(r) for r in performance.reanchors],
              "recoveries": [asdict(r) for r in performance.recoveries],
              "simulated_fraction": 1.0 - len(performance.reanchors) / performance.last,
              "clean_config": asdict(config),
              "reward_ratio": performance.reward_ratio()}
    return reference.with_qpos(out, name=f"{reference.name} (cleaned)", loop=False, source=source)


def reanchor_frames(cleaned: Motion) -> list[int]:
    """The frames of ``cleaned`` (a :func:`clean_motion` result) restarted from the reference state."""
    return [r["frame"] for r in cleaned.source.get("reanchors", [])]


def touched_up(cleaned: Motion, **settings) -> tuple[Motion, TouchUpReport]:
    """``cleaned`` (a :func:`clean_motion` result) with the contact touch-up
    (:func:`reference_motion.touch_up.touch_up`, its ``smooth_s`` / ``pinning`` in ``settings``),
    each stretch between its re-anchors on its own, and the report of what moved."""
    return touch_up(cleaned, reanchor_frames(cleaned), **settings)


def reanchor_marks(cleaned: Motion, seconds: float = REANCHOR_MARK_S) -> np.ndarray:
    """``(T,)`` bool: the frames of ``cleaned`` within ``seconds`` after a re-anchor (for the video)."""
    marked = np.zeros(cleaned.n_frames, dtype=bool)
    span = max(1, int(round(seconds * cleaned.fps)))
    for frame in reanchor_frames(cleaned):
        marked[frame:frame + span] = True
    return marked


@dataclass(frozen=True)
class CleanPreset:
    """A validated way to clean one kind of take (``--preset``): the policy and the take's
    preparation that validation chose for it (README, the main job's table), as the command-line
    values they stand for. A value given on the command line wins over the preset's; what a preset
    turns on (a denoiser, its slowing, evening, parting, grounding, the lift, the mirror average,
    ``--no-adapt``) cannot be turned off: give the flags yourself instead of the preset.

    Attributes:
        policy: the policy directory (``--policy``).
        denoise: the IMU denoiser (``--denoise``); ``None``: none.
        denoise_slow: seconds of ``--denoise-slow``; ``None``: the denoiser's whole correction.
        even_legs: ``--even-legs``.
        part_legs: ``--part-legs``'s smallest median sideways gap of the feet (m), below which
            the legs are parted; ``None``: not parted.
        ground: ``--ground``.
        swing_lift: the knee angle (deg) of ``--swing-lift``; ``None``: no lift.
        mirror_average: ``--mirror-average``.
        no_adapt: ``--no-adapt`` (zero-shot: the presets' actors were chosen zero-shot).
    """

    policy: Path
    denoise: Path | None = None
    denoise_slow: float | None = None
    even_legs: bool = False
    part_legs: float | None = None
    ground: bool = True
    swing_lift: float | None = SwingLift.knee_deg
    mirror_average: bool = True
    no_adapt: bool = True


PRESETS: dict[str, CleanPreset] = {
    # an IMU-suit take: the row "behind the IMU denoiser" (DXSSET: LSS with the backward, dash, fast, sideways and
    # turning experts BXS2R, DXS, FXS, SX and TX2, rounds 35-44, behind the denoiser SQ's full corrections, round 46;
    # its policy_set.json keeps the dash expert's takes behind the slow ones, round 48)
    "imu": CleanPreset(policy=MODELS_DIR / "mimic_general_expert_set", denoise=STANCES_DENOISER,
                       even_legs=True, part_legs=LegGap.min_gap_m),
    # an optical (marker) take: the clean row's choice (G, "A symmetric actor", "Round 9")
    "optical": CleanPreset(policy=MODELS_DIR / "mimic_general_stance_avg"),
}
"""``--preset NAME``: :class:`CleanPreset` of each kind of take."""


def cleans_as_preset(args: argparse.Namespace) -> bool:
    """Whether ``args`` (:func:`parse_clean_args`) name a ``--preset`` and prepare and perform a take as it
    says: none of its values given otherwise (a path to the same directory counts as the same), and the
    swing lift read as the presets read it (no ``--swing-from``)."""
    if args.preset is None or args.swing_from is not None:
        return False

    def same(given: object, value: object) -> bool:
        if isinstance(value, Path) and given is not None:
            return Path(given).resolve() == value.resolve()
        return given == value

    return all(same(getattr(args, name), value) for name, value in asdict(PRESETS[args.preset]).items())


def parse_clean_args(parser: CliParser, argv: list[str] | None) -> argparse.Namespace:
    """``argv`` (default: ``sys.argv[1:]``) parsed by ``parser`` (:func:`build_parser`), the values of
    its ``--preset`` (:data:`PRESETS`) filling what the command line leaves out; a bad combination
    is the parser's error (no ``--policy`` and no preset; a preset with ``--method diffpd``)."""
    first = CliParser(prog=parser.prog, add_help=False)
    first.add_argument("--preset", choices=sorted(PRESETS))
    known, _ = first.parse_known_args(argv)
    if known.preset is not None:
        parser.set_defaults(**asdict(PRESETS[known.preset]))
    args = parser.parse_args(argv)
    if args.policy is None:
        parser.error("the following arguments are required: --policy (or --preset)")
    if args.preset is not None and args.method != "ppo":
        parser.error(f"--preset {args.preset} cleans with a PPO policy; it goes with --method ppo")
    return args


def build_parser(prog: str | None = None, method: bool = True) -> CliParser:
    """The command line of ``agents/clean.py`` (parse it with :func:`parse_clean_args`, which applies
    ``--preset`` and requires ``--policy`` when no preset gives it); ``method=False`` leaves out
    ``--preset``, ``--method`` and ``--touch-up`` (for a command that re-performs with a PPO policy
    only and reports the simulation itself, such as ``agents/reconstruct_gait.py``)."""
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0],
                  formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("source", help="deepmimic:NAME, library:DIR#TAKE, or a .npz / .bvh / .amc / .txt file")
    add_mocap_options(p)
    if method:
        p.add_argument("--preset", choices=sorted(PRESETS),
                       help="clean with the policy and preparation validation chose for this kind of take: imu, an "
                            "IMU-suit take (the policy set models/mimic_general_expert_set, its backward, dash, fast, "
                            "sideways and turning takes to its experts, behind the stance-trained IMU denoiser's "
                            "corrections, the dash expert's takes behind their slow part, legs evened and parted, "
                            "grounded, swing-lifted, mirror-averaged, zero-shot); optical, a marker "
                            "take (models/mimic_general_stance_avg, grounded, swing-lifted, mirror-averaged, zero-shot). "
                            "A value given as well wins; what the preset turns on cannot be turned off (give the flags "
                            "instead)")
        p.add_argument("--method", choices=METHODS, default="ppo",
                       help="ppo: a mimic policy re-performs the clip (--policy: its directory); diffpd: the "
                            "differentiable PD cycle tracks it (--policy: a diff-PD model directory, e.g. "
                            "models/diffpd; agents/diffpd_clean.py)")
    p.add_argument("--policy", required=not method,
                   help="policy directory (model.zip, model_vecnormalize.pkl, sidecar.json), or a policy set "
                        "(policy_set.json: a policy per motion class); with --method diffpd a diff-PD model "
                        "directory (diffpd.pt)" + ("; or given by --preset" if method else ""))
    p.add_argument("--out", type=output_file(".npz"), required=True, help="cleaned motion (.npz)")
    p.add_argument("--bvh", type=output_file(".bvh"), help="also write the cleaned motion as BVH")
    p.add_argument("--video", type=output_file(*VIDEO_SUFFIXES),
                   help="side-by-side video (.mp4/.gif; .png: first frame): reference | cleaned, re-anchors "
                        "framed in red")
    p.add_argument("--min-frames", type=non_negative_int, help="loop a cyclic clip to at least this many 60 Hz frames")
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS, help="corrupt the clip with IMU artefacts first")
    p.add_argument("--strength", type=non_negative_float, default=1.0)
    p.add_argument("--seed", type=int, default=0, help="artefact seed")
    p.add_argument("--json", type=output_file(".json"), help="write the before/after metrics as JSON")
    if method:
        p.add_argument("--denoise", nargs="?", const=DEFAULT_DENOISER, type=Path, metavar="DIR",
                       help="an IMU take: undo its joint-angle and height errors with the IMU denoiser "
                            "(perception/imu_denoiser.py; DIR default: models/imu_denoiser_soles_quint_mirror, "
                            "validation's choice until stop 75; --preset imu uses "
                            "models/imu_denoiser_stances_quint_mirror) before the policy is "
                            "adapted to it and re-performs it; the input metrics and the video's left side "
                            "stay the take as given")
        add_slow_corrections_option(p)
        add_leg_symmetry_option(p, "the policy is adapted to the take with its legs evened and re-performs it")
        add_leg_gap_option(p, "the policy is adapted to the take with its legs parted and re-performs it")
        add_grounding_option(p, "the policy is adapted to the grounded take and re-performs it")
        add_swing_lift_options(p, "the policy is adapted to the lifted take and re-performs it, so the simulated "
                                  "swing foot does not drag on the floor")
        p.add_argument("--mirror-average", action="store_true",
                       help="re-perform with the policy's mirror-symmetric actor (agents/mirror.py: the mean of its "
                            "action and, mapped back, its action on the mirrored observation), after any adaptation; "
                            "measured best with --no-adapt (after adaptation its retries re-anchor more)")
        p.add_argument("--touch-up", action="store_true",
                       help="after the simulation, lift the body out of the floor where soft contacts let it sink "
                            "and pin planted feet with leg IK (reference_motion.touch_up); the output and the "
                            "'cleaned' metrics are then the touched-up clip, the simulation's own metrics and how "
                            "far the bodies moved are reported beside them")
    add_performance_options(p)
    return p


sr90_target = or_none(fraction)
"""``--adapt-target``: a fraction (stop adapting at that SR90), or ``none`` (train to the budget)."""


def add_performance_options(p: argparse.ArgumentParser) -> None:
    """The options of how a clip is re-performed (failures, per-clip adaptation), shared by every
    command that cleans a clip with a policy; read back by :func:`clean_config` and :func:`adapt_to_clip`."""
    g = p.add_argument_group("search and failures")
    g.add_argument("--search", choices=SEARCH_MODES, default="all",
                   help="where the policy-guided search runs: every stretch (all), only after a failure "
                        "(retries), nowhere (off: the policy alone, then --retries stochastic retries)")
    g.add_argument("--search-beam", type=positive_int, default=SearchConfig.beam,
                   help="simulated states the search keeps after each window")
    g.add_argument("--search-samples", type=positive_int, default=SearchConfig.samples,
                   help="rollouts per search window (cleaning then takes about half this many times as long as with the "
                        "policy alone)")
    g.add_argument("--search-noise", type=non_negative_float, default=SearchConfig.noise,
                   help="the search's action noise, times the policy's own exploration sigma")
    g.add_argument("--search-noise-per-step", action="store_true",
                   help="draw the search's action noise anew each control step, not once per rollout")
    g.add_argument("--search-value", type=non_negative_float, default=SearchConfig.value_weight,
                   help="weight of the policy's critic (its estimate of the return still to come) when the search "
                        "ranks the states it reached; 0: the reward so far alone")
    g.add_argument("--search-max-drift", type=or_none(positive_float), default=SearchConfig.max_drift_m,
                   help="a search rollout whose root ends further than this (m, horizontally) from the reference's "
                        "fails; 'none': only the task's own failures (the body may then trail the take's path)")
    g.add_argument("--rewind-s", type=positive_float, default=CleanConfig.rewind_s,
                   help="after a failure, try again from this long before it (s)")
    g.add_argument("--retries", type=non_negative_int, default=CleanConfig.retries,
                   help="with --search off: stochastic retries before re-anchoring to the reference")
    p.add_argument("--physics-rate-hz", type=positive_float, default=None, metavar="HZ",
                   help="adapt and perform with the physics stepped at this rate, a multiple of 60 "
                        "(MimicConfig.physics_rate_hz: finer steps, stiffer contacts, so soles sink and slide less; "
                        "default: the rate the policy trained at, recorded in its sidecar)")
    p.add_argument("--steer-gain", type=non_negative_float, default=None, metavar="HZ",
                   help="adapt and perform with the observed reference velocities steered back onto the take's "
                        "position at this rate, 1/s (MimicConfig.steer_gain_hz: the body keeps closer to the take's "
                        "path; default: the gain the policy trained with, recorded in its sidecar)")
    g = p.add_argument_group("per-clip adaptation (PPO fine-tuning on the clip before cleaning)")
    g.add_argument("--no-adapt", action="store_true", help="clean with the policy as given (zero-shot)")
    g.add_argument("--adapt-budget-s", type=positive_float, default=AdaptConfig.budget_s,
                   help="wall-time budget of the adaptation (s)")
    g.add_argument("--adapt-target", type=sr90_target, default=AdaptConfig.target_sr90,
                   help="stop adapting once SR90 on the clip reaches this; 'none': use the whole budget, "
                        "keeping the chunk ranked best by --adapt-keep")
    g.add_argument("--adapt-steps", type=positive_int, default=None, help="most environment steps (None: no limit)")
    g.add_argument("--adapt-variance", type=or_none(positive_float), default=AdaptConfig.action_variance,
                   help="exploration noise sigma^2 (rad^2) while adapting; 'none': the policy's own")
    g.add_argument("--adapt-lr", type=or_none(positive_float), default=AdaptConfig.learning_rate,
                   help="PPO learning rate while adapting; 'none': the policy's own")
    g.add_argument("--adapt-keep", choices=KEEP_RULES, default=AdaptConfig.keep,
                   help="which chunk is kept: the best evaluation (SR90, ELR, reward ratio over rollouts from "
                        "reference states), or the best performance of the whole clip (fewest re-anchors, "
                        "then fewest recoveries, then the highest reward ratio; --adapt-target then also needs "
                        "the clip performed with no re-anchor)")
    g.add_argument("--adapt-chunk", type=positive_int, default=AdaptConfig.chunk_steps,
                   help="environment steps between evaluations")
    g.add_argument("--adapt-cache", type=output_dir, default=None,
                   help=f"where adapted policies are cached (None: {default_cache_dir()})")


def load_clip(model: str, args: argparse.Namespace) -> Motion:
    """The clip of ``args.source`` for humanoid ``model`` (e.g. ``FOOT_MODELS[policy.foot]``), looped
    to ``--min-frames`` and corrupted as ``--corrupt`` asks (the options of :func:`build_parser`)."""
    reference = require_frames(load_motion(args.source, model, min_frames=args.min_frames,
                                           mocap=mocap_options(args)),
                               MIN_FRAMES, args.source, "cleaning")
    if args.corrupt:
        reference = corrupt(reference, ArtefactRecipe.named(args.corrupt, args.strength), args.seed)
    return reference


def print_performance(cleaned: Motion, out: Path) -> None:
    """Print how ``cleaned`` (written to ``out``) was simulated: its simulated fraction, the
    recoveries and every re-anchor."""
    source = cleaned.source
    searched = (source.get("clean_config") or {}).get("search") is not None
    tries = "search rollouts" if searched else "retries"
    print(f"wrote {out} ({cleaned.n_frames} frames, all simulated; simulated fraction "
          f"{source['simulated_fraction']:.4f}: {len(source['recoveries'])} failures recovered by "
          f"{'a second search' if searched else 'a retry'}, {len(source['reanchors'])} re-anchored to the reference)")
    for r in source["reanchors"]:
        jump = f", root jumped {r['jump_m']:.2f} m" if r["jump_m"] is not None else ""
        print(f"  re-anchored at frame {r['frame']} ({r['frame'] / cleaned.fps:.2f} s): {r['reason']} at frame "
              f"{r['failed_at']}, {r['retries']} {tries} failed (best reached frame {r['best_reached']}){jump}")


def performing_policy(policy: MimicPolicy, args: argparse.Namespace) -> MimicPolicy:
    """``policy`` at the physics rate ``--physics-rate-hz`` asks for (:meth:`MimicPolicy.simulating`)
    and with the steering gain ``--steer-gain`` asks for (:meth:`MimicPolicy.steering`), or as it is."""
    if args.physics_rate_hz:
        policy = policy.simulating(args.physics_rate_hz)
    return policy if args.steer_gain is None else policy.steering(args.steer_gain)


def clean_config(policy: MimicPolicy, reference: Motion, args: argparse.Namespace) -> CleanConfig:
    """The :class:`CleanConfig` of the command line, checked against ``policy``'s task before any work."""
    search = None if args.search == "off" else SearchConfig(beam=args.search_beam, samples=args.search_samples,
                                                             noise=args.search_noise, value_weight=args.search_value,
                                                             hold_noise=not args.search_noise_per_step,
                                                             max_drift_m=args.search_max_drift)
    config = CleanConfig(rewind_s=args.rewind_s, retries=args.retries, search=search,
                         search_retries_only=args.search == "retries")
    task = policy.record.env.mimic_config()
    config.rewind_frames(reference.fps, task.frames_per_control, task.episode_frames)
    return config


def adapt_to_clip(policy: MimicPolicy, reference: Motion, args: argparse.Namespace) -> AdaptResult | None:
    """The policy adapted to ``reference`` as the command line asks, printed; ``None`` without."""
    if args.no_adapt:
        return None
    if reference.n_frames < MIN_ADAPT_FRAMES:
        print(f"not adapting: {reference.n_frames} frames, adaptation needs {MIN_ADAPT_FRAMES}; cleaning zero-shot")
        return None
    config = AdaptConfig(budget_s=args.adapt_budget_s, target_sr90=args.adapt_target, max_steps=args.adapt_steps,
                         chunk_steps=args.adapt_chunk, action_variance=args.adapt_variance, learning_rate=args.adapt_lr,
                         keep=args.adapt_keep, cache_dir=args.adapt_cache or default_cache_dir())
    result = adapt_policy(policy, reference, config)
    how = "reused from the cache" if result.cached else f"stopped by {result.stopped_by}"
    print(f"adapted {policy.name} to the clip: SR90 {result.sr90_before:.2f} -> {result.sr90_after:.2f}, "
          f"ELR {result.elr_before:.2f} -> {result.elr_after:.2f}, {result.steps} steps in {result.wall_s:.0f} s "
          f"({how}; {result.path})")
    return result


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> dict:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the before/after metrics."""
    parser = build_parser(prog)
    args = parse_clean_args(parser, argv)
    if args.method == "ppo":  # with diffpd --denoise-slow is refused below, as every preparation is
        check_slowing(args.denoise, args.denoise_slow)
    steps = preparation_of(args)
    lift, grounding, legs, symmetry = steps["lift"], steps["grounding"], steps["legs"], steps["symmetry"]
    adaptation, extra, own_slowing = None, {}, {}
    if args.method == "diffpd":
        given = [flag for flag, on in (("--denoise", args.denoise), ("--denoise-slow", args.denoise_slow),
                                       ("--even-legs", symmetry), ("--part-legs", legs),
                                       ("--ground", args.ground),
                                       ("--swing-lift", args.swing_lift),
                                       ("--mirror-average", args.mirror_average)) if on]
        if given:
            parser.error(f"{' and '.join(given)} go{'es' if len(given) == 1 else ''} with --method ppo")
        from agents.diffpd_clean import clean_from_args  # torch cycle only when asked for

        reference, cleaned, extra = clean_from_args(args, parser)
    else:
        [(policy, [reference])] = route_clips(args.policy, lambda foot: [load_clip(FOOT_MODELS[foot], args)])
        whole = slowed(load_network(args.denoise, "denoiser") if args.denoise else None, args.denoise_slow)
        denoiser = member_denoiser(args.policy, policy, whole)  # a set may slow its member's corrections its own way
        own_slowing = slowed_members({policy.name: denoiser}, whole)
        policy = performing_policy(policy, args)
        config = clean_config(policy, reference, args)
        # a preset's preparation is what validation chose for its policies as they were trained (round 46 gives the
        # IMU preset's members the denoiser's full corrections): the note is for preparations chosen otherwise
        note = None if cleans_as_preset(args) else policy.preparation_note(args.denoise, **steps,
                                                                             denoise_slow_s=slowing_of(denoiser))
        if note:
            print(note)
        performed = prepared(reference, denoiser, **steps)
        slowly = f" ({denoiser.label})" if isinstance(denoiser, SlowCorrections) else ""
        applied = [step for step, on in ((f"denoised with {args.denoise}{slowly}", denoiser),
                                       (symmetry.label if symmetry else "", symmetry), (legs.label if legs else "", legs),
                                       ("set on the floor", grounding), (lift.label if lift else "", lift)) if on]
        if applied:
            hinges = np.degrees(np.abs(performed.hinges - reference.hinges)).mean()
            height = 100 * np.abs(performed.root_pos[:, 2] - reference.root_pos[:, 2]).mean()
            print(f"{', '.join(applied)}: hinges moved {hinges:.2f}° on average, pelvis height {height:.1f} cm")
        adaptation = adapt_to_clip(policy, performed, args)
        performer = adaptation.policy if adaptation else policy
        if args.mirror_average:
            performer = performer.mirror_averaged_on(performed)
        cleaned = clean_motion(performer, performed, config)
    touch = None
    if args.touch_up:
        simulated_quality = motion_quality(cleaned).as_dict()
        cleaned, report = touched_up(cleaned)
        touch = {**report.as_dict(), "simulated": simulated_quality}
    cleaned.save(args.out)
    before, after = motion_quality(reference).as_dict(), motion_quality(cleaned).as_dict()
    print(f"{'metric':<24}{'input':>12}{'cleaned':>12}")
    for k in ARTEFACT_METRICS:
        print(f"{k:<24}{before[k]:>12.4f}{after[k]:>12.4f}")
    print_performance(cleaned, args.out)
    if touch:
        print(f"touched up: root lifted up to {touch['lift_max_m'] * 100:.1f} cm (mean {touch['lift_mean_m'] * 100:.2f} cm), "
              f"bodies moved {touch['body_shift_mean_m'] * 100:.2f} cm on average, at most "
              f"{touch['body_shift_max_m'] * 100:.1f} cm (simulated: foot skate {touch['simulated']['foot_skate_mps']:.4f} "
              f"m/s, penetration max {touch['simulated']['penetration_max_m']:.4f} m)")
    source = cleaned.source
    if args.bvh:
        print(f"wrote {write_bvh(cleaned, args.bvh)}")
    if args.video:
        marked = [None, reanchor_marks(cleaned)]  # the result framed in red after each re-anchor
        print(f"wrote {render([reference, cleaned], args.video, marked=marked, progress=True)}")
    result = {"source": args.source, "policy": repository_relative(args.policy), "preset": args.preset,
              "cleaned_by": source["cleaned_by"],
              "input": before, "cleaned": after, "simulated_fraction": source["simulated_fraction"],
              "reanchors": source["reanchors"], "recoveries": source["recoveries"],
              "adaptation": adaptation.as_dict() if adaptation else None, "method": args.method,
              "touch_up": touch, "denoiser": str(args.denoise) if args.denoise else None,
              "denoise_slow_s": args.denoise_slow,
              **({"denoise_slow_s_of_members": own_slowing} if own_slowing else {}),
              "mirror_average": args.mirror_average, **preparation_record(steps), **extra}
    if args.json:
        write_json(args.json, result)
    return result


if __name__ == "__main__":
    main()
