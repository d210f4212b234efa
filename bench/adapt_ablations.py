"""ADAPT Table 4 at small scale: the training-data mix and the observation / action configurations.

Usage: ``python bench/adapt_ablations.py --data {deepmimic,library} [--configs NAME ...] [--steps N]
[--runs-dir DIR] [--json [OUT]]``

Each configuration is one ``agents/train_ppo.py`` run, identical to the others (budget, seed,
network, clips, PPO settings) but for what the configuration changes:

============== ====================== ==================== =================================
configuration  environment            corrupted episodes   ADAPT Table 4 row
============== ====================== ==================== =================================
clean_only     ``MimicIMU-v0``        0                    optical (clean) data only
corrupted_only ``MimicIMU-v0``        all                  IMU data only
mixed          ``MimicIMU-v0``        half                 IMU + optical (ADAPT's own)
drecon         ``MimicDReCon-v0``     half                 DReCon configuration
full_action    ``MimicFullAction-v0`` half                 full state & action space
============== ====================== ==================== =================================

Data (``--data``):

* ``deepmimic``: the locomotion clips minus the three held-out walkers (walker/0walk_forward,
  turn_left1, turn_right1), which are also the evaluation clips during training and the test.
* ``library``: the motion library's train split (``data/library``, made by ``python -m
  reference_motion import``) plus DeepMimic walk, run, turn_left0 and turn_right0, mirrored, as
  ``models/mimic_general`` was trained; model selection on the validation split; the test is the
  test split (styles never seen), which no run sees before the final evaluation.

Each run's best checkpoint (by its evaluations on the selection clips) is evaluated with
``agents/evaluate.py`` on the test clips corrupted at IMU strength 1 with seeds from 1000 on, which
training never uses (its variants draw seeds from the run seed). Re-running resumes unfinished runs
and skips finished ones, so the script can be stopped and started again.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/

HELD_OUT = ["deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1"]


@dataclass(frozen=True)
class Configuration:
    """One Table 4 row: the environment and the share of episodes with a corrupted reference."""

    env_id: str
    corrupted_fraction: float


CONFIGURATIONS = {
    "clean_only": Configuration("MimicIMU-v0", 0.0),
    "corrupted_only": Configuration("MimicIMU-v0", 1.0),
    "mixed": Configuration("MimicIMU-v0", 0.5),
    "drecon": Configuration("MimicDReCon-v0", 0.5),
    "full_action": Configuration("MimicFullAction-v0", 0.5),
}


@dataclass(frozen=True)
class Data:
    """Training clips and options, model-selection clips, test clips and default budget of a ``--data``."""

    train: list[str]
    train_options: list[str]
    selection: list[str]
    test: list[str]
    steps: int
    runs_dir: Path
    configs: list[str]


DATA = {
    "deepmimic": Data(["locomotion", "--exclude", *HELD_OUT], ["--lr", "1e-4", "--eval-every", "250000"],
                      HELD_OUT, HELD_OUT, 2_500_000, Path("runs/data_mix"), ["clean_only", "corrupted_only", "mixed"]),
    "library": Data(["library:data/library/train", "deepmimic:walk", "deepmimic:run", "deepmimic:walker/turn_left0",
                     "deepmimic:walker/turn_right0"], ["--mirror", "--lr", "1e-4", "--eval-every", "250000"],
                    ["library:data/library/val"], ["library:data/library/test"], 1_000_000,
                    Path("runs/adapt_ablations"), list(CONFIGURATIONS)),
}


def train(run: Path, config: Configuration, data: Data, steps: int) -> None:
    """Train (or resume, or leave alone if finished) the run of ``config`` in ``run``; exits if the
    run was interrupted (``kill``: the checkpoint is saved, and the same command resumes it)."""
    from agents.train_ppo import CHECKPOINT, newest_checkpoint
    from agents.train_ppo import main as train_ppo

    if (run / "args.json").exists():
        # sharded stepping (the default since) gives the same transitions as a run's earlier in-process
        # envs, on both cores
        train_ppo(["--run-dir", str(run), "--resume", "--total-steps", str(steps), "--vec", "sharded",
                   "--torch-threads", "1", "--no-progress"])
    else:
        train_ppo(["--run-dir", str(run), "--env-id", config.env_id, "--clips", *data.train, "--eval-clips",
                   *data.selection, "--corrupted-fraction", str(config.corrupted_fraction), "--total-steps", str(steps),
                   *data.train_options, "--checkpoint-every", "100000", "--eval-episodes", "5", "--no-progress"])
    newest = newest_checkpoint(run)
    if newest is None or int(CHECKPOINT.search(newest.name).group(1)) < steps:
        raise SystemExit(f"{run}: stopped before {steps} steps; run the same command again to resume")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", choices=list(DATA), default="library")
    parser.add_argument("--configs", nargs="+", choices=list(CONFIGURATIONS), default=None,
                        help="configurations to run (default: the data's: all five for library, the data mix "
                             "for deepmimic)")
    parser.add_argument("--steps", type=int, default=None, help="control steps per run (default: the data's)")
    parser.add_argument("--runs-dir", type=Path, default=None, help="where the runs live (default: the data's)")
    parser.add_argument("--episodes", type=int, default=None,
                        help="test rollouts per clip (default: 20 on the three DeepMimic walkers, 5 on the "
                             "library's 22 test takes)")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args(argv)
    from agents import evaluate

    data = DATA[args.data]
    steps = args.steps or data.steps
    runs_dir = args.runs_dir or data.runs_dir
    episodes = args.episodes or (20 if args.data == "deepmimic" else 5)
    rows = {}
    for name in args.configs or data.configs:
        config, run = CONFIGURATIONS[name], runs_dir / name
        train(run, config, data, steps)
        result = evaluate.main(["--policy", str(run / "best"), "--clips", *data.test, "--corrupt", "imu",
                                "--strength", "1", "--seed", "1000", "--episodes", str(episodes),
                                "--json", str(run / "test_eval.json")])
        rows[name] = {"env_id": config.env_id, "corrupted_fraction": config.corrupted_fraction,
                      **{k: result[k] for k in ("ELR_mean", "ELR_std", "SR90", "RDE_mean", "MRR_mean", "MRR_std")},
                      "artefacts": result["artefacts"]}
    print("| configuration | environment | corrupted share | ELR | SR90 | RDE (m²) | MRR | "
          "foot skate out (m/s) | penetration max out (cm) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, r in rows.items():
        a = r["artefacts"]
        print(f"| {name} | {r['env_id']} | {r['corrupted_fraction']:g} | {r['ELR_mean']:.3f} ± {r['ELR_std']:.3f} | "
              f"{r['SR90']:.2f} | {r['RDE_mean']:.4f} | {r['MRR_mean']:.3f} ± {r['MRR_std']:.3f} | "
              f"{a['foot_skate_mps']['output']:.3f} | {100 * a['penetration_max_m']['output']:.2f} |")
    emit_json({"data": args.data, "steps": steps, "test": data.test, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
