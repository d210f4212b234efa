"""Probe: how much does the IMU draw decide? Policies scored on many IMU-corrupted draws of each take.

Usage: ``python bench/imu_draws.py --policies models/mimic_general_taught runs/distill_fb/student
[--clips library:data/library/val] [--draws 10] [--first-seed 9300] [--stride 10] [--episodes 2]
[--denoise models/imu_denoiser_dm] [--json [OUT]]``

Validation's IMU rows (``evaluate.py --corrupt imu --seed 9100`` and ``9200``) corrupt each take
once per seed and roll out that one corrupted reference 20 times, so a take the policy falls on in
one draw costs its whole share. Here every policy tracks ``--draws`` corrupted draws of every take
(draw ``j`` of clip ``i`` has artefact seed ``first_seed + j * stride + i``, so with ``--stride`` at
least the number of clips no two references share a seed), ``--episodes`` rollouts each, after
``--denoise`` and judged against the take as given (as ``evaluate.py --denoise``). Same clips,
seeds and start frames for every policy. Prints each policy's ELR per draw and over all draws, and
for each policy after the first how many draws it scores above the first one (paired by draw).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import denoise
from perception.weights import load_network


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True, help="policy directories or run checkpoints")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--draws", type=int, default=10, help="IMU-corrupted draws of each clip")
    p.add_argument("--first-seed", type=int, default=9300, help="artefact seed of the first clip's first draw")
    p.add_argument("--stride", type=int, default=10, help="seed step from one draw to the next")
    p.add_argument("--episodes", type=int, default=2, help="rollouts per clip and draw")
    p.add_argument("--denoise", type=Path, default=Path("models/imu_denoiser_dm"))
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policies = [load_policy(path) for path in args.policies]
    feet = {policy.foot for policy in policies}
    if len(feet) > 1:
        raise SystemExit(f"error: the policies drive different humanoids ({sorted(feet)}); compare one foot model")
    net = load_network(args.denoise, "denoiser")
    model = FOOT_MODELS[feet.pop()]
    seeds = [args.first_seed + j * args.stride for j in range(args.draws)]
    draws = []
    for seed in seeds:
        given = reference_clips(args.clips, model, MimicConfig(), "imu", 1.0, seed)
        draws.append(([denoise(net, clip) for clip in given], given))
    rows = []
    for path, policy in zip(args.policies, policies):
        elr = [evaluate_tracking(policy, tracked, judged, episodes=args.episodes)[0]["ELR_mean"]
               for tracked, judged in draws]
        rows.append({"policy": path, "ELR": float(np.mean(elr)), "ELR_per_draw": [float(e) for e in elr]})
        print(f"{path:<48} ELR {np.mean(elr):.3f}  per draw {' '.join(f'{e:.2f}' for e in elr)}", flush=True)
    first = np.array(rows[0]["ELR_per_draw"])
    for row in rows[1:]:
        row["draws_above_first"] = int(np.sum(np.array(row["ELR_per_draw"]) > first))
        print(f"{row['policy']:<48} above {rows[0]['policy']} on {row['draws_above_first']} of {args.draws} draws")
    emit_json({"policies": args.policies, "clips": args.clips, "seeds_of_first_clip": seeds,
               "episodes": args.episodes, "denoiser": str(args.denoise), "rows": rows}, args.json)


if __name__ == "__main__":
    main()
