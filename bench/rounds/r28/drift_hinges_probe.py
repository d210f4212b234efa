"""Round 28 probe: where the suit's hinge drift costs WW on raw takes, the hinges the policy drives (hips, knees,
ankles, shoulders: its PD targets are the take's angle plus its action) or the ones that follow the take open-loop
(spine, neck, elbows ...). Each take is corrupted at IMU strength 1, and again without drift; the hybrids keep the
drift on one group of hinges only (the other artefacts' random numbers are the same in both). WW with the raw rows'
preparation (mirror-averaged, legs evened and parted, grounded, swing-lifted), the ten takes of the train split in
bench/rounds/r28/takes.txt, 40 rollouts per take (start frames 0, 3, ..., 117: ten times the kinds probe's
four, so its rows are not the same rollouts as that probe's).

usage: python bench/rounds/r28/drift_hinges_probe.py SEED [SEED ...]   (prints a JSON line per seed)
"""
import json
import sys
from dataclasses import replace

import numpy as np

sys.path.insert(0, ".")
import envs  # noqa: F401
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import MimicConfig
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.swing_lift import SwingLift

TAKES = open("bench/rounds/r28/takes.txt").read().split()
SOURCES = [f"library:data/library#{t}" for t in TAKES]
policy = load_policy("models/mimic_general_wide")
first = reference_clips(SOURCES[:1], "humanoid_1seg", MimicConfig(), None, 1.0, 0)
env = policy.make_env(first, artefacts=None)
hinge = np.arange(first[0].qpos.shape[1]) >= 7  # qpos columns of the hinge angles (after the root's 7)
driven = np.isin(np.arange(len(hinge)), np.asarray(env.unwrapped.actuator_qpos)[env.unwrapped.driven])
DRIFT_KEPT_ON = {"every": np.ones_like(hinge), "no_drift": np.zeros_like(hinge), "drift_driven_only": driven,
                 "drift_open_loop_only": hinge & ~driven}
"""Per condition, the qpos columns that keep the drift (the rest are the take's without it; drift is a hinge kind,
so the root's columns are the same in both)."""
for seed in map(int, sys.argv[1:]):
    every = reference_clips(SOURCES, "humanoid_1seg", MimicConfig(), "imu", 1.0, seed)
    no_drift = reference_clips(SOURCES, "humanoid_1seg", MimicConfig(), "imu", 1.0, seed, without=["drift"])
    rows = {}
    for name, kept in DRIFT_KEPT_ON.items():
        clips = [replace(a, qpos=np.where(kept, a.qpos, b.qpos)) for a, b in zip(every, no_drift)]
        tracked, judged = tracked_and_judged(clips, None, symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(),
                                             lift=SwingLift())
        summary, _ = evaluate_tracking(policy, tracked, judged, episodes=40, mirror_average=True)
        rows[name] = round(summary["ELR_mean"], 4)
    print(json.dumps({"seed": seed, "driven_columns": int(driven.sum()), **rows}), flush=True)
