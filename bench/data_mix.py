"""ADAPT's data-mix finding at small scale: clean-only vs corrupted-only vs mixed training.

Usage: ``python bench/data_mix.py [--steps 2500000] [--runs-dir runs/data_mix] [--json [OUT]]``

Three policies are trained with ``agents/train_ppo.py`` on the locomotion clips minus the three
held-out ones (walker/0walk_forward, walker/turn_left1, walker/turn_right1), identical but for the
share of episodes with an IMU-corrupted reference (0, 1, 0.5; strength 0.5–1). Each is evaluated
with ``agents/evaluate.py`` on the held-out clips corrupted at strength 1 with seeds 1000–1002,
which training never uses (its variants draw seeds from the run seed). Re-running resumes
unfinished runs and skips finished ones; the mixed run is the one shipped as ``models/mimic_imu``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/

HELD_OUT = ["deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1"]
MIXES = {"clean_only": 0.0, "corrupted_only": 1.0, "mixed": 0.5}


def train(run: Path, fraction: float, steps: int) -> None:
    from agents.train_ppo import main as train_ppo

    args = ["--run-dir", str(run), "--clips", "locomotion", "--exclude", *HELD_OUT, "--eval-clips", *HELD_OUT,
            "--corrupted-fraction", str(fraction), "--total-steps", str(steps), "--lr", "1e-4",
            "--eval-every", "250000", "--checkpoint-every", "100000", "--eval-episodes", "5", "--no-progress"]
    train_ppo(["--run-dir", str(run), "--resume", "--total-steps", str(steps), "--no-progress"]
              if (run / "args.json").exists() else args)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=2_500_000)
    parser.add_argument("--runs-dir", type=Path, default=Path("runs/data_mix"))
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    from agents import evaluate

    rows = {}
    for name, fraction in MIXES.items():
        run = args.runs_dir / name
        train(run, fraction, args.steps)
        result = evaluate.main(["--policy", str(run / "best"), "--clips", *HELD_OUT, "--corrupt", "imu",
                                "--strength", "1", "--seed", "1000", "--episodes", str(args.episodes),
                                "--json", str(run / "heldout_eval.json")])
        rows[name] = {"corrupted_fraction": fraction, **{k: result[k] for k in ("ELR_mean", "ELR_std", "SR90",
                                                                                  "RDE_mean", "MRR_mean")},
                      "artefacts": result["artefacts"]}
    print("| training data | ELR | SR90 | RDE (m²) | MRR | foot skate out (m/s) | penetration max out (cm) |")
    print("|---|---|---|---|---|---|---|")
    for name, r in rows.items():
        a = r["artefacts"]
        print(f"| {name} | {r['ELR_mean']:.3f} ± {r['ELR_std']:.3f} | {r['SR90']:.2f} | {r['RDE_mean']:.4f} | "
              f"{r['MRR_mean']:.3f} | {a['foot_skate_mps']['output']:.3f} | {100 * a['penetration_max_m']['output']:.2f} |")
    emit_json({"steps": args.steps, "held_out": HELD_OUT, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
