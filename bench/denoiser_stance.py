"""Does an IMU denoiser give a wide stance back? Takes walked wider, IMU-corrupted, denoised.

Usage: ``python bench/denoiser_stance.py --denoisers models/imu_denoiser_soles_quint_mirror [DIR ...]
[--clips library:data/library/val] [--extra 0 0.2 0.35] [--draws 2] [--first-seed 1030000] [--json [OUT]]``

The suit's hip adduction offset is nearly the same for every take: at IMU strength 1 it narrows the
feet's median sideways gap (:func:`reference_motion.leg_gap.lateral_foot_gap`) by about 0.22 m. A
denoiser must tell that offset from a take that really walks wide (the unseen style "giant" does).
Every take of ``--clips`` is walked ``--extra`` metres wider (:func:`reference_motion.stance.wider_stance`,
the body swaying as the wider steps need), corrupted at IMU strength 1 (draw ``j`` of take ``i``: seed
``first_seed + 10·i + j``) and passed through each denoiser. Printed per width: the raw take's and
each denoiser's median foot gap minus the widened clean take's (m, mean ± standard error over takes and
draws), and each denoiser's RMS error (degrees) of the leg hinges and of all hinges against it.
"""

from __future__ import annotations

import argparse

import numpy as np

from agents.evaluate import reference_clips
from agents.gait_metrics import joint_angle_rmse_deg
from envs.config import MimicConfig
from json_report import emit_json
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.leg_gap import median_foot_gap
from reference_motion.leg_symmetry import LEG_HINGES
from reference_motion.motion import Motion
from reference_motion.stance import wider_stance

MODEL = "humanoid_1seg"


def median_gap(motion: Motion) -> float:
    """The feet's median sideways gap (m) over ``motion``."""
    return median_foot_gap(motion.model, motion.qpos)


def hinge_rms_deg(motion: Motion, truth: Motion, columns: list[int] | slice) -> float:
    """RMS difference (degrees) of ``motion``'s qpos ``columns`` (hinge angles) from ``truth``'s."""
    return joint_angle_rmse_deg(motion.qpos[:, columns], truth.qpos[:, columns])


def mean_and_error(values: list[float]) -> dict[str, float]:
    """Mean and standard error of ``values``."""
    a = np.asarray(values, dtype=float)
    return {"mean": float(a.mean()), "standard_error": float(a.std(ddof=1) / np.sqrt(len(a))) if len(a) > 1 else 0.0}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--denoisers", nargs="+", required=True, help="shipped IMU denoiser folders")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"], help="clean takes to widen")
    p.add_argument("--extra", type=float, nargs="+", default=[0.0, 0.2, 0.35], help="extra stance widths (m)")
    p.add_argument("--draws", type=int, default=2, help="IMU draws of each take and width")
    p.add_argument("--first-seed", type=int, default=1_030_000, help="artefact seed of the first take's first draw")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    if not 1 <= args.draws <= 10:
        p.error(f"--draws {args.draws}: expected 1 to 10 (take i's draws use seeds first_seed + 10·i + 0…9)")
    nets = {d: load_network(d, "denoiser") for d in args.denoisers}
    model = load_model(MODEL)
    legs = [model.qpos_index(h) for h in LEG_HINGES] + [model.qpos_index("r" + h[1:]) for h in LEG_HINGES]
    hinges = slice(7, None)
    clean = reference_clips(args.clips, MODEL, MimicConfig(), None, 1.0, 0)
    rows = []
    for extra in args.extra:
        raw_gap, gap, leg_rms, all_rms = [], {d: [] for d in nets}, {d: [] for d in nets}, {d: [] for d in nets}
        for i, take in enumerate(clean):
            wide = wider_stance(take, extra) if extra else take
            for j in range(args.draws):
                given = corrupt(wide, ArtefactRecipe.imu(1.0), args.first_seed + 10 * i + j)
                raw_gap.append(median_gap(given) - median_gap(wide))
                for d, net in nets.items():
                    out = denoise(net, given)
                    gap[d].append(median_gap(out) - median_gap(wide))
                    leg_rms[d].append(hinge_rms_deg(out, wide, legs))
                    all_rms[d].append(hinge_rms_deg(out, wide, hinges))
        row = {"extra_m": extra, "raw_gap_error_m": mean_and_error(raw_gap),
               "denoisers": {d: {"gap_error_m": mean_and_error(gap[d]), "leg_hinge_rms_deg": float(np.mean(leg_rms[d])),
                                 "hinge_rms_deg": float(np.mean(all_rms[d]))} for d in nets}}
        rows.append(row)
        print(f"stance {extra:+.2f} m: the raw take's gap {row['raw_gap_error_m']['mean']:+.3f} m off", flush=True)
        for d, r in row["denoisers"].items():
            print(f"  {d:<48} gap {r['gap_error_m']['mean']:+.3f} ± {r['gap_error_m']['standard_error']:.3f} m off, "
                  f"leg hinges {r['leg_hinge_rms_deg']:.2f}°, all hinges {r['hinge_rms_deg']:.2f}° RMS", flush=True)
    emit_json({"clips": args.clips, "draws": args.draws, "first_seed": args.first_seed, "rows": rows}, args.json)


if __name__ == "__main__":
    main()
