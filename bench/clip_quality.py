"""Artefact metrics of all 20 DeepMimic clips retargeted onto both humanoids (kinematic replay).

Each clip is measured as ``load_motion`` returns it (footskate-pinned) and, for the foot-skate
column, also without pinning (``pin_feet=False``), so the effect of pinning is seen side by side.

Usage: ``python bench/clip_quality.py [--json OUT]``; prints the README's Markdown table.
"""

from __future__ import annotations

import argparse
import json
import time

from tqdm import tqdm

from reference_motion.library import load_motion, named_set
from reference_motion.quality import motion_quality


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", help="also write the rows as JSON to this file")
    args = parser.parse_args()
    rows = []
    start = time.perf_counter()
    for source in tqdm(named_set("deepmimic"), desc="clips"):
        for model in ("humanoid_1seg", "humanoid_2seg"):
            q = motion_quality(load_motion(source, model))
            unpinned = motion_quality(load_motion(source, model, pin_feet=False)).foot_skate_mps
            rows.append({"clip": source, "model": model, "foot_skate_unpinned_mps": unpinned, **q.as_dict()})
    print("| clip | model | frames @60 Hz | foot skate unpinned (m/s) | foot skate (m/s) | penetration max (cm) "
          "| floating (cm) | jitter (rad/s³) | self-pen. frac |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['clip']} | {r['model'][-4:]} | {r['frames']} | {r['foot_skate_unpinned_mps']:.3f} "
              f"| {r['foot_skate_mps']:.3f} "
              f"| {100 * r['penetration_max_m']:.2f} | {100 * r['floating_m']:.2f} | {r['jitter']:.0f} "
              f"| {r['self_penetration_frac']:.2f} |")
    print(f"\n{len(rows)} rows in {time.perf_counter() - start:.1f} s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
