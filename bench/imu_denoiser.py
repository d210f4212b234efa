"""What the IMU denoiser undoes, artefact kind by kind, on takes it never trained on.

Usage: ``python bench/imu_denoiser.py [--denoiser models/imu_denoiser] [--splits val test]
[--strength 1] [--seed 9100] [--json [OUT]]``

Each take of each split of the motion library (``library:data/library/SPLIT``) is corrupted with
every artefact kind together (``imu``) and with each joint-angle or height kind alone, at
``--strength`` with seed ``--seed + i`` for take i, and passed clean too; the denoiser
(:mod:`perception.imu_denoiser`) corrects it. Reported per split and kind, before and after the
correction, against the clean take: the RMS error of the hinge angles (degrees, over frames and
hinges), the mean error of the pelvis height (cm), and the hip adduction offset (degrees: the mean
over frames of the two hips' x-angle error, averaged over the hips and takes), and the RMS error of
the four sole points relative to the pelvis, in its frame (cm: where the hinge angles put the feet,
``perception.denoiser_training.sole_points_in_pelvis_frame``). On a clean take the "after" column is
what the denoiser wrongly changes.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.denoiser_training import sole_points_in_pelvis_frame
from perception.imu_denoiser import DEFAULT_DENOISER, denoise
from perception.kinematics import torch_kinematics
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion

KINDS = ("clean", "imu", "adduction", "bias", "drift", "noise", "height")
"""Corruptions measured: none, every kind together, and each kind that acts on the hinge angles or
the pelvis height (what the denoiser corrects) alone."""


def soles(motion) -> torch.Tensor:
    """The four sole points of ``motion`` relative to its pelvis, in its frame ``(T, 4, 3)`` (m)."""
    return sole_points_in_pelvis_frame(torch_kinematics(motion.model), torch.from_numpy(motion.qpos[:, 7:]).float())


def errors(clean, clean_soles: torch.Tensor, given, hips: list[int]) -> dict[str, float]:
    """Hinge RMS error (deg), mean pelvis height error (cm), hip adduction offset (deg) and sole
    points' RMS error relative to the pelvis (cm) of ``given`` against ``clean`` (whose
    :func:`soles` are ``clean_soles``)."""
    diff = given.qpos - clean.qpos
    return {"hinge_rms_deg": float(np.degrees(np.sqrt((diff[:, 7:] ** 2).mean()))),
            "height_cm": float(100 * np.abs(diff[:, 2]).mean()),
            "hip_offset_deg": float(np.degrees(np.abs(diff[:, hips].mean(0)).mean())),
            "sole_rms_cm": float(100 * ((soles(given) - clean_soles) ** 2).sum(-1).mean().sqrt())}


def pooled(rows: list[dict[str, float]], key: str) -> float:
    """``key`` over the takes' ``rows``: the RMS of an RMS error, the mean of the others."""
    values = np.array([r[key] for r in rows])
    return float(np.sqrt(np.mean(values ** 2))) if "_rms_" in key else float(values.mean())


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--denoiser", type=Path, default=DEFAULT_DENOISER)
    p.add_argument("--library", default="data/library")
    p.add_argument("--splits", nargs="+", default=["val", "test"])
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=9100, help="artefact seed of the first take (take i: seed + i)")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    net = load_network(args.denoiser, "denoiser")
    hm = load_model(net.model)
    hips = [hm.qpos_index("l_thigh_x"), hm.qpos_index("r_thigh_x")]
    table = {}
    print(f"{'split':<6}{'kind':<11}{'hinge RMS (deg)':>18}{'height (cm)':>16}{'hip offset (deg)':>19}"
          f"{'soles RMS (cm)':>17}")
    for split in args.splits:
        takes = [load_motion(s, net.model) for s in expand_clips([f"library:{args.library}/{split}"])]
        take_soles = [soles(clean) for clean in takes]
        for kind in KINDS:
            before, after = [], []
            for i, (clean, clean_soles) in enumerate(zip(takes, take_soles)):
                given = clean if kind == "clean" else corrupt(clean, ArtefactRecipe.named(kind, args.strength),
                                                              args.seed + i)
                before.append(errors(clean, clean_soles, given, hips))
                after.append(errors(clean, clean_soles, denoise(net, given), hips))
            row = {key: {"before": pooled(before, key), "after": pooled(after, key)} for key in before[0]}
            table[f"{split}/{kind}"] = {"takes": len(takes), **row}
            print(f"{split:<6}{kind:<11}" + "".join(f"{row[k]['before']:>9.2f} → {row[k]['after']:<5.2f}"
                                                    for k in ("hinge_rms_deg", "height_cm", "hip_offset_deg", "sole_rms_cm")))
    emit_json({"denoiser": str(args.denoiser), "strength": args.strength, "seed": args.seed, "table": table},
              args.json)


if __name__ == "__main__":
    main()
