"""Evaluate a trained mimic policy with ADAPT's protocol, and what it does to the artefacts.

Usage::

    python agents/evaluate.py --policy models/mimic_walk --clips deepmimic:walk
    python agents/evaluate.py --policy models/mimic_imu --clips deepmimic:walker/turn_left1 \\
        --corrupt imu --strength 1 --seed 1000 --episodes 20 --json out/eval.json

Each clip is one ``episode_frames`` segment rolled out ``--episodes`` times from start offsets
0, 3, 6, ... frames (adapt §4.1). Printed: mean and σ of ELR, RDE, MRR, and SR90; then the
artefact metrics (:mod:`reference_motion.quality`) of the reference the policy was given
(``input``) and of the simulated motion (``output``), averaged over rollouts.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

if __package__ in (None, ""):  # `python agents/evaluate.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluation import evaluate_tracking, per_clip, summarize
from agents.mirror import actor_label
from agents.policy_set import is_policy_set, member_denoiser, route_clips, slowed_members, slowing_label
from envs.config import FOOT_MODELS, MimicConfig
from envs.observations import SAME_LAYOUT_FRAMES
from envs.preparation import PreparationSteps, prepared, preparation_of, preparation_record, prepares_any
from perception.imu_denoiser import (DEFAULT_DENOISER, DenoiserEnsemble, IMUDenoiser, SlowCorrections,
                                     add_slow_corrections_option, slowed, slowing_of)
from perception.weights import load_network
from reference_motion.atomic import write_json
from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.cli import (CliParser, add_mocap_options, mocap_options, non_negative_float, non_negative_int,
                                  one_line_errors, output_file, positive_float, positive_int, require_frames)
from reference_motion.grounding import Grounding, add_grounding_option
from reference_motion.leg_gap import LegGap, add_leg_gap_option
from reference_motion.leg_symmetry import LegSymmetry, add_leg_symmetry_option
from reference_motion.library import expand_clips, load_motion
from reference_motion.motion import Motion
from reference_motion.quality import ARTEFACT_METRICS, motion_quality
from reference_motion.rigs import MocapOptions
from reference_motion.swing_lift import SwingLift, add_swing_lift_options

def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0],
                  formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--policy", required=True, help="policy directory (model.zip, model_vecnormalize.pkl, sidecar.json), "
                                                   "or a policy set (policy_set.json: a policy per motion class)")
    p.add_argument("--clips", nargs="+", required=True,
                   help="SOURCE strings or files of the clips to evaluate on, or clip sets (library:DIR/test)")
    add_mocap_options(p)
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS, help="corrupt each clip with IMU artefacts first")
    p.add_argument("--without", nargs="+", choices=ARTEFACT_KINDS, default=[], metavar="KIND",
                   help="with --corrupt imu: switch these artefact kinds off (what the others cost together; "
                        "the others' random numbers stay the same)")
    p.add_argument("--strength", type=non_negative_float, default=1.0, help="artefact strength")
    p.add_argument("--seed", type=int, default=1000, help="artefact seed of the first clip (clip i gets seed + i)")
    p.add_argument("--denoise", nargs="?", const=DEFAULT_DENOISER, type=Path, metavar="DIR",
                   help="the policy mimics each clip after the IMU denoiser (perception/imu_denoiser.py; DIR "
                        "default: models/imu_denoiser_soles_quint_mirror, validation's choice until stop 75; since then "
                        "models/imu_denoiser_stances_quint_mirror) and is judged against "
                        "the clip as given")
    add_slow_corrections_option(p)
    add_leg_symmetry_option(p, "the policy mimics the clip with its legs evened and is judged against the clip as given")
    add_leg_gap_option(p, "the policy mimics the clip with its legs parted and is judged against the clip as given")
    add_grounding_option(p, "the policy mimics the grounded clip and is judged against the clip as given")
    add_swing_lift_options(p, "the policy mimics the lifted clip and is judged against the clip as given")
    p.add_argument("--obs-frame", choices=SAME_LAYOUT_FRAMES,
                   help="run a world-frame policy observing in this frame (envs.observations; default: the frame its "
                        "sidecar records)")
    p.add_argument("--physics-rate-hz", type=positive_float, metavar="HZ",
                   help="step the physics at this rate, a multiple of 60 (MimicConfig.physics_rate_hz: finer steps, "
                        "stiffer contacts; default: the rate its sidecar records, 120 for every shipped policy)")
    p.add_argument("--steer-gain", type=non_negative_float, metavar="HZ",
                   help="steer the observed reference velocities back onto the reference's position at this rate, "
                        "1/s (MimicConfig.steer_gain_hz; default: the gain its sidecar records)")
    p.add_argument("--mirror-average", action="store_true",
                   help="act with the mean of the policy's action and its action on the mirrored observation, "
                        "mapped back: an exactly mirror-symmetric policy from the same weights (agents/mirror.py)")
    p.add_argument("--episodes", type=positive_int, default=20, help="rollouts per clip")
    p.add_argument("--offset-step", type=non_negative_int, default=3, help="frames between the rollouts' start offsets")
    p.add_argument("--per-clip", action="store_true",
                   help="also print each clip's mean ELR and SR90, worst first (the JSON always has them)")
    p.add_argument("--json", type=output_file(".json"), help="also write the results as JSON here")
    return p


def reference_clips(sources: list[str], model: str, config: MimicConfig, kind: str | None, strength: float,
                    seed: int, mocap: MocapOptions = MocapOptions(), without: Sequence[str] = ()) -> list[Motion]:
    """The clips as the policy gets them: loaded for ``model`` (cyclic ones looped to two episodes
    of ``config``; each as long as the environment needs) and optionally corrupted (``kind``, with
    the artefact kinds ``without`` switched off: :meth:`ArtefactRecipe.without`)."""
    out = []
    for source in expand_clips(sources):
        motion = load_motion(source, model, min_frames=2 * (config.episode_frames + 1), mocap=mocap)
        require_frames(motion, config.min_clip_frames + 1, source, "a mimic episode")
        out.append(motion)
    return corrupted(out, kind, strength, seed, without) if kind else out


def corrupted(clips: Sequence[Motion], kind: str, strength: float, seed: int, without: Sequence[str] = ()) -> list[Motion]:
    """``clips`` corrupted with the artefacts ``kind`` at ``strength`` (those ``without`` names switched
    off: :meth:`ArtefactRecipe.without`), clip ``i`` with artefact seed ``seed + i``."""
    recipe = ArtefactRecipe.named(kind, strength).without(without)
    return [corrupt(motion, recipe, seed + i) for i, motion in enumerate(clips)]


def tracked_and_judged(clips: list[Motion], denoiser: IMUDenoiser | DenoiserEnsemble | SlowCorrections | None, *,
                       symmetry: LegSymmetry | None = None, legs: LegGap | None = None,
                       grounding: Grounding | None = None,
                       lift: SwingLift | None = None) -> tuple[list[Motion], list[Motion] | None]:
    """What a policy tracks and what it is judged against: ``clips`` themselves (judged against
    what it tracks: ``None``), or the clips :func:`prepared`, judged against the clips as given."""
    steps = PreparationSteps(symmetry=symmetry, legs=legs, grounding=grounding, lift=lift)
    if denoiser is None and not prepares_any(steps):
        return clips, None
    return [prepared(c, denoiser, **steps) for c in clips], clips


def tracked_label(label: str, *, denoiser: object = None, symmetry: LegSymmetry | None = None,
                  legs: LegGap | None = None, grounding: Grounding | None = None, lift: SwingLift | None = None) -> str:
    """How results name an actor that tracked clips behind a denoiser's slow corrections
    (``denoiser``, a :class:`SlowCorrections`), with their legs evened or parted, grounded or
    swing-lifted (so ``bench/select_policy.py`` tells it from the same actor without them), in the
    order :func:`prepared` applies them. A denoiser used as it is is not named (its path is a field
    of the results)."""
    slow = denoiser if isinstance(denoiser, SlowCorrections) else None
    steps = (slow, symmetry, legs, grounding, lift)
    return " + ".join([label, *(step.label for step in steps if step is not None)])


def artefact_table(runs: list) -> dict[str, dict[str, float]]:
    """Mean artefact metrics of the references (``input``) and simulations (``output``) of ``runs``."""
    table = {k: {"input": [], "output": []} for k in ARTEFACT_METRICS}
    for r in runs:
        for side, motion in (("input", r.reference), ("output", r.simulated)):
            q = motion_quality(motion).as_dict()
            for k in ARTEFACT_METRICS:
                table[k][side].append(q[k])
    out = {}
    for k, v in table.items():
        inp, outp = float(np.mean(v["input"])), float(np.mean(v["output"]))
        out[k] = {"input": inp, "output": outp, "reduction": (1 - outp / inp) if inp > 0 else 0.0}
    return out


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> dict:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the results."""
    args = build_parser(prog).parse_args(argv)
    if args.without and args.corrupt != "imu":
        raise ValueError(f"--without {' '.join(args.without)}: it switches kinds off in --corrupt imu; "
                         + ("give --corrupt imu" if args.corrupt is None else f"got --corrupt {args.corrupt}"))
    denoiser = slowed(load_network(args.denoise, "denoiser") if args.denoise else None, args.denoise_slow)
    steps = preparation_of(args)
    runs, frames, rates, gains, routed_to, behind_of = [], set(), set(), set(), {}, {}
    for policy, clips in route_clips(args.policy, lambda foot: reference_clips(
            args.clips, FOOT_MODELS[foot], MimicConfig(), args.corrupt, args.strength, args.seed, mocap_options(args),
            args.without)):
        behind = member_denoiser(args.policy, policy, denoiser)  # a set may slow a member's corrections its own way
        behind_of[policy.name] = behind
        note = policy.preparation_note(args.denoise, **steps, denoise_slow_s=slowing_of(behind))
        if note:
            print(note)
        if args.obs_frame:
            policy = policy.observing(args.obs_frame)
        if args.physics_rate_hz:
            policy = policy.simulating(args.physics_rate_hz)
        if args.steer_gain is not None:
            policy = policy.steering(args.steer_gain)
        task = policy.record.env.mimic_config()
        frames.add(task.obs_frame)
        rates.add(task.physics_rate_hz)
        gains.add(task.steer_gain_hz)
        routed_to |= {clip.name: policy.name for clip in clips}  # a run's checkpoint by its file
        tracked, judged = tracked_and_judged(clips, behind, **steps)
        runs += evaluate_tracking(policy, tracked, judged, episodes=args.episodes, offset_step=args.offset_step,
                                  mirror_average=args.mirror_average)[1]
    summary = summarize(runs)
    result = {"policy": tracked_label(actor_label(args.policy, args.mirror_average)
                                      + slowing_label(args.policy, denoiser), denoiser=denoiser,
                                      **steps),
              "mirror_average": args.mirror_average, **preparation_record(steps), "clips": args.clips,
              "corrupt": args.corrupt,
              "without": args.without,
              "obs_frame": ", ".join(sorted(frames)), "physics_rate_hz": sorted(rates),
              "steer_gain_hz": sorted(gains),
              "denoiser": str(args.denoise) if args.denoise else None, "denoise_slow_s": args.denoise_slow,
              "strength": args.strength if args.corrupt else None, "seed": args.seed if args.corrupt else None,
              **summary, "artefacts": artefact_table(runs), "per_clip": per_clip(runs)}
    if is_policy_set(args.policy):  # which of the set's policies performed each clip
        result["routed_to"] = routed_to
    own_slowing = slowed_members(behind_of, denoiser)
    if own_slowing:  # the members the set tracks behind their own slowing (seconds)
        result["denoise_slow_s_of_members"] = own_slowing
    symmetry, legs, grounding, lift = steps["symmetry"], steps["legs"], steps["grounding"], steps["lift"]
    changes = [text for text in (f"with their {symmetry.label}" if symmetry else "",
                                 f"with their {legs.label}" if legs else "", "set on the floor" if grounding else "",
                                 f"with a {lift.label}" if lift else "") if text]
    print(f"{len(runs)} rollouts ({args.episodes} per clip) of {result['policy']} on {', '.join(args.clips)}"
          + (f", corrupted '{args.corrupt}' strength {args.strength} seed {args.seed}+" if args.corrupt else "")
          + (f" without {', '.join(args.without)}" if args.without else "")
          + (f", denoised by {args.denoise}" if args.denoise else "")
          + (f" ({denoiser.label})" if isinstance(denoiser, SlowCorrections) else "")
          + (f", tracking takes {' and '.join(changes)}" if changes else ""))
    print(f"  ELR  {summary['ELR_mean']:.3f} ± {summary['ELR_std']:.3f}    SR90 {summary['SR90']:.3f}")
    print(f"  RDE  {summary['RDE_mean']:.5f} ± {summary['RDE_std']:.5f} m²    MRR {summary['MRR_mean']:.3f} ± "
          f"{summary['MRR_std']:.3f}")
    print(f"  {'artefact':<24}{'input':>12}{'output':>12}{'reduction':>11}")
    for k, v in result["artefacts"].items():
        print(f"  {k:<24}{v['input']:>12.4f}{v['output']:>12.4f}{100 * v['reduction']:>10.0f}%")
    if args.per_clip:
        print(f"  {'clip (worst first)':<56}{'ELR':>6}{'SR90':>6}")
        for row in result["per_clip"]:
            print(f"  {row['clip']:<56}{row['ELR']:>6.2f}{row['SR90']:>6.2f}")
    if args.json:
        write_json(args.json, result)
    return result


if __name__ == "__main__":
    main()
