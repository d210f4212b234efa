"""How ``clean.py`` recovers from a fall: its rewind-and-retry settings, side by side, on validation takes.

Usage: ``python bench/retry_strategies.py [--policy models/mimic_general]
[--settings 0.5x4 1:search:16x64 1:searchall:16x64,value=1] [--seconds 10] [--strength 1] [--seed 7000]
[--json [OUT]]``

Each setting is a :class:`agents.clean.CleanConfig` as ``bench/clean_settings.py`` names it:
``REWINDxRETRIES`` (the policy alone, stochastic retries after a fall),
``REWIND:search:BEAMxSAMPLES[,KEY=VALUE...]`` (the policy alone, the policy-guided
search of :mod:`agents.search` after a fall) or ``REWIND:searchall:...`` (every stretch searched).
Every take of the library's validation split (never the test split: this is for choosing the
settings) is cut to ``--seconds``, IMU-corrupted at ``--strength`` with seed
``--seed + i`` and re-performed zero-shot by the policy with each setting. Reported per setting:
re-anchors (teleports back to the reference) and recoveries (failures a second try got
past) in all, the takes simulated whole, the cleaning wall time, and what the output's frames
look like against the input: the share of frames whose root is more than 0.2 m below the input's
(``sunk``: the character down or going down) and more than 0.5 m from it horizontally
(``astray``; ``from clean``: from the take's root before the corruption, whose IMU drift moves the
input's root off the path the body took), and the output's jitter (median over the takes,
rad/s³; the action noise of the search adds some). Fewer re-anchors are worth having only if they do not come from keeping more of
the frames where the character is falling.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import asdict

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.clean import clean_motion
from agents.policy import load_policy
from adapted_cleaning import corrupted_take, cut_take  # bench/adapted_cleaning.py: the protocol's takes
from clean_settings import label, setting  # bench/clean_settings.py
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.library import expand_clips
from reference_motion.quality import motion_quality

SUNK_M = 0.2
"""Root this far (m) below the input's root: the character is down or going down."""
ASTRAY_M = 0.5
"""Root this far (m) from the input's root, horizontally."""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"], help="takes (validation only)")
    p.add_argument("--settings", nargs="+", type=setting, default=[setting(s) for s in ("0.5x4", "1:search:16x64", "1:searchall:16x64")])
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=7000, help="artefact seed of the first take (take i: seed + i)")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    policy = load_policy(args.policy)
    clips = expand_clips(args.clips)
    takes = [corrupted_take(clip, policy.foot, args.seconds, args.strength, args.seed + i) for i, clip in enumerate(clips)]
    truths = [cut_take(clip, policy.foot, args.seconds) for clip in clips]  # the takes before the corruption
    input_jitter = [motion_quality(take).jitter for take in takes]
    rows = []
    print(f"{'setting':<30} {'re-anchors':>10} {'recoveries':>10} {'whole':>6} {'sunk':>6} {'astray':>7} "
          f"{'from clean':>10} {'jitter':>7} {'clean s':>8}")
    for config in args.settings:
        start = time.perf_counter()
        per_take = []
        for reference, truth, jitter_input in zip(takes, truths, input_jitter):
            out = clean_motion(policy, reference, config, progress=False)
            below = out.qpos[:, 2] < reference.qpos[:, 2] - SUNK_M
            away = np.linalg.norm(out.qpos[:, :2] - reference.qpos[:, :2], axis=1) > ASTRAY_M
            away_truth = np.linalg.norm(out.qpos[:, :2] - truth.qpos[:, :2], axis=1) > ASTRAY_M
            per_take.append({"take": reference.name, "frames": reference.n_frames,
                             "reanchors": len(out.source["reanchors"]), "recoveries": len(out.source["recoveries"]),
                             "sunk_frac": float(below.mean()), "astray_frac": float(away.mean()),
                             "astray_from_clean_frac": float(away_truth.mean()),
                             "jitter": motion_quality(out).jitter, "jitter_input": jitter_input})
        row = {"setting": label(config), "rewind_s": config.rewind_s, "retries": config.retries,
               "search": None if config.search is None else asdict(config.search),
               "reanchors": sum(t["reanchors"] for t in per_take), "recoveries": sum(t["recoveries"] for t in per_take),
               "takes_whole": sum(t["reanchors"] == 0 for t in per_take), "takes": len(per_take),
               "sunk_frac": float(np.mean([t["sunk_frac"] for t in per_take])),
               "astray_frac": float(np.mean([t["astray_frac"] for t in per_take])),
               "astray_from_clean_frac": float(np.mean([t["astray_from_clean_frac"] for t in per_take])),
               "jitter_median": float(np.median([t["jitter"] for t in per_take])),
               "jitter_input_median": float(np.median([t["jitter_input"] for t in per_take])),
               "clean_s": time.perf_counter() - start, "per_take": per_take}
        rows.append(row)
        print(f"{label(config):<30} {row['reanchors']:>10} {row['recoveries']:>10} "
              f"{row['takes_whole']:>3}/{row['takes']:<2} {row['sunk_frac']:>6.1%} {row['astray_frac']:>7.1%} "
              f"{row['astray_from_clean_frac']:>10.1%} {row['jitter_median']:>7.0f} {row['clean_s']:>8.1f}", flush=True)
    emit_json({"policy": args.policy, "clips": args.clips, "seconds": args.seconds, "strength": args.strength,
               "seed": args.seed, "settings": rows}, args.json)


if __name__ == "__main__":
    main()
