"""ContactVision Table 1 on our data: the ContactTransformer against its three ablations, trained
with the same budget and scored on the held-out test clips seen from the held-out views.

Usage: ``python bench/keypoint_ablations.py --dataset data/physics [--epochs 12] [--runs runs/ablations] [--json [OUT]]``

Variants (everything else identical, seed 0): ``proposed`` (lower body, learnable PE, random
subsequences), ``sinusoidal_pe``, ``full_body`` (all 25 BODY_25 keypoints), ``sliding_window``
(stride-1 windows inside episodes). Each trains for exactly ``--epochs`` epochs (early stopping
off, so budgets match; the best validation epoch is scored). Runs are resumable: re-running
continues unfinished variants and re-scores finished ones.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

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
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    test = load_keypoint_split(args.dataset, "test")
    result = {"epochs": args.epochs, "dataset": str(args.dataset), "views": "rig at the held-out azimuths",
              "variants": {}}
    for name in args.variants:
        config = replace(KeypointTrainConfig(), max_epochs=args.epochs, patience=args.epochs + 1, **VARIANTS[name])
        sidecar = train_keypoints(args.dataset, args.runs / name, config)
        net = ContactTransformer(**sidecar["network"])
        net.load_state_dict(torch.load(args.runs / name / "best.pt"))
        filmed = film_split(test, held_out_views(), config.keypoints, seed=0, test=True)
        scores = evaluate_keypoint_contacts(net.eval(), filmed, progress=True)
        overall = scores["scores"]["overall"]
        result["variants"][name] = {**overall, "best_epoch": sidecar["best_epoch"], "wall_s": sidecar["wall_s"],
                                    "gait": scores["gait"], "contactvision_f1": CONTACTVISION_F1[name]}
    print(f"{'variant':<16}{'precision':>10}{'recall':>8}{'F1':>7}   ContactVision F1   (test clips, held-out views, "
          f"{args.epochs} epochs each)")
    for name, r in result["variants"].items():
        print(f"{name:<16}{r['precision']:>10.3f}{r['recall']:>8.3f}{r['f1']:>7.3f}   {r['contactvision_f1']:.2f}")
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
