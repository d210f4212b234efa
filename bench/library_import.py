"""What the motion-library import made of the real mocap: takes kept and refused, quality per content.

Usage::

    python -m reference_motion import ../shared/mocap --out data/library     # ~2.5 min on 2 cores
    python bench/library_import.py --library data/library --json bench/results/library_import.json

Reads the library's manifest (written by the import) and reports: takes imported and refused (with
the reasons), takes per split, the import wall time, the retarget's bone-direction error (share of
takes with a mean ≤ 5°), and per content the mean artefact metrics of the retargeted takes before
and after footskate pinning (foot skate, penetration, floating, jitter) on ``humanoid_1seg``.
"""

from __future__ import annotations

import argparse
from collections import defaultdict

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.motion_library import SPLITS, read_manifest

METRICS = ("foot_skate_mps", "penetration_max_m", "floating_m", "jitter")
BONE_LIMIT_DEG = 5.0


def summarise(manifest: dict, model: str = "humanoid_1seg") -> dict:
    """The report of a library manifest (see the module docstring)."""
    takes = manifest["takes"]
    errors = np.array([t["models"][model]["bone_error_deg_mean"] for t in takes])
    by_content: dict[str, list[dict]] = defaultdict(list)
    for t in takes:
        by_content[t["content"]].append(t)
    contents = {}
    for content, group in sorted(by_content.items()):
        row = {"takes": len(group), "duration_s": round(float(sum(t["duration_s"] for t in group)), 1)}
        for stage in ("quality_before", "quality_after"):
            for metric in METRICS:
                row[f"{metric}_{stage.split('_')[1]}"] = float(np.mean([t["models"][model][stage][metric]
                                                                         for t in group]))
        contents[content] = row
    return {"takes": len(takes), "refused": manifest["refused"],
            "splits": {s: sum(t["split"] == s for t in takes) for s in SPLITS},
            "wall_s": manifest["wall_s"], "model": model,
            "bone_error_deg": {"mean": float(errors.mean()), "max": float(errors.max()),
                               f"share_le_{BONE_LIMIT_DEG:g}": float(np.mean(errors <= BONE_LIMIT_DEG))},
            "contents": contents}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--library", default="data/library", help="library folder (python -m reference_motion import)")
    p.add_argument("--json", nargs="?", const="-", default=None, help="write the report as JSON (to a file or -)")
    args = p.parse_args()
    report = summarise(read_manifest(args.library))
    print(f"{report['takes']} takes imported ({', '.join(f'{n} {s}' for s, n in report['splits'].items())}), "
          f"{len(report['refused'])} refused, import {report['wall_s']:.0f} s")
    for r in report["refused"]:
        print(f"  refused {r['file']}: {r['reason']}")
    b = report["bone_error_deg"]
    print(f"bone-direction error: mean {b['mean']:.2f}°, worst take {b['max']:.2f}°, "
          f"{100 * b[f'share_le_{BONE_LIMIT_DEG:g}']:.0f}% of takes ≤ {BONE_LIMIT_DEG:g}°")
    print(f"{'content':<11} takes  {'skate m/s':>15} {'penetr. m':>15} {'floating m':>15} {'jitter':>17}")
    for content, r in report["contents"].items():
        cells = " ".join(f"{r[f'{m}_before']:7.3f}→{r[f'{m}_after']:<7.3f}" for m in METRICS)
        print(f"{content:<11} {r['takes']:>5}  {cells}")
    emit_json(report, args.json)


if __name__ == "__main__":
    main()
