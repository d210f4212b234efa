"""How far the footskate pinning moves each foot: the largest correction a clip's contact windows ask for.

Usage: ``python bench/pinning_corrections.py [--manifest data/library/manifest.json | --clips SOURCE ...]
[--model humanoid_1seg] [--json [OUT]]``

Each clip is retargeted and resampled to 60 Hz as the library import does, before any pinning;
then, per foot, :func:`reference_motion.footskate.pin_corrections` gives the horizontal correction
(m) that would keep its planted points still, with no limit. A planted stance needs a few
centimetres up to about a quarter of a metre (DeepMimic's walk 0.23 m: the heel-strike approach
and the toe-off are held too); a window that asks for more holds a foot still while the body walks
on: several steps of a shuffling foot that never rises ``contact_height`` off the floor. Printed
per clip, worst first: that largest correction, and whether the default
``PinningConfig.max_correction_m`` leaves the window alone. With ``--manifest`` the clips are the
library's takes (their mocap files, as imported), each labelled with its split.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.footskate import FOOT_SIDES, PinningConfig, foot_channels, pin_corrections, planted_points
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion


def largest_correction(source: str, model_name: str, config: PinningConfig = PinningConfig()) -> float:
    """The largest horizontal correction (m) the pinning of ``source`` (retargeted to ``model_name``
    and resampled, unpinned) asks of either foot, with no limit on it."""
    motion = load_motion(source, model_name, pin_feet=False)
    kin = load_model(model_name).forward_kinematics(motion.qpos)
    planted = planted_points(kin, motion.fps, config)
    return max(float(np.linalg.norm(pin_corrections(kin.foot_points[:, ch, :2], planted[:, ch], None), axis=-1).max())
               for ch in map(foot_channels, FOOT_SIDES))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--manifest", default="data/library/manifest.json",
                       help="a motion library's manifest: its takes' mocap files (default)")
    which.add_argument("--clips", nargs="+", help="SOURCE strings or clip sets instead")
    parser.add_argument("--model", default="humanoid_1seg")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    if args.clips:
        clips = [(clip, "") for clip in expand_clips(args.clips)]
    else:
        takes = json.loads(open(args.manifest).read())["takes"]
        clips = [(take["file"], take["split"]) for take in takes]
    limit = PinningConfig().max_correction_m
    rows = sorted(({"clip": clip, "split": split, "largest_correction_m": largest_correction(clip, args.model)}
                   for clip, split in clips), key=lambda r: -r["largest_correction_m"])
    for r in rows:
        r["left_alone"] = limit is not None and r["largest_correction_m"] > limit
    result = {"model": args.model, "max_correction_m": limit, "rows": rows,
              "over_0.2_m": sum(r["largest_correction_m"] > 0.2 for r in rows), "clips": len(rows)}
    if emit_json(result, args.json):
        return
    print(f"{'clip':<72}{'split':>6}{'largest correction (m)':>25}  left alone")
    for r in rows:
        print(f"{r['clip']:<72}{r['split']:>6}{r['largest_correction_m']:>25.3f}  {'yes' if r['left_alone'] else ''}")
    print(f"{result['over_0.2_m']} of {len(rows)} clips ask for more than 0.2 m; the default limit is {limit} m")


if __name__ == "__main__":
    main()
