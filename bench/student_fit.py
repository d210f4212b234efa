"""How well students of several widths fit a distillation's labelled states: capacity or information?

Usage: ``python bench/student_fit.py --run runs/distill_privileged_corrupt --nets 256,256 512,512
1024,1024 --epochs 20 [--json [OUT]]``

A privileged distillation (``agents/distill.py --teacher-reads clean``) held its held-out action
RMSE at 0.14-0.15 rad from round 0 on, where students of a teacher that reads what they read fit to
0.07-0.12 (README, "Round 16"). Either a [256, 256] network cannot hold the mapping (a wider one
fits the training states closer and the held-out ones with them), or the corrupted take does not
show that much of the teacher's action on the clean one (every width stalls at the same held-out
error however close it fits the training states). This fits fresh students of each ``--nets`` to
the run's labelled states (``data.npz``; the held-out tenth of episodes as the run splits it) for
``--epochs`` passes of :func:`agents.distill.fit` (the run's batch size and learning rate), and
prints each width's action RMSE (rad) on the training states and the held-out ones after every
``--report-every`` epochs, with the fitting wall time on this machine.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from agents.distill import DistillConfig, Labels, fit, fit_report, new_student, split_holdout
from agents.policy import load_policy
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/


def read_run(run: Path) -> tuple[dict, Labels]:
    """The run's ``args.json`` and labelled states, with a clear error where either is missing."""
    settings, data = run / "args.json", run / "data.npz"
    for file in (settings, data):
        if not file.is_file():
            raise SystemExit(f"{file}: missing; --run must be an agents/distill.py --out directory with its "
                             "labelled states (data.npz stays in runs/, it is not committed)")
    return json.loads(settings.read_text()), Labels.load(data)


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--run", type=Path, required=True, help="an agents/distill.py --out directory")
    p.add_argument("--nets", nargs="+", default=["256,256", "512,512", "1024,1024"])
    p.add_argument("--epochs", type=int, default=20)
    p.add_argument("--report-every", type=int, default=5, help="epochs between two RMSE reports")
    p.add_argument("--train-sample", type=int, default=50_000, help="training states the training RMSE is read on")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args(argv)
    settings, labels = read_run(args.run)
    base = DistillConfig(batch_size=settings["batch_size"], lr=settings["lr"], seed=settings["seed"])
    train_rows, held = split_holdout(labels, base.holdout, base.seed)
    rng = np.random.default_rng(base.seed)  # the rows drawn as from a copy of the training states
    sample = labels.take(rng.choice(train_rows, min(args.train_sample, len(train_rows)), replace=False))
    default = load_policy(settings["teacher"])
    env = default.make_env(["deepmimic:walk"])  # the spaces only: any clip observes alike
    sigma = float(default.model.policy.log_std.detach().exp().mean())
    print(f"{args.run}: {len(train_rows)} training states, {len(held)} held out", flush=True)
    rows = []
    for net in args.nets:
        config = replace(base, net=net, epochs=args.report_every)
        student = new_student(env, default, config)
        started, curve = time.monotonic(), []
        for done in range(args.report_every, args.epochs + 1, args.report_every):
            fit(student, labels, config, sigma, rng, progress=False, rows=train_rows)
            point = {"epochs": done, "train_rmse": fit_report(student, sample, [])["action_rmse"],
                     "held_out_rmse": fit_report(student, held, [])["action_rmse"],
                     "wall_s": time.monotonic() - started}
            curve.append(point)
            print(f"net {net:>10}  epoch {done:3d}  train {point['train_rmse']:.4f}  held out "
                  f"{point['held_out_rmse']:.4f} rad  ({point['wall_s']:.0f} s)", flush=True)
        rows.append({"net": net, "curve": curve})
    env.close()
    result = {"run": str(args.run), "states": len(labels), "train_states": len(train_rows),
              "held_out_states": len(held), "epochs": args.epochs, "rows": rows}
    emit_json(result, args.json)
    return result


if __name__ == "__main__":
    main()
