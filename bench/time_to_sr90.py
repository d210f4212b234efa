"""Wall time for ``agents/train_ppo.py`` (2 cores) to reach SR90 ≥ 0.9 on walk.

Usage: ``python bench/time_to_sr90.py [--run-dir runs/time_to_sr90] [--lr 1e-4] [--epochs 6] [--seed 0]
[--json [OUT]] [TRAIN_PPO_OPTION ...]``

Trains from scratch on ``deepmimic:walk`` with the default configuration (learning rate and PPO epochs
per rollout as given), evaluating 5 rollouts every 100,000 steps, and stops at the first evaluation
with SR90 ≥ 0.9. Reports the steps, the wall time, and the training throughput in 60 Hz frames/s over
the whole run (evaluations included). Any other option is passed on to ``agents/train_ppo.py`` (e.g.
``--vec sharded-batched --n-envs 64``; not ``--clips`` or ``--stop-at-sr90``, which this benchmark
fixes) and recorded in the JSON.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

from agents.train_ppo import main as train
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run-dir", type=Path, default=Path("runs/time_to_sr90"))
    parser.add_argument("--lr", default="1e-4")
    parser.add_argument("--epochs", default="6", help="PPO optimisation epochs per rollout (train_ppo.py's default: 6)")
    parser.add_argument("--max-steps", type=int, default=3_000_000)
    parser.add_argument("--seed", default="0")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args, train_options = parser.parse_known_args()
    shutil.rmtree(args.run_dir, ignore_errors=True)
    train(["--run-dir", str(args.run_dir), "--clips", "deepmimic:walk", "--lr", args.lr, "--total-steps",
           str(args.max_steps), "--eval-every", "100000", "--checkpoint-every", "100000", "--eval-episodes", "5",
           "--stop-at-sr90", "0.9", "--seed", args.seed, "--epochs", args.epochs, "--no-progress",
           *train_options])
    evals = [json.loads(line) for line in (args.run_dir / "evaluations.jsonl").read_text().splitlines()]
    hit = next((e for e in evals if e["SR90"] >= 0.9), None)
    last = hit or evals[-1]  # the evaluation that reached SR90, or the run's last
    result = {"lr": float(args.lr), "epochs": int(args.epochs), "train_options": train_options, "seed": int(args.seed),
              "reached": hit is not None,
              "steps": last["steps"], "wall_s": round(last["wall_s"], 1),
              "frames_per_s": round(2 * last["steps"] / last["wall_s"]),
              "evaluations": [{k: e[k] for k in ("steps", "wall_s", "ELR_mean", "SR90")} for e in evals]}
    if not emit_json(result, args.json):
        print(f"SR90 >= 0.9 after {result['steps']} steps, {result['wall_s']:.0f} s ({result['frames_per_s']} "
              f"frames/s)" if hit else f"not reached in {result['steps']} steps")


if __name__ == "__main__":
    main()
