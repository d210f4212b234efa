"""Probe: how much does the IMU draw decide? Policies scored on many IMU-corrupted draws of each take.

Usage: ``python bench/imu_draws.py --policies models/mimic_general_taught models/mimic_general_fastback
[--clips library:data/library/val] [--draws 10] [--first-seed 20000] [--stride N] [--episodes 2] [--strength 1]
[--denoise DIR [--denoise-slow [S]] | --no-denoise] [--mirror-average] [--ensemble] [--style-shifts] [--even-legs]
[--part-legs [M]] [--ground] [--swing-lift [DEG] [--swing-from speed]] [--json [OUT]]``

``--denoise-slow`` slows the corrections of the denoiser that ``--denoise`` names, which here defaults to
``models/imu_denoiser_dm``, not validation's choice: name the denoiser with it.

Validation's IMU rows (``evaluate.py --corrupt imu --seed 9100`` and ``9200``) corrupt each take
once per seed and roll that one corrupted reference out 20 times, so a take the policy falls on in
one draw costs its whole share. Here every policy tracks ``--draws`` corrupted draws of every take
(draw ``j`` of clip ``i`` has artefact seed ``first_seed + j * stride + i``; ``--stride`` defaults
to the number of clips and may not be smaller, so no two references share a seed), ``--episodes``
rollouts each, after ``--denoise`` and judged against the take as given (as ``evaluate.py
--denoise``). Same clips, seeds and start frames for every policy; policy directories, run
checkpoints or policy sets (each take routed as given, before the denoiser, as ``evaluate.py`` routes
it; not with ``--ensemble``; a set's JSON row gives, under ``routed_to``, each take's policies and how
often each performed it; every row gives, under ``ELR_per_take``, each take's ELR over all draws, a take in each
version its own). Prints each policy's ELR per draw and over all draws and, for each
policy after the first, its mean paired difference from the first (± standard error over the
draws) and on how many draws it scores above, equal to and below it.

``--style-shifts`` tracks every clip in five versions per draw (as given, walked wider, at 0.8x and 1.25x
its pace, carried with another posture: :func:`reference_motion.library.style_shifted`, the width and
posture drawn with the draw's seed), so one style's takes also stand for the ways other styles differ
from it; the JSON then also gives each policy's ELR by version.

``--strength`` sets the draws' IMU strength (default 1, the IMU rows'); at 0 the takes are tracked clean, each
version still drawn with its seed, which tells what a version costs the policy clean from what the IMU costs it.
The selection rules (``select_policy.py``, ``select_denoiser.py``) read only strength-1 files.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import corrupted, reference_clips, tracked_and_judged, tracked_label
from agents.evaluation import Rollout, evaluate_tracking
from agents.mirror import actor_label
from agents.policy import MimicPolicy, load_policy
from agents.policy_set import is_policy_set, load_policy_set, slowed_members, slowing_label, source_name
from envs.config import FOOT_MODELS, MimicConfig
from envs.preparation import PreparationSteps, no_preparation, prepared, preparation_of, preparation_record
from ensemble import MeanAction, ensemble_label  # bench/ensemble.py: the scripts run from bench/
from json_report import emit_json
from paired_draws import paired
from perception.imu_denoiser import SlowCorrections, add_slow_corrections_option, slowed, slowing_of
from perception.weights import load_network
from reference_motion.grounding import add_grounding_option
from reference_motion.leg_gap import add_leg_gap_option
from reference_motion.leg_symmetry import add_leg_symmetry_option
from reference_motion.artefacts import ARTEFACT_KINDS
from reference_motion.cli import non_negative_float, require_frames
from reference_motion.library import STYLE_SHIFT_NAMES, expand_clips, style_shifted
from reference_motion.motion import Motion
from reference_motion.swing_lift import add_swing_lift_options


def drawn_clips(sources: list[str], model: str, config: MimicConfig, seed: int, style_shifts: bool) -> list[Motion]:
    """The clean clips of the draw with seed ``seed``: ``sources`` loaded for ``model`` as the policy gets them
    (:func:`agents.evaluate.reference_clips`), with ``style_shifts`` each in its five versions
    (:func:`style_shifted` with that seed; a faster copy is shorter, so each is checked to still hold an
    episode of ``config``)."""
    clips = reference_clips(sources, model, config, None, 1.0, seed)
    if not style_shifts:
        return clips
    return [require_frames(c, config.min_clip_frames + 1, c.name, "a mimic episode") for c in style_shifted(clips, seed)]


class Routed:
    """A policy set's actor over a draw: each take goes to the policy the set routes it to
    (:meth:`agents.policy_set.PolicySet.route`, on the take as given), loaded once. A member the set
    tracks behind its own slowing of the denoiser (:attr:`agents.policy_set.PolicySet.denoise_slow_s`)
    tracks its takes prepared anew from the takes as given (:meth:`tracked`).

    Args:
        path: the policy-set directory.
        denoiser: what the draw's takes were tracked behind (``None``: no denoiser).
        steps: the draw's other preparation (:func:`envs.preparation.preparation_of`).
    """

    def __init__(self, path: str, denoiser: object = None, steps: PreparationSteps | None = None):
        if denoiser is not None and steps is None:
            raise ValueError("Routed: give the draw's preparation steps with its denoiser (no_preparation() for none)")
        self.set = load_policy_set(path)
        self.policies = {p: load_policy(p) for p in self.set.policies}
        self.denoiser, self.steps = denoiser, steps or no_preparation()
        self.behind = {p: self.set.denoiser_for(p, denoiser) for p in self.policies}

    def tracked(self, member: Path, tracked: list[Motion], judged: list[Motion] | None, indices: list[int]
                ) -> list[Motion]:
        """What ``member`` tracks of the draw's takes ``indices``: the draw's ``tracked`` takes, or, where the set
        slows the member's denoiser its own way, the takes as given (``judged``) prepared behind that."""
        if self.behind[member] is self.denoiser:
            return [tracked[i] for i in indices]
        return [prepared(judged[i], self.behind[member], **self.steps) for i in indices]

    def routes(self, tracked: list[Motion], judged: list[Motion] | None) -> dict[Path, list[int]]:
        """``{policy directory: indices of its takes}``: the takes of a draw (``judged``, the takes as given, or
        ``tracked`` where they are tracked as given) grouped by the policy that performs them
        (:meth:`agents.policy_set.PolicySet.grouped`)."""
        return self.set.grouped(tracked if judged is None else judged)

    def groups(self, tracked: list[Motion], judged: list[Motion] | None
               ) -> list[tuple[MimicPolicy, list[int], list[Motion]]]:
        """``[(policy, indices of its takes, what it tracks of them), ...]``: :meth:`routes` with each policy
        loaded and its takes as :meth:`tracked` gives them."""
        return [(self.policies[p], indices, self.tracked(p, tracked, judged, indices))
                for p, indices in self.routes(tracked, judged).items()]

    def routing(self, draws: list[tuple[list[Motion], list[Motion] | None]],
                versions: tuple[str, ...] | None = None) -> dict[str, dict[str, int]]:
        """``{take: {policy directory: count}}``: how many times, over the ``(tracked,
        judged)`` draws, each take was routed to each policy of the set (a take near a rule's speed can go
        either way, by its IMU draw), takes named by :func:`take_label` (``versions``: the draws hold each
        take in these versions, in turn, :data:`STYLE_SHIFT_NAMES`)."""
        counts: dict[str, dict[str, int]] = {}
        for tracked, judged in draws:
            for policy, indices in self.routes(tracked, judged).items():
                for i in indices:
                    per_policy = counts.setdefault(take_label(tracked, i, versions), {})
                    per_policy[str(policy)] = per_policy.get(str(policy), 0) + 1
        return counts


def evaluate_draw(policy: MimicPolicy | Routed, tracked: list[Motion], judged: list[Motion] | None, episodes: int,
                  actor: object, mirror_average: bool) -> tuple[float, list[Rollout]]:
    """The mean ELR and the rollouts of ``policy`` (acting as ``actor``), or of each policy of a set for the takes
    routed to it, tracking ``tracked`` judged against ``judged`` (:func:`agents.evaluation.evaluate_tracking`)."""
    if not isinstance(policy, Routed):
        summary, runs = evaluate_tracking(policy, tracked, judged, episodes=episodes, actor=actor,
                                          mirror_average=mirror_average)
        return summary["ELR_mean"], runs
    runs = []
    for member, indices, its_takes in policy.groups(tracked, judged):
        runs += evaluate_tracking(member, its_takes,
                                  None if judged is None else [judged[i] for i in indices], episodes=episodes,
                                  mirror_average=mirror_average)[1]
    return float(np.mean([r.elr for r in runs])), runs


def take_label(tracked: list[Motion], i: int, versions: tuple[str, ...] | None) -> str:
    """How a report names the draw's take ``tracked[i]``: its name, or with ``versions`` (the draw holds each take in
    these versions, in turn) its source take's name (:func:`agents.policy_set.source_name`) and its version, so that a
    version whose name holds a stance or posture drawn anew in each draw is one take over the draws."""
    return tracked[i].name if versions is None else f"{source_name(tracked[i].name)} [{versions[i % len(versions)]}]"


def take_means(scored: list[tuple[float, list[Rollout]]], draws: list[tuple[list[Motion], list[Motion] | None]],
               versions: tuple[str, ...] | None) -> dict[str, float]:
    """``{take: mean ELR}`` over every draw's rollouts of it (:func:`take_label`), from the draws' ``(tracked, judged)``
    clips and their ``(mean ELR, rollouts)`` as :func:`evaluate_draw` returns them; takes in the order of the first
    draw."""
    elrs: dict[str, list[float]] = {}
    for (_, runs), (tracked, _) in zip(scored, draws):
        label = {clip.name: take_label(tracked, i, versions) for i, clip in enumerate(tracked)}
        for take in label.values():
            elrs.setdefault(take, [])
        for r in runs:
            elrs[label[r.clip]].append(r.elr)
    return {take: float(np.mean(values)) for take, values in elrs.items()}


def shift_means(runs: list[Rollout], tracked: list[Motion]) -> dict[str, float]:
    """Mean ELR of ``runs`` by style-shifted version (:data:`STYLE_SHIFT_NAMES`), the clips ``tracked``
    being :func:`style_shifted`'s five versions take by take; a rollout's version is read from its
    clip's name (a take listed twice has the same five names, and so the same versions)."""
    version = {clip.name: STYLE_SHIFT_NAMES[i % len(STYLE_SHIFT_NAMES)] for i, clip in enumerate(tracked)}
    return {name: float(np.mean([r.elr for r in runs if version[r.clip] == name])) for name in STYLE_SHIFT_NAMES}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True,
                   help="policy directories, run checkpoints or policy sets (policy_set.json)")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--draws", type=int, default=10, help="IMU-corrupted draws of each clip")
    p.add_argument("--first-seed", type=int, default=20000,
                   help="artefact seed of the first clip's first draw (default: a range no earlier run used)")
    p.add_argument("--stride", type=int, default=None, help="seed step from one draw to the next (default: the "
                                                            "number of clips, five times it with --style-shifts)")
    p.add_argument("--episodes", type=int, default=2, help="rollouts per clip and draw")
    p.add_argument("--strength", type=non_negative_float, default=1.0,
                   help="IMU artefact strength of the draws (default 1, the IMU rows'; 0: the takes clean, the "
                        "--style-shifts versions still drawn with each seed, to tell what a version costs clean)")
    p.add_argument("--without", nargs="+", choices=ARTEFACT_KINDS, default=[], metavar="KIND",
                   help="switch these IMU artefact kinds off (what the others cost together; the others' random "
                        "numbers stay the same, as evaluate.py --without)")
    p.add_argument("--style-shifts", action="store_true",
                   help="each draw tracks every clip in five versions, " + ", ".join(STYLE_SHIFT_NAMES) + " (a "
                        "stance, pace and carriage drawn anew for each draw with its seed: "
                        "reference_motion.library.style_shifted), so the clips of one style also stand for "
                        "takes of other styles; the stride defaults to five times the clips")
    p.add_argument("--mirror-average", action="store_true",
                   help="every policy acts mirror-symmetrically (agents/mirror.py); rows name it 'PATH (mirror-averaged)'")
    p.add_argument("--ensemble", action="store_true",
                   help="the policies act as one actor, the mean of their actions (one row)")
    denoising = p.add_mutually_exclusive_group()
    denoising.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_dm"),
                           help="the IMU denoiser every take passes through first (default, unlike evaluate.py's: "
                                "models/imu_denoiser_dm, kept so the README's earlier commands reproduce; "
                                "--no-denoise for the takes as given)")
    denoising.add_argument("--no-denoise", action="store_true", help="track the IMU takes as given")
    add_slow_corrections_option(p)
    add_leg_symmetry_option(p, "every policy mimics the takes with their legs evened and is judged against them as given")
    add_leg_gap_option(p, "every policy mimics the takes with their legs parted and is judged against them as given")
    add_grounding_option(p, "every policy mimics the grounded takes and is judged against them as given")
    add_swing_lift_options(p, "every policy mimics the lifted takes and is judged against them as given")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    if args.without and args.strength == 0:
        p.error(f"--without {' '.join(args.without)} switches IMU artefacts off: the takes are clean at --strength 0")
    steps = preparation_of(args)
    n_clips = len(expand_clips(args.clips)) * (len(STYLE_SHIFT_NAMES) if args.style_shifts else 1)
    stride = n_clips if args.stride is None else args.stride
    if stride < n_clips:
        p.error(f"--stride {stride} is below the {n_clips} clips{' (style-shifted)' if args.style_shifts else ''}: "
                "draws would share artefact seeds")
    sets = [path for path in args.policies if is_policy_set(path)]
    if sets and args.ensemble:
        p.error(f"--ensemble averages policies, not policy sets: {', '.join(sets)}")
    denoiser_path = None if args.no_denoise else args.denoise
    if args.denoise_slow is not None and denoiser_path is None:
        p.error(f"--denoise-slow {args.denoise_slow:g} slows the denoiser's corrections: drop --no-denoise")
    net = slowed(load_network(denoiser_path, "denoiser") if denoiser_path else None, args.denoise_slow)
    policies = [Routed(path, net, steps) if path in sets else load_policy(path) for path in args.policies]
    members = []  # (each policy a set or a plain policy stands for, the denoiser it tracks behind)
    for policy in policies:
        members += zip(policy.policies.values(), policy.behind.values()) if isinstance(policy, Routed) else [(policy, net)]
    feet = {policy.foot for policy, _ in members}
    if len(feet) > 1:
        p.error(f"the policies drive different humanoids ({sorted(feet)}); compare one foot model")
    for policy, behind in members:
        note = policy.preparation_note(denoiser_path, **steps, denoise_slow_s=slowing_of(behind))
        if note:
            print(note)
    slowly = f" ({net.label})" if isinstance(net, SlowCorrections) else ""
    takes = "IMU takes" if args.strength > 0 else "the clean takes (--strength 0)"
    print(f"{takes} pass through the denoiser {denoiser_path}{slowly} first (--no-denoise: as given)" if denoiser_path
          else f"{takes} are tracked as given (--no-denoise)", flush=True)
    model = FOOT_MODELS[feet.pop()]
    seeds = [args.first_seed + j * stride for j in range(args.draws)]

    config = MimicConfig()

    def corrupted_draw(seed: int) -> list:
        clips = drawn_clips(args.clips, model, config, seed, args.style_shifts)
        return corrupted(clips, "imu", args.strength, seed, args.without) if args.strength > 0 else clips

    draws = [tracked_and_judged(corrupted_draw(seed), net, **steps) for seed in seeds]
    if args.ensemble:
        mean = MeanAction(policies)
        actors = [(ensemble_label(args.policies), mean.widest, mean)]
    else:
        actors = [(path, policy, policy) for path, policy in zip(args.policies, policies)]
    versions = STYLE_SHIFT_NAMES if args.style_shifts else None  # how each draw holds its takes
    rows = []
    for path, policy, actor in actors:
        scored = [evaluate_draw(policy, tracked, judged, args.episodes, actor, args.mirror_average)
                  for tracked, judged in draws]
        elr = np.array([mean for mean, _ in scored])
        label = tracked_label(actor_label(path, args.mirror_average) + slowing_label(path, net), denoiser=net, **steps)
        rows.append({"policy": label, "ELR": float(elr.mean()), "ELR_per_draw": elr.tolist(),
                     "ELR_per_take": take_means(scored, draws, versions)})
        if isinstance(policy, Routed):
            rows[-1]["routed_to"] = policy.routing(draws, versions)
            own_slowing = slowed_members({policy.policies[p].name: behind for p, behind in policy.behind.items()}, net)
            if own_slowing:  # the members the set tracks behind their own slowing (seconds)
                rows[-1]["denoise_slow_s_of_members"] = own_slowing
        print(f"{label:<48} ELR {elr.mean():.3f}  per draw {' '.join(f'{e:.2f}' for e in elr)}", flush=True)
        if args.style_shifts:
            by_shift = [shift_means(runs, tracked) for (_, runs), (tracked, _) in zip(scored, draws)]
            rows[-1]["ELR_per_shift"] = {name: float(np.mean([d[name] for d in by_shift])) for name in STYLE_SHIFT_NAMES}
            print("  by version: " + ", ".join(f"{k} {v:.3f}" for k, v in rows[-1]["ELR_per_shift"].items()), flush=True)
    first = np.array(rows[0]["ELR_per_draw"])
    for row in rows[1:]:
        row["against_first"] = paired(np.array(row["ELR_per_draw"]), first)
        c = row["against_first"]
        print(f"{row['policy']:<48} {c['mean_difference']:+.3f} ± {c['standard_error']:.3f} against "
              f"{rows[0]['policy']}; above / equal / below on {c['draws_above']} / {c['draws_equal']} / "
              f"{c['draws_below']} of {args.draws} draws")
    emit_json({"policies": args.policies, "ensemble": args.ensemble, "clips": args.clips, "seeds_of_first_clip": seeds,
               "episodes": args.episodes, "strength": args.strength, "without": args.without,
               "style_shifts": versions,
               "denoiser": str(denoiser_path) if denoiser_path else None,
               "denoise_slow_s": args.denoise_slow,
               "mirror_average": args.mirror_average, **preparation_record(steps),
               "rows": rows}, args.json)


if __name__ == "__main__":
    main()
