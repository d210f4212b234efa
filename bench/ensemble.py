"""Probe: does the mean action of several generalists perform unseen takes better than each alone?

Usage: ``python bench/ensemble.py [--policies models/mimic_general_dashes models/mimic_dash_set/general
models/mimic_general_steered] [--clips library:data/library/val] [--episodes 20] [--seeds 9100 9200]
[--denoise models/imu_denoiser_dm] [--mirror-average] [--ground] [--swing-lift [DEG]] [--clean-json OUT]
[--json [OUT]]``

An ensemble of policies acts with the mean of its members' deterministic actions, each member
normalising the observation with its own statistics. The members must have been trained in the
same task (environment id, foot, every ``MimicConfig`` constant) except for the action limit; the
ensemble runs in the task of the member with the widest one, so each member's action stays within
its own limit (its ``__call__`` clips it). Rows: each member alone, then the ensemble, on the clean
takes and on the IMU takes of each seed (tracked after ``--denoise``, judged against the take as
given, as ``evaluate.py --denoise``); every row has the same clips, artefact seeds and start frames.
With ``--mirror-average`` every actor, the ensemble too, acts as its symmetric actor (the ensemble's
is the mean of its members' symmetric actors); with ``--ground`` and ``--swing-lift`` every take is
tracked as evaluation prepares it and judged against it as given. ``--clean-json`` writes the
ensemble's clean row as ``evaluate.py --per-clip --json`` writes one policy's, for
``bench/select_policy.py --clean``; ``bench/imu_draws.py --ensemble`` scores its IMU draws.
First measured without the symmetric actor: see the README ("The training takes the generalist
loses"); the mean of D's and G's symmetric actors: "Round 19".
"""

from __future__ import annotations

import argparse
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips, tracked_and_judged, tracked_label
from agents.evaluation import evaluate_tracking, per_clip
from agents.mirror import actor_label
from agents.policy import MimicPolicy, PolicyError, load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.weights import load_network
from reference_motion.grounding import add_grounding_option, grounding_of
from reference_motion.swing_lift import add_swing_lift_options, swing_lift_of


class MeanAction:
    """The mean deterministic action ``(A,)`` of ``members`` for one raw observation ``(D,)``."""

    def __init__(self, members: list[MimicPolicy]):
        def task(member: MimicPolicy) -> tuple:
            return member.env_id, member.foot, replace(member.record.env.mimic_config(), action_limit_rad=0.0)

        if any(task(member) != task(members[0]) for member in members[1:]):
            raise PolicyError(f"an ensemble's members must share their task (all but the action limit); "
                              f"{[m.name for m in members]} do not")
        self.members = members
        self.widest = max(members, key=lambda m: m.record.env.mimic_config().action_limit_rad)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return np.mean([member(obs) for member in self.members], axis=0)


def ensemble_label(paths: list[str]) -> str:
    """How results name the mean action of the policies at ``paths``."""
    return "mean action of " + " and ".join(map(str, paths))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", default=["models/mimic_general_dashes", "models/mimic_dash_set/general",
                                                      "models/mimic_general_steered"])
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip and row")
    p.add_argument("--seeds", type=int, nargs="*", default=[9100, 9200], help="IMU artefact seeds of the first clip")
    p.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_dm"))
    p.add_argument("--mirror-average", action="store_true", help="every actor acts as its symmetric actor")
    add_grounding_option(p, "every take is tracked set on the floor and judged against it as given")
    add_swing_lift_options(p, "every take is tracked lifted and judged against it as given")
    p.add_argument("--clean-json", type=Path, help="write the ensemble's clean row as evaluate.py --json writes one")
    p.add_argument("--members-too", action=argparse.BooleanOptionalAction, default=True,
                   help="also score each member alone (the default)")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    lift, grounding = swing_lift_of(args), grounding_of(args)
    members = [load_policy(path) for path in args.policies]
    ensemble = MeanAction(members)
    net = load_network(args.denoise, "denoiser")
    model = FOOT_MODELS[members[0].foot]
    clean = reference_clips(args.clips, model, MimicConfig(), None, 1.0, 0)
    inputs = {"clean": tracked_and_judged(clean, None, grounding=grounding, lift=lift)}
    for seed in args.seeds:
        given = reference_clips(args.clips, model, MimicConfig(), "imu", 1.0, seed)
        inputs[f"IMU seed {seed}, denoised"] = tracked_and_judged(given, net, grounding=grounding, lift=lift)
    rows = []
    ensemble_name = tracked_label(actor_label(ensemble_label(args.policies), args.mirror_average),
                                  grounding=grounding, lift=lift)
    actors = [(m.name, m, m) for m in members] if args.members_too else []
    actors += [(ensemble_name, ensemble.widest, ensemble)]
    for name, builder, actor in actors:
        for input_name, (tracked, judged) in inputs.items():
            summary, runs = evaluate_tracking(builder, tracked, judged, episodes=args.episodes, actor=actor,
                                              mirror_average=args.mirror_average)
            rows.append({"policy": name, "input": input_name, "ELR": summary["ELR_mean"], "SR90": summary["SR90"],
                         "rollouts": summary["rollouts"]})
            print(f"{name:<36} {input_name:<26} ELR {summary['ELR_mean']:.3f}  SR90 {summary['SR90']:.3f}", flush=True)
            if args.clean_json and actor is ensemble and input_name == "clean":
                emit_json({"policy": ensemble_name, "mirror_average": args.mirror_average, "clips": args.clips,
                           "corrupt": None, "episodes": args.episodes, **summary, "per_clip": per_clip(runs)},
                          str(args.clean_json))
    emit_json({"policies": args.policies, "clips": args.clips, "episodes": args.episodes, "seeds": args.seeds,
               "denoiser": str(args.denoise), "mirror_average": args.mirror_average,
               "grounding": asdict(grounding) if grounding else None, "swing_lift": asdict(lift) if lift else None,
               "rows": rows}, args.json)


if __name__ == "__main__":
    main()
