"""ContactVision Table 1 on our data: the ContactTransformer against its three ablations, trained
with the same budget and scored on the held-out test clips seen from the held-out views.

Usage: ``python bench/keypoint_ablations.py --dataset data/physics [--epochs 12] [--seeds 0 1] [--runs runs/ablations] [--json [OUT]]``

Variants (everything else identical, seed 0): ``proposed`` (lower body, learnable PE, random
subsequences), ``sinusoidal_pe``, ``full_body`` (all 25 BODY_25 keypoints), ``sliding_window``
(stride-1 windows inside episodes). Each trains for exactly ``--epochs`` epochs per seed (early
stopping off, so budgets match; the best validation epoch is scored); F1 is reported per seed and
as the mean. Runs are resumable: re-running continues unfinished runs and re-scores finished ones,
so seeds or variants can be trained by parallel invocations and gathered by a last one.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.contact_transformer import ContactTransformer
from perception.keypoint_data import held_out_views, load_keypoint_split
from perception.keypoint_evaluation import evaluate_keypoint_contacts, film_split
from perception.keypoint_training import KeypointTrainConfig, train_keypoints

VARIANTS = {"proposed": {}, "sinusoidal_pe": {"positional": "sinusoidal"}, "full_body": {"keypoints": "full"},
            "sliding_window": {"sampling": "sliding"}}
CONTACTVISION_F1 = {"proposed": 0.93, "sinusoidal_pe": 0.87, "full_body": 0.86, "sliding_window": 0.88}
"""ContactVision Table 1's F1 (real video, BioCV) for reference."""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dataset", type=Path, required=True)
    p.add_argument("--epochs", type=int, default=12)
    p.add_argument("--runs", type=Path, default=Path("runs/ablations"))
    p.add_argument("--variants", nargs="+", choices=tuple(VARIANTS), default=list(VARIANTS))
    p.add_argument("--seeds", nargs="+", type=int, default=[0])
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    test = load_keypoint_split(args.dataset, "test")
    result = {"epochs": args.epochs, "dataset": str(args.dataset), "views": "rig at the held-out azimuths",
              "variants": {}}
    for name in args.variants:
        runs = []
        for seed in args.seeds:
            config = replace(KeypointTrainConfig(), max_epochs=args.epochs, patience=args.epochs + 1, seed=seed,
                             **VARIANTS[name])
            run_dir = args.runs / (name if seed == 0 else f"{name}_seed{seed}")
            sidecar = train_keypoints(args.dataset, run_dir, config)
            net = ContactTransformer(**sidecar["network"])
            net.load_state_dict(torch.load(run_dir / "best.pt"))
            filmed = film_split(test, held_out_views(), config.keypoints, seed=0, test=True)
            scores = evaluate_keypoint_contacts(net.eval(), filmed, progress=True)
            runs.append({"seed": seed, **scores["scores"]["overall"], "best_epoch": sidecar["best_epoch"],
                         "wall_s": sidecar["wall_s"], "gait": scores["gait"]})
        f1 = [r["f1"] for r in runs]
        result["variants"][name] = {"f1_mean": float(np.mean(f1)), "f1_range": [min(f1), max(f1)],
                                    "precision_mean": float(np.mean([r["precision"] for r in runs])),
                                    "recall_mean": float(np.mean([r["recall"] for r in runs])),
                                    "runs": runs, "contactvision_f1": CONTACTVISION_F1[name]}
    print(f"{'variant':<16}{'precision':>10}{'recall':>8}{'F1':>7}  F1 per seed{'':<8}ContactVision F1   (test clips, "
          f"held-out views, {args.epochs} epochs each, seeds {args.seeds})")
    for name, r in result["variants"].items():
        per_seed = " ".join(f"{run['f1']:.3f}" for run in r["runs"])
        print(f"{name:<16}{r['precision_mean']:>10.3f}{r['recall_mean']:>8.3f}{r['f1_mean']:>7.3f}  {per_seed:<19}"
              f"{r['contactvision_f1']:.2f}")
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
