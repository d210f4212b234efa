"""Probe: does the mean action of several generalists perform unseen takes better than each alone?

Usage: ``python bench/ensemble.py [--policies models/mimic_general_dashes models/mimic_dash_set/general
models/mimic_general_steered] [--clips library:data/library/val] [--episodes 20] [--seeds 9100 9200]
[--denoise models/imu_denoiser_dm] [--json [OUT]]``

An ensemble of policies acts with the mean of its members' deterministic actions, each member
normalising the observation with its own statistics. The members must have been trained in the
same task (environment id, foot, every ``MimicConfig`` constant) except for the action limit; the
ensemble runs in the task of the member with the widest one, so each member's action stays within
its own limit (its ``__call__`` clips it). Rows: each member alone, then the ensemble, on the clean
takes and on the IMU takes of each seed (tracked after ``--denoise``, judged against the take as
given, as ``evaluate.py --denoise``); every row has the same clips, artefact seeds and start frames.
Not adopted: see the README ("The training takes the generalist loses"), where the measured rows are.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import Policy, evaluate_tracking
from agents.policy import MimicPolicy, PolicyError, load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.weights import load_network
from reference_motion.motion import Motion


class MeanAction:
    """The mean deterministic action ``(A,)`` of ``members`` for one raw observation ``(D,)``."""

    def __init__(self, members: list[MimicPolicy]):
        def task(member: MimicPolicy) -> tuple:
            return member.env_id, member.foot, replace(member.record.env.mimic_config(), action_limit_rad=0.0)

        if any(task(member) != task(members[0]) for member in members[1:]):
            raise PolicyError(f"an ensemble's members must share their task (all but the action limit); "
                              f"{[str(m.path) for m in members]} do not")
        self.members = members
        self.widest = max(members, key=lambda m: m.record.env.mimic_config().action_limit_rad)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return np.mean([member(obs) for member in self.members], axis=0)


def score(builder: MimicPolicy, actor: Policy, tracked: list[Motion], judged: list[Motion] | None,
          episodes: int) -> dict:
    """ELR and SR90 of ``actor`` in ``builder``'s task, tracking ``tracked`` judged against ``judged``."""
    summary = evaluate_tracking(builder, tracked, judged, episodes=episodes, actor=actor)[0]
    return {"ELR": summary["ELR_mean"], "SR90": summary["SR90"], "rollouts": summary["rollouts"]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", default=["models/mimic_general_dashes", "models/mimic_dash_set/general",
                                                      "models/mimic_general_steered"])
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip and row")
    p.add_argument("--seeds", type=int, nargs="*", default=[9100, 9200], help="IMU artefact seeds of the first clip")
    p.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_dm"))
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    members = [load_policy(path) for path in args.policies]
    ensemble = MeanAction(members)
    net = load_network(args.denoise, "denoiser")
    model = FOOT_MODELS[members[0].foot]
    inputs = {"clean": (reference_clips(args.clips, model, MimicConfig(), None, 1.0, 0), None)}
    for seed in args.seeds:
        given = reference_clips(args.clips, model, MimicConfig(), "imu", 1.0, seed)
        inputs[f"IMU seed {seed}, denoised"] = tracked_and_judged(given, net)
    rows = []
    actors = [(str(m.path), m, m) for m in members] + [("ensemble (mean action)", ensemble.widest, ensemble)]
    for name, builder, actor in actors:
        for input_name, (tracked, judged) in inputs.items():
            row = {"policy": name, "input": input_name, **score(builder, actor, tracked, judged, args.episodes)}
            rows.append(row)
            print(f"{name:<36} {input_name:<26} ELR {row['ELR']:.3f}  SR90 {row['SR90']:.3f}", flush=True)
    emit_json({"policies": args.policies, "clips": args.clips, "episodes": args.episodes, "seeds": args.seeds,
               "denoiser": str(args.denoise), "rows": rows}, args.json)


if __name__ == "__main__":
    main()
