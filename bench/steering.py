"""What steering the observed reference velocities back onto the reference does to a policy.

Usage: ``python bench/steering.py [--policy models/mimic_general_robust] [--clips library:data/library/val]
[--episodes 20] [--gains 0 0.5 1 2] [--corrupt imu] [--strength 1] [--seed 9100] [--denoise [DIR]]
[--json [OUT]]``

One policy, the same clips, corruptions and start frames, side by side in one run, with the
observed reference CoM and body velocities pulled towards the reference's position at each of
``--gains`` (:attr:`envs.config.MimicConfig.steer_gain_hz`, 1/s; :func:`envs.observations.steered_velocities`).
ADAPT's observation holds no position error, so a drift from the reference is invisible to the
policy until the lag termination ends the episode on it. Per row: ELR, SR90, RDE (the root's
mean squared horizontal distance from the reference's, m²) and MRR (:mod:`agents.evaluation`),
and how the early ends ended. A policy trained with a gain records it in its sidecar; the
row at that gain is the policy as shipped.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate, summarize
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import DEFAULT_DENOISER, denoise
from perception.weights import load_network
from reference_motion.artefacts import ARTEFACT_KINDS


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general_robust")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip and row")
    p.add_argument("--gains", type=float, nargs="+", default=[0.0, 0.5, 1.0, 2.0], help="steering gains, 1/s")
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS, help="corrupt each clip with IMU artefacts first")
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=9100, help="artefact seed of the first clip (clip i gets seed + i)")
    p.add_argument("--denoise", nargs="?", const=DEFAULT_DENOISER, type=Path, metavar="DIR",
                   help="mimic each clip after the IMU denoiser, judged against the clip as given")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    clips = reference_clips(args.clips, FOOT_MODELS[policy.foot], MimicConfig(), args.corrupt, args.strength, args.seed)
    denoiser = load_network(args.denoise, "denoiser") if args.denoise else None
    performed = clips if denoiser is None else [denoise(denoiser, c) for c in clips]
    trained_gain = policy.record.env.mimic_config().steer_gain_hz
    table = []
    for gain in args.gains:
        steered = policy.steering(gain)
        env = steered.make_env(performed, artefacts=None, judged_clips=None if denoiser is None else clips)
        env.reset(seed=0)
        runs = evaluate(env, steered, episodes=args.episodes)[1]
        summary = summarize(runs)
        row = {"steer_gain_hz": gain, "as_trained": gain == trained_gain, "rollouts": len(runs),
               "ELR": summary["ELR_mean"], "SR90": summary["SR90"], "RDE": summary["RDE_mean"],
               "MRR": summary["MRR_mean"], "ended_by": dict(Counter(r.ended_by for r in runs))}
        table.append(row)
        print(f"gain {gain:4.2g}/s{' (as trained)' if row['as_trained'] else '':13}  ELR {row['ELR']:.3f}  "
              f"SR90 {row['SR90']:.2f}  RDE {row['RDE']:.4f} m²  MRR {row['MRR']:.3f}  ended by "
              + ", ".join(f"{k} {v}" for k, v in sorted(row["ended_by"].items())), flush=True)
    emit_json({"policy": args.policy, "clips": args.clips, "episodes": args.episodes, "corrupt": args.corrupt,
               "strength": args.strength if args.corrupt else None, "seed": args.seed if args.corrupt else None,
               "denoiser": str(args.denoise) if args.denoise else None, "rows": table}, args.json)


if __name__ == "__main__":
    main()
