"""Are the performance's failures falls, or a reference path the body cannot follow?

Usage: ``python bench/failure_heights.py [--policy models/mimic_general] [--json [OUT]]``

Performs, zero-shot as :mod:`agents.clean` does (no adaptation), the seven validation takes cut to
10 s and IMU-corrupted at strength 1 (seeds 6000–6006) and the demo's clip (``walker/turn_left1``,
10 s, IMU strength 1, seed 1000), and for every failure of the deterministic policy (before any
retry) records how it ended (``lagging``: the head more than 0.91 m from the reference's;
``fallen``), the simulated pelvis height against the reference's at that frame, and the root's
horizontal distance from the reference's root at that frame. A failure with the pelvis more than 15 cm below
the reference's counts as a fall in progress.
"""

from __future__ import annotations

import argparse

import numpy as np

import envs  # noqa: F401  (registers the ids)
from adapted_cleaning import corrupted_take  # bench/adapted_cleaning.py: the scripts run from bench/
from agents import clean
from agents.policy import load_policy
from json_report import emit_json
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.library import expand_clips, load_motion

FALL_DROP_M = 0.15
"""A failure with the pelvis this much (m) below the reference's is a fall in progress."""


def failures_of(policy, reference) -> list[dict]:
    """Each failure of ``policy``'s deterministic rollouts while it performs ``reference``."""
    found = []
    retry = clean._Performance._retry

    def recording(performance, failed):
        track = performance.env.unwrapped.current_track.motion.qpos
        sim, ref = failed.qpos[-1], track[min(failed.end_frame, len(track) - 1)]
        found.append({"frame": failed.end_frame, "reason": failed.ended_by, "pelvis_m": float(sim[2]),
                      "reference_pelvis_m": float(ref[2]), "off_path_m": float(np.linalg.norm(sim[:2] - ref[:2]))})
        return retry(performance, failed)

    clean._Performance._retry = recording
    try:
        clean.clean_motion(policy, reference, clean.POLICY_ALONE, progress=False)  # where the policy alone fails
    finally:
        clean._Performance._retry = retry
    return found


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    policy = load_policy(args.policy)
    takes = [(c.split("#")[-1], corrupted_take(c, policy.foot, 10.0, 1.0, 6000 + i))
             for i, c in enumerate(expand_clips(["library:data/library/val"]))]
    demo = load_motion("deepmimic:walker/turn_left1", "humanoid_1seg", min_frames=600)
    takes.append(("demo walker/turn_left1", corrupt(demo, ArtefactRecipe.named("imu", 1.0), 1000)))
    rows = []
    for name, reference in takes:
        found = failures_of(policy, reference)
        falls = sum(f["reference_pelvis_m"] - f["pelvis_m"] > FALL_DROP_M for f in found)
        print(f"{name:<30} {len(found):2d} failures, {falls} falls in progress; reasons "
              f"{sorted({f['reason'] for f in found})}")
        rows.append({"take": name, "failures": found, "falls": falls})
    emit_json({"policy": args.policy, "fall_drop_m": FALL_DROP_M, "takes": rows}, args.json)


if __name__ == "__main__":
    main()
