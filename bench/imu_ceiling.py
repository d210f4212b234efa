"""Where a policy's loss on IMU takes sits: joint angles, root placement, or the judge.

Usage: ``python bench/imu_ceiling.py [--policy models/mimic_general_steered] [--clips library:data/library/val]
[--episodes 20] [--kind imu] [--strength 1] [--seed 9100] [--draws 1] [--denoise DIR ...] [--rows ROW ...]
[--mirror-average] [--ground] [--swing-lift [DEG]] [--json [OUT]]``

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
- ``imu_path``: the clean take on the take's horizontal pelvis path (root drift, stance skate, and
  the path bent by the heading drift): what the path's errors alone cost;
- ``imu_rotation``: the clean take with the take's pelvis orientation: what the heading drift
  costs (the only artefact that turns the pelvis; at 2°/min a fraction of a degree per take);
- ``clean``: the clean take (a perfect cleaner): what is left is the policy's own loss on the
  clips plus what the judge (the take as given, drifted and skating) costs it.

The rows run on the same clips, artefact seeds and start frames, side by side in one run;
``--rows`` picks some of them (``given``, ``denoised``, ``clean_root``, ``clean_joints``, ``imu_path``,
``imu_rotation``, ``clean``).
``--draws N`` repeats every row on N artefact draws (draw k: seed ``--seed + k * len(clips)``, so
the clips' seeds never overlap), each row's ELR then the mean over every rollout and its paired
difference from the first row per draw is reported (mean ± standard error over draws). As
``evaluate.py`` does, ``--ground`` and ``--swing-lift`` prepare every row's tracked take after the
denoiser (:func:`envs.preparation.prepared`), and ``--mirror-average`` makes the actor symmetric.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips, tracked_label
from agents.evaluation import evaluate_tracking, per_clip, summarize
from agents.mirror import actor_label
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from envs.preparation import prepared
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.artefacts import ARTEFACT_KINDS
from reference_motion.cli import positive_int
from reference_motion.grounding import add_grounding_option, grounding_of
from reference_motion.motion import Motion
from reference_motion.swing_lift import add_swing_lift_options, swing_lift_of

ROWS = ("given", "denoised", "clean_root", "clean_joints", "imu_path", "imu_rotation", "clean")
"""The rows, in the order they run."""
SPLICED_ROWS = {"clean_root": ("clean root", slice(7, None)),
                "clean_joints": ("clean joints and height", [0, 1, 3, 4, 5, 6]),
                "imu_path": ("clean on the take's path", [0, 1]),
                "imu_rotation": ("clean with the take's pelvis rotation", [3, 4, 5, 6])}
"""The rows that track the clean take with some qpos columns of the IMU take: (name, columns):
its hinge angles; its pelvis placement without the height (horizontal position, m, and
orientation); its horizontal pelvis position; its pelvis orientation (quaternion w, x, y, z)."""


def with_columns_of(motion: Motion, other: Motion, columns: list[int] | slice) -> Motion:
    """``motion`` with qpos ``columns`` taken from ``other``, frame by frame (same length and rate)."""
    qpos = motion.qpos.copy()
    qpos[:, columns] = other.qpos[:, columns]
    taken = np.arange(qpos.shape[1])[columns].tolist()
    return motion.with_qpos(qpos, source={**motion.source, "qpos_columns_from": [taken, other.source]})


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general_steered")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=20, help="rollouts per clip and row")
    p.add_argument("--kind", choices=("imu",) + ARTEFACT_KINDS, default="imu", help="artefact kinds: all, or one")
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=9100, help="artefact seed of the first clip (clip i of draw k gets seed + k * clips + i)")
    p.add_argument("--denoise", nargs="*", type=Path, default=[Path("models/imu_denoiser_dm")], metavar="DIR",
                   help="IMU denoisers, a row each")
    p.add_argument("--rows", nargs="+", choices=ROWS, default=list(ROWS), help="which rows to run")
    p.add_argument("--draws", type=positive_int, default=1, help="artefact draws (each row on each)")
    p.add_argument("--mirror-average", action="store_true", help="the symmetric actor (agents/mirror.py)")
    add_grounding_option(p, "every row's tracked take")
    add_swing_lift_options(p, "every row's tracked take")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    model, config = FOOT_MODELS[policy.foot], MimicConfig()
    grounding, lift = grounding_of(args), swing_lift_of(args)
    nets = ({path: load_network(path, "denoiser") for path in dict.fromkeys(args.denoise)}  # each once
            if "denoised" in args.rows else {})
    runs_of: dict[str, list] = {}
    elr_of_draw: dict[str, list[float]] = {}
    clean = reference_clips(args.clips, model, config, None, args.strength, args.seed)
    for draw in range(args.draws):
        seed = args.seed + draw * len(clean)
        given = reference_clips(args.clips, model, config, args.kind, args.strength, seed)
        rows = {}
        if "given" in args.rows:
            rows["given"] = given
        if "denoised" in args.rows:
            for path, net in nets.items():
                rows[f"denoised {path}"] = [denoise(net, c) for c in given]
        for row, (name, columns) in SPLICED_ROWS.items():
            if row in args.rows:
                rows[name] = [with_columns_of(c, g, columns) for g, c in zip(given, clean)]
        if "clean" in args.rows:
            rows["clean"] = clean
        for name, tracked in rows.items():
            tracked = [prepared(c, None, grounding=grounding, lift=lift) for c in tracked]
            summary, runs = evaluate_tracking(policy, tracked, given, episodes=args.episodes,
                                              mirror_average=args.mirror_average)
            runs_of.setdefault(name, []).extend(runs)
            elr_of_draw.setdefault(name, []).append(summary["ELR_mean"])
            print(f"draw {draw} (seed {seed}) {name:<44} ELR {summary['ELR_mean']:.3f}", flush=True)
    table = []
    first = next(iter(elr_of_draw.values()), None)
    for name, runs in runs_of.items():
        summary = summarize(runs)
        gap = np.asarray(elr_of_draw[name]) - np.asarray(first)
        row = {"tracked": name, "rollouts": len(runs), "ELR": summary["ELR_mean"], "SR90": summary["SR90"],
               "RDE": summary["RDE_mean"], "ELR_per_draw": elr_of_draw[name],
               "vs_first_row": {"mean": float(gap.mean()),
                                "stderr": float(gap.std(ddof=1) / np.sqrt(len(gap))) if len(gap) > 1 else None},
               "ended_by": dict(Counter(r.ended_by for r in runs)), "per_clip": per_clip(runs)}
        table.append(row)
        spread = row["vs_first_row"]["stderr"]
        print(f"{name:<44} ELR {row['ELR']:.3f}  SR90 {row['SR90']:.2f}  RDE {row['RDE']:.4f} m²  vs first row "
              f"{gap.mean():+.3f}" + (f" ± {spread:.3f}" if spread is not None else ""), flush=True)
    actor = tracked_label(actor_label(args.policy, args.mirror_average), grounding=grounding, lift=lift)
    emit_json({"policy": args.policy, "actor": actor, "clips": args.clips, "episodes": args.episodes,
               "kind": args.kind, "strength": args.strength, "seed": args.seed, "draws": args.draws,
               "seeds_of_first_clip": [args.seed + k * len(clean) for k in range(args.draws)],
               "first_row": next(iter(runs_of), None),
               "judged_against": "the IMU take as given", "rows": table}, args.json)


if __name__ == "__main__":
    main()
