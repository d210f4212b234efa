"""Does the simulated body walk as far as the take? The progress ratio of policies, take by take.

Usage: ``python bench/walking_speed.py --policies models/mimic_general_stance_avg [...]
[--mirror-average] [--clips library:data/library/val] [--episodes 8] [--corrupt-seed S
[--denoise [DIR]]] [--json [OUT]]``

Every policy performs every clip ``--episodes`` times (ADAPT's start offsets, :mod:`agents.evaluation`),
clean, or IMU-corrupted at strength 1 with artefact seed ``--corrupt-seed`` (then tracked after
``--denoise`` and judged against the take as given, as ``evaluate.py --denoise``). Per take and
policy: ELR, the mean progress ratio (:func:`agents.metrics.progress_ratio`: how far the root got
along the take's way over the rollout, 1.0 = as far as the take) and the mean along-the-way speed
of the simulated foot points held on the floor (m/s; 0 when a planted foot does not slip, so a
ratio below 1 then comes from shorter steps). Same clips, seeds and start frames for every policy.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import Rollout, evaluate_tracking
from agents.metrics import progress_ratio
from agents.mirror import actor_label
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import DEFAULT_DENOISER
from perception.weights import load_network
from reference_motion.quality import QualityConfig, held_contact_speeds, kinematic_contacts, replay_on_ground


def planted_slip(rollout: Rollout) -> float:
    """Mean velocity (m/s) along the take's way of the simulated foot points held on the floor
    (:func:`reference_motion.quality.held_contact_speeds`'s pairs), NaN when none is held or the take
    does not move."""
    sim, ref = rollout.simulated, rollout.reference.qpos
    way = ref[-1, :2] - ref[0, :2]
    if np.linalg.norm(way) < 0.3:
        return float("nan")
    kin, ground = replay_on_ground(sim)
    points = kin.foot_points
    _, held = held_contact_speeds(points, kinematic_contacts(points, ground, QualityConfig.contact_height), sim.fps)
    along = np.diff(points[..., :2], axis=0) @ (way / np.linalg.norm(way)) * sim.fps
    return float(along[held].mean()) if held.any() else float("nan")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True, help="policy directories or run checkpoints")
    p.add_argument("--mirror-average", action="store_true", help="every policy acts mirror-symmetrically")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=8, help="rollouts per clip")
    p.add_argument("--corrupt-seed", type=int, help="IMU-corrupt every take at strength 1 with this artefact seed")
    p.add_argument("--denoise", nargs="?", type=Path, const=DEFAULT_DENOISER,
                   help="with --corrupt-seed: track the takes after this IMU denoiser")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    if args.denoise and args.corrupt_seed is None:
        p.error("--denoise needs --corrupt-seed: a denoiser undoes IMU artefacts")
    policies = [load_policy(path) for path in args.policies]
    feet = {policy.foot for policy in policies}
    if len(feet) > 1:
        p.error(f"the policies drive different humanoids ({sorted(feet)}); compare one foot model")
    model = FOOT_MODELS[feet.pop()]
    corrupted = args.corrupt_seed is not None
    clips = reference_clips(args.clips, model, MimicConfig(), "imu" if corrupted else None, 1.0, args.corrupt_seed or 0)
    tracked, judged = tracked_and_judged(clips, load_network(args.denoise, "denoiser") if args.denoise else None)
    rows = []
    for path, policy in zip(args.policies, policies):
        label = actor_label(path, args.mirror_average)
        summary, runs = evaluate_tracking(policy, tracked, judged, episodes=args.episodes,
                                          mirror_average=args.mirror_average)
        takes = {}
        for r in runs:
            takes.setdefault(r.clip, []).append(r)
        per_take = [{"clip": clip, "ELR": float(np.mean([r.elr for r in rs])),
                     "progress": float(np.nanmean([progress_ratio(r.simulated.qpos[:, :3], r.reference.qpos[:, :3])
                                                   for r in rs])),
                     "planted_slip_mps": float(np.nanmean([planted_slip(r) for r in rs]))} for clip, rs in takes.items()]
        rows.append({"policy": label, "ELR": summary["ELR_mean"], "per_take": per_take})
        print(f"{label}: ELR {summary['ELR_mean']:.3f}")
        for t in per_take:
            print(f"  {t['clip']:<40} ELR {t['ELR']:.3f}  progress {t['progress']:.3f}  "
                  f"planted feet along the way {t['planted_slip_mps']:+.3f} m/s", flush=True)
    emit_json({"policies": args.policies, "mirror_average": args.mirror_average, "clips": args.clips,
               "episodes": args.episodes, "corrupt_seed": args.corrupt_seed,
               "denoiser": str(args.denoise) if args.denoise else None, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
