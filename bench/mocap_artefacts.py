"""How far below an IMU-corrupted take its clean mocap lies: what a cleaner that recovered the
original motion would score on the artefact goals.

Usage: ``python bench/mocap_artefacts.py --clips TAKE ... [--seed 5000] [--seconds 10] [--json [OUT]]``

Each take ``i`` is cut to ``--seconds`` and corrupted at IMU strength 1 with seed ``--seed + i``
exactly as ``bench/adapted_cleaning.py`` does for a policy of the one-segment foot
(``humanoid_1seg``, as ``mimic_general``); the clean take is cut the same way. Reported per take
and as medians: foot skate, floating, penetration (max, mean) and jitter of both, and how far below
the corrupted copy the clean one lies (``n/a`` where the corrupted copy has none).
"""

from __future__ import annotations

import argparse

import numpy as np

from adapted_cleaning import ARTEFACTS, corrupted_take, cut_take, reduction, reduction_of  # bench/: the scripts run from there
from json_report import emit_json
from reference_motion.library import expand_clips
from reference_motion.quality import motion_quality


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", required=True)
    p.add_argument("--seed", type=int, default=5000)
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    rows = []
    for i, clip in enumerate(expand_clips(args.clips)):
        corrupted = corrupted_take(clip, "one", args.seconds, 1.0, args.seed + i)
        clean = cut_take(clip, "one", args.seconds)
        before, after = motion_quality(corrupted).as_dict(), motion_quality(clean).as_dict()
        rows.append({"clip": clip, "seed": args.seed + i, **{f"{k}_corrupted": before[k] for k in ARTEFACTS},
                     **{f"{k}_clean": after[k] for k in ARTEFACTS},
                     **{f"{k}_reduction": reduction_of(before[k], after[k]) for k in ARTEFACTS}})
        print(f"{clip.split('#')[-1]:<32} " + "  ".join(f"{k} {reduction(rows[-1][f'{k}_reduction'])}"
                                                          for k in ARTEFACTS))
    summary = {k: float(np.nanmedian([r[f"{k}_reduction"] for r in rows])) for k in ARTEFACTS}
    print("median: " + "  ".join(f"{k} {v:.0%}" for k, v in summary.items()))
    emit_json({"seed": args.seed, "seconds": args.seconds, "summary": summary, "takes": rows}, args.json)


if __name__ == "__main__":
    main()
