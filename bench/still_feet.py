"""What the still-feet reward term does to a policy's simulated motion: foot skate against tracking.

Usage: ``python bench/still_feet.py --policies adapt=models/mimic_general_480 still=runs/still_480/best
[--clips library:data/library/val] [--episodes 10] [--corrupt imu --strength 1 --seed 9100] [--json [OUT]]``

Several policies (each at the physics rate its sidecar records), the same clips and start frames,
side by side in one run. Per policy: its reward's still-feet weight
(:attr:`envs.config.MimicConfig.still_feet_weight`), ELR and SR90 (:mod:`agents.evaluation`), and
the simulated motion's foot skate, floor penetration (max and mean), floating and jitter (SPEC
"Metrics", :mod:`reference_motion.quality`, the mean over rollouts), with the references' own
figures for scale. Foot skate is split by how high the foot point is (within 2 mm of the floor:
bearing weight; 2–20 mm: rolling onto or off the floor, or scuffing in swing), the share of the
summed skate each band carries.
"""

from __future__ import annotations

import argparse

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import artefact_table, reference_clips
from agents.evaluation import evaluate, summarize
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.quality import QualityConfig, held_contact_speeds, kinematic_contacts, replay_on_ground

METRICS = ("foot_skate_mps", "penetration_max_m", "penetration_mean_m", "floating_m", "jitter")
BEARING_HEIGHT_M = 0.002
"""A foot point in contact lower than this above its ground counts as bearing weight."""


def skate_by_height(runs: list, config: QualityConfig = QualityConfig()) -> dict[str, float]:
    """Share of the summed foot skate (the speeds :func:`reference_motion.quality.foot_skate`
    averages, :func:`~reference_motion.quality.held_contact_speeds`) from points lower than
    :data:`BEARING_HEIGHT_M` (``bearing``) and from the rest of the contact band (``rolling``), and
    each band's mean speed (m/s), over the simulated motions of ``runs``."""
    speed, low = [], []
    for r in runs:
        kin, ground = replay_on_ground(r.simulated, config)
        contacts = kinematic_contacts(kin.foot_points, ground, config.contact_height)
        step, held = held_contact_speeds(kin.foot_points, contacts, r.simulated.fps)
        speed.append(step[held])
        low.append((kin.foot_points[1:, :, 2] - ground[1:, None])[held] < BEARING_HEIGHT_M)
    speed, low = np.concatenate(speed), np.concatenate(low)
    total = speed.sum() or 1.0
    return {"bearing_share": float(speed[low].sum() / total), "rolling_share": float(speed[~low].sum() / total),
            "bearing_mps": float(speed[low].mean()) if low.any() else 0.0,
            "rolling_mps": float(speed[~low].mean()) if (~low).any() else 0.0}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True, metavar="NAME=DIR")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=10, help="rollouts per clip and policy")
    p.add_argument("--corrupt", choices=["imu"], default=None, help="corrupt the references (the policy's input)")
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=9100, help="corruption seed of the first clip")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    named = [spec.split("=", 1) for spec in args.policies]
    if any(len(n) != 2 for n in named):
        p.error(f"--policies takes NAME=DIR pairs, got {args.policies}")
    table = []
    for name, path in named:
        policy = load_policy(path)
        clips = reference_clips(args.clips, FOOT_MODELS[policy.foot], MimicConfig(), args.corrupt, args.strength,
                                args.seed)
        config = policy.record.env.mimic_config()
        env = policy.make_env(clips, artefacts=None)
        env.reset(seed=0)
        runs = evaluate(env, policy, episodes=args.episodes)[1]
        summary, artefacts = summarize(runs), artefact_table(runs)
        row = {"policy": name, "path": path, "physics_rate_hz": config.physics_rate_hz,
               "still_feet_weight": config.still_feet_weight, "rollouts": len(runs),
               "ELR": summary["ELR_mean"], "SR90": summary["SR90"], **{k: artefacts[k]["output"] for k in METRICS},
               "skate_by_height": skate_by_height(runs), "input": {k: artefacts[k]["input"] for k in METRICS}}
        table.append(row)
        split = row["skate_by_height"]
        print(f"{name:<12} w_still {row['still_feet_weight']:g}  ELR {row['ELR']:.3f}  SR90 {row['SR90']:.2f}  skate "
              f"{row['foot_skate_mps']:.3f} m/s ({100 * split['bearing_share']:.0f}% bearing at "
              f"{split['bearing_mps']:.3f}, {100 * split['rolling_share']:.0f}% rolling at {split['rolling_mps']:.3f})  "
              f"penetration max {100 * row['penetration_max_m']:.2f} cm, mean {1000 * row['penetration_mean_m']:.2f} mm  "
              f"floating {1000 * row['floating_m']:.1f} mm  jitter {row['jitter']:.0f}", flush=True)
    result = {"clips": args.clips, "episodes": args.episodes, "corrupt": args.corrupt,
              "strength": args.strength if args.corrupt else None, "seed": args.seed if args.corrupt else None,
              "rows": table}
    if not emit_json(result, args.json):
        inp = table[0]["input"]
        print(f"{'references':<12} skate {inp['foot_skate_mps']:.3f} m/s  penetration max "
              f"{100 * inp['penetration_max_m']:.2f} cm, mean {1000 * inp['penetration_mean_m']:.2f} mm  floating "
              f"{1000 * inp['floating_m']:.1f} mm  jitter {inp['jitter']:.0f}")


if __name__ == "__main__":
    main()
