"""Which library takes never put their heels down: the lowest heel and toe of every take, kinematically.

Usage: ``python bench/heel_clearance.py [--library data/library] [--model humanoid_2seg]
[--threshold-m 0.02] [--json [OUT]]``

For every take of the library (all splits), the clip is posed frame by frame on ``--model`` and the
height above the floor (z = 0) of the lowest sole sphere of each contact region (left/right toe,
left/right heel; the spheres' radius taken off) is tracked; printed are the takes whose heel on
either side never comes within ``--threshold-m`` of the floor, with their split. A take walked on
the forefoot keeps its heels up throughout, while ĉ (VGRFNet) may still mark heel contacts on it.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import mujoco
import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.humanoid.model import CONTACT_CHANNELS, load_model
from reference_motion.library import expand_clips, load_motion


def lowest_regions(qpos: np.ndarray, model_name: str) -> np.ndarray:
    """``(4,)`` m: over the frames of ``qpos (T, nq)``, the lowest height above z = 0 of each
    contact region's sole spheres (CONTACT_CHANNELS order: LT, RT, LH, RH)."""
    humanoid = load_model(model_name)
    model, data = humanoid.model, mujoco.MjData(humanoid.model)
    spheres = [np.flatnonzero(humanoid.geom_contact_channel == c) for c in range(len(CONTACT_CHANNELS))]
    lowest = np.full(len(CONTACT_CHANNELS), np.inf)
    for pose in qpos:
        data.qpos[:] = pose
        mujoco.mj_kinematics(model, data)
        for c, geoms in enumerate(spheres):
            lowest[c] = min(lowest[c], float((data.geom_xpos[geoms, 2] - model.geom_size[geoms, 0]).min()))
    return lowest


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--library", type=Path, default=Path("data/library"))
    p.add_argument("--model", default="humanoid_2seg", choices=["humanoid_1seg", "humanoid_2seg"])
    p.add_argument("--threshold-m", type=float, default=0.02)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    manifest = args.library / "manifest.json"
    if not manifest.is_file():
        raise SystemExit(f"{manifest}: not found (import the library first: python -m reference_motion import "
                         f"../shared/mocap --out {args.library})")
    split = {t["name"]: t["split"] for t in json.loads(manifest.read_text())["takes"]}
    rows = []
    for clip in expand_clips([f"library:{args.library}"]):
        name = clip.split("#")[-1]
        lowest = lowest_regions(load_motion(clip, args.model).qpos, args.model)
        rows.append({"take": name, "split": split.get(name), **{f"lowest_{c}_m": float(v)
                                                                 for c, v in zip(CONTACT_CHANNELS, lowest)}})
    raised = [r for r in rows if max(r["lowest_left_heel_m"], r["lowest_right_heel_m"]) > args.threshold_m]
    print(f"{len(raised)} of {len(rows)} takes keep a heel more than {args.threshold_m * 100:g} cm up throughout "
          f"({args.model}):")
    for r in raised:
        print(f"  {r['take']:<34} {r['split']:<5} lowest heel L/R {1000 * r['lowest_left_heel_m']:5.1f} / "
              f"{1000 * r['lowest_right_heel_m']:5.1f} mm, toe L/R {1000 * r['lowest_left_toe_m']:5.1f} / "
              f"{1000 * r['lowest_right_toe_m']:5.1f} mm")
    emit_json({"library": str(args.library), "model": args.model, "threshold_m": args.threshold_m,
               "raised": [r["take"] for r in raised], "takes": rows}, args.json)


if __name__ == "__main__":
    main()
