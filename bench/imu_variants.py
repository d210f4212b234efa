"""Where a policy's losses to IMU artefacts come from, on the clips it trained on.

Usage: ``python bench/imu_variants.py --policy models/mimic_general_still [--run DIR] [--clip-every 10]
[--episodes 8] [--strength 1] [--seed 777] [--json [OUT]]``

The policy's training clips (rebuilt from its run's ``args.json``: ``--run``, default the
policy's ``run/`` folder; mirrored and time-warped copies included, every ``--clip-every``-th),
the same start frames, side by side in one run, with the references:

- ``clean``: as given;
- ``trained variants``: the corrupted variants PPO trained on (the run's ``ArtefactMix`` seed,
  strength range and variant count, :func:`agents.train_ppo.artefact_mix`), i.e. what it could have
  memorised;
- ``fresh variants``: the same recipe and strength range from another seed (``--seed``): what
  a new take of a known motion looks like;
- ``imu``: every artefact kind at ``--strength`` (the evaluation protocol's), fresh seed;
- each artefact kind alone at ``--strength``, fresh seed.

Per row: ELR and SR90 (:mod:`agents.evaluation`), and how the rollouts that ended early ended:
the simulated root's height at the end against the reference's (a fall, when far below) and
their horizontal gap (m), medians over those rollouts.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.evaluation import evaluate, summarize
from agents.policy import load_policy
from agents.train_ppo import artefact_mix, run_args, training_motions
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe


def early_ends(runs: list) -> dict[str, float]:
    """Of ``runs`` that ended before their time limit: how many, and medians of the simulated and
    reference root heights (m) at the last simulated frame and of their horizontal gap (m)."""
    ended = [r for r in runs if r.ended_by != "time_limit"]
    if not ended:
        return {"early": 0}
    sim = np.array([r.simulated.qpos[-1, :3] for r in ended])
    ref = np.array([r.reference.qpos[-1, :3] for r in ended])  # the reference over the simulated frames
    return {"early": len(ended), "root_z_m": float(np.median(sim[:, 2])),
            "reference_root_z_m": float(np.median(ref[:, 2])),
            "gap_m": float(np.median(np.linalg.norm(sim[:, :2] - ref[:, :2], axis=1)))}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", required=True, help="policy directory")
    p.add_argument("--run", type=Path, default=None,
                   help="the run that trained it (its args.json; default: POLICY/run)")
    p.add_argument("--clip-every", type=int, default=10, help="every n-th training clip (mirrored copies count)")
    p.add_argument("--episodes", type=int, default=8, help="rollouts per clip and row")
    p.add_argument("--offset-step", type=int, default=20, help="frames between a clip's start offsets")
    p.add_argument("--strength", type=float, default=1.0, help="strength of the imu and single-kind rows")
    p.add_argument("--seed", type=int, default=777, help="seed of the fresh variants (not the run's)")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    run = run_args(args.run or Path(args.policy) / "run")
    if not run.corrupted_fraction:
        p.error(f"{run.run_dir}: the run trained on clean clips only; it has no corrupted variants")
    trained = artefact_mix(run, 1.0)
    if trained.seed is None:
        p.error(f"{run.run_dir}: a run with one subprocess per env (--vec subproc) gave each env its own variants; "
                "they cannot be rebuilt here")
    if trained.seed == args.seed:
        p.error(f"--seed {args.seed} is the run's own variant seed; pick another for the fresh variants")
    motions = training_motions(run)
    picks = list(range(0, len(motions), args.clip_every))
    at = (args.strength, args.strength)  # the other rows differ from the trained variants only as named
    rows = [("clean", replace(trained, fraction=0.0)), ("trained variants", trained),
            ("fresh variants", replace(trained, seed=args.seed)),
            ("imu", replace(trained, recipe=ArtefactRecipe.imu(), strength=at, seed=args.seed))]
    rows += [(kind, replace(trained, recipe=ArtefactRecipe.only(kind), strength=at, seed=args.seed))
             for kind in ARTEFACT_KINDS]
    print(f"{args.policy}: {len(picks)} of its {len(motions)} training clips, {args.episodes} rollouts each; trained "
          f"variants: seed {trained.seed}, strength {trained.strength[0]:g}-{trained.strength[1]:g}, "
          f"{trained.variants_per_clip} per clip", flush=True)
    table = []
    for name, mix in rows:
        env = policy.make_env(motions, artefacts=mix)
        env.reset(seed=args.seed)  # which variant each rollout draws; the variants themselves follow mix.seed
        runs = evaluate(env, policy, clips=picks, episodes=args.episodes, offset_step=args.offset_step,
                        corrupted=name != "clean")[1]
        summary = summarize(runs)
        row = {"row": name, "rollouts": len(runs), "ELR": summary["ELR_mean"], "SR90": summary["SR90"],
               **early_ends(runs)}
        table.append(row)
        ends = (f"{row['early']} ended early: root {row['root_z_m']:.2f} m up (reference "
                f"{row['reference_root_z_m']:.2f}), {row['gap_m']:.2f} m apart" if row["early"] else "none ended early")
        print(f"{name:<17} ELR {row['ELR']:.3f}  SR90 {row['SR90']:.2f}  {ends}", flush=True)
    emit_json({"policy": args.policy, "clips": [motions[i].name for i in picks], "episodes": args.episodes,
               "strength": args.strength, "seed": args.seed, "trained_seed": trained.seed,
               "trained_strength": list(trained.strength), "rows": table}, args.json)


if __name__ == "__main__":
    main()
