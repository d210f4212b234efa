"""Where a policy's loss on IMU takes sits: joint angles, root placement, or the judge.

Usage: ``python bench/imu_ceiling.py [--policy models/mimic_general_steered] [--clips library:data/library/val]
[--episodes 20] [--kind imu] [--strength 1] [--seed 9100] [--denoise DIR ...] [--rows ROW ...]
[--json [OUT]]``

Every clip is corrupted with every IMU artefact kind (:func:`reference_motion.artefacts.corrupt`,
ADAPT's protocol at ``--strength``; ``--kind`` for one kind alone), and the policy tracks, row by row, a different version of
it, always judged (rewarded and terminated) against the take as given, as ``evaluate.py
--denoise`` judges:

- ``given``: the IMU take itself (``evaluate.py --corrupt imu``);
- ``denoised DIR``: the take after each IMU denoiser of ``--denoise`` (``evaluate.py --denoise DIR``);
- ``clean root``: the take's joint angles on the clean take's pelvis (position, height,
  orientation): what the root's errors cost (heading and root drift, stance skate, height);
- ``clean joints``: the clean take's joint angles and pelvis height on the take's pelvis placement
  over the ground (horizontal position and orientation): what a denoiser that undid every error
  it corrects (hinge angles and pelvis height, :func:`perception.imu_denoiser.denoise`) would reach
  (a reference point, not a bound: a denoised take is another draw of the same errors);
- ``clean``: the clean take (a perfect cleaner): what is left is the policy's own loss on the
  clips plus what the judge (the take as given, drifted and skating) costs it.

The rows run on the same clips, artefact seeds and start frames, side by side in one run;
``--rows`` picks some of them (``given``, ``denoised``, ``clean_root``, ``clean_joints``, ``clean``).
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate_tracking, per_clip
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.artefacts import ARTEFACT_KINDS
from reference_motion.motion import Motion

ROWS = ("given", "denoised", "clean_root", "clean_joints", "clean")
"""The rows, in the order they run."""
PELVIS = [0, 1, 2, 3, 4, 5, 6]
"""qpos columns of the pelvis: position (m) and orientation (quaternion w, x, y, z)."""
PLACEMENT = [0, 1, 3, 4, 5, 6]
"""The pelvis without its height: horizontal position (m) and orientation."""


def with_columns_of(motion: Motion, other: Motion, columns: list[int]) -> Motion:
    """``motion`` with qpos ``columns`` taken from ``other``, frame by frame (same length and rate)."""
    qpos = motion.qpos.copy()
    qpos[:, columns] = other.qpos[:, columns]
    return motion.with_qpos(qpos, source={**motion.source, "qpos_columns_from": [columns, other.source]})


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general_steered")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip and row")
    p.add_argument("--kind", choices=("imu",) + ARTEFACT_KINDS, default="imu", help="artefact kinds: all, or one")
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=9100, help="artefact seed of the first clip (clip i gets seed + i)")
    p.add_argument("--denoise", nargs="*", type=Path, default=[Path("models/imu_denoiser_dm")], metavar="DIR",
                   help="IMU denoisers, a row each")
    p.add_argument("--rows", nargs="+", choices=ROWS, default=list(ROWS), help="which rows to run")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    model, config = FOOT_MODELS[policy.foot], MimicConfig()
    clean = reference_clips(args.clips, model, config, None, args.strength, args.seed)
    given = reference_clips(args.clips, model, config, args.kind, args.strength, args.seed)
    rows = {}
    if "given" in args.rows:
        rows["given"] = given
    if "denoised" in args.rows:
        for path in dict.fromkeys(args.denoise):  # each once
            net = load_network(path, "denoiser")
            rows[f"denoised {path}"] = [denoise(net, c) for c in given]
    if "clean_root" in args.rows:
        rows["clean root"] = [with_columns_of(g, c, PELVIS) for g, c in zip(given, clean)]
    if "clean_joints" in args.rows:
        rows["clean joints and height"] = [with_columns_of(c, g, PLACEMENT) for g, c in zip(given, clean)]
    if "clean" in args.rows:
        rows["clean"] = clean
    table = []
    for name, tracked in rows.items():
        summary, runs = evaluate_tracking(policy, tracked, given, episodes=args.episodes)
        row = {"tracked": name, "rollouts": len(runs), "ELR": summary["ELR_mean"], "SR90": summary["SR90"],
               "RDE": summary["RDE_mean"], "ended_by": dict(Counter(r.ended_by for r in runs)),
               "per_clip": per_clip(runs)}
        table.append(row)
        print(f"{name:<44} ELR {row['ELR']:.3f}  SR90 {row['SR90']:.2f}  RDE {row['RDE']:.4f} m²", flush=True)
    emit_json({"policy": args.policy, "clips": args.clips, "episodes": args.episodes, "kind": args.kind,
               "strength": args.strength,
               "seed": args.seed, "judged_against": "the IMU take as given", "rows": table}, args.json)


if __name__ == "__main__":
    main()
