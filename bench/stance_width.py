"""Could a take's hip adduction error be calibrated away against the library's usual stance?

Usage: ``python bench/stance_width.py [--library data/library] [--json [OUT]]``

The IMU synthesizer's costliest artefact for the shipped generalist is the hip adduction offset
(8° per leg at strength 1, :class:`reference_motion.artefacts.ArtefactScales`): it narrows a take's
stance by 16°. A calibration step could subtract, per take, the difference between its mean stance
and the library's, if takes' mean stances were much closer to each other than 16°. Reported per
split of the motion library: the stance width of each take, the mean over its frames of left
minus right hip x angle (``l_thigh_x − r_thigh_x``, degrees; positive = legs apart), and its mean,
standard deviation and range over the split's takes.
"""

from __future__ import annotations

import argparse

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.artefacts import ArtefactScales
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion

MODEL = "humanoid_1seg"


def stance_width_deg(qpos: np.ndarray, left: int, right: int) -> float:
    """Mean over frames of ``qpos[:, left] − qpos[:, right]`` (rad), in degrees."""
    return float(np.degrees(np.mean(qpos[:, left] - qpos[:, right])))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--library", default="data/library", help="the imported motion library")
    p.add_argument("--json", nargs="?", const="-", default=None, help="write JSON to OUT (or print it)")
    args = p.parse_args()
    model = load_model(MODEL)
    left, right = model.qpos_index("l_thigh_x"), model.qpos_index("r_thigh_x")
    result = {}
    for split in ("train", "val", "test"):
        takes = {c.split("#", 1)[-1]: stance_width_deg(load_motion(c, MODEL).qpos, left, right)
                 for c in expand_clips([f"library:{args.library}/{split}"])}
        widths = np.array(list(takes.values()))
        result[split] = {"takes": takes, "mean_deg": float(widths.mean()), "std_deg": float(widths.std()),
                         "min_deg": float(widths.min()), "max_deg": float(widths.max())}
        print(f"{split:5s} {len(widths):3d} takes: stance width {widths.mean():5.1f} ± {widths.std():4.1f}° "
              f"(range {widths.min():.1f} to {widths.max():.1f}°)")
    result["adduction_narrowing_deg_at_strength_1"] = float(np.degrees(2 * ArtefactScales().adduction_rad))
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
