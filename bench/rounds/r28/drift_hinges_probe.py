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
env = policy.make_env(reference_clips(SOURCES[:1], "humanoid_1seg", MimicConfig(), None, 1.0, 0), artefacts=None)
driven = np.asarray(env.unwrapped.actuator_qpos)[env.unwrapped.driven]  # qpos columns of the driven hinges
for seed in map(int, sys.argv[1:]):
    every = reference_clips(SOURCES, "humanoid_1seg", MimicConfig(), "imu", 1.0, seed)
    no_drift = reference_clips(SOURCES, "humanoid_1seg", MimicConfig(), "imu", 1.0, seed, without=["drift"])
    rows = {}
    for name in ("every", "no_drift", "drift_driven_only", "drift_open_loop_only"):
        clips = []
        for a, b in zip(every, no_drift):
            q = {"every": a, "no_drift": b}.get(name)
            if q is None:
                keep_drift = np.zeros(a.qpos.shape[1], bool)
                keep_drift[driven] = True
                if name == "drift_open_loop_only":
                    keep_drift[7:] = ~keep_drift[7:]
                qpos = np.where(keep_drift, a.qpos, b.qpos)
                q = replace(a, qpos=qpos)
            clips.append(q)
        tracked, judged = tracked_and_judged(clips, None, symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(),
                                             lift=SwingLift())
        summary, _ = evaluate_tracking(policy, tracked, judged, episodes=40, mirror_average=True)
        rows[name] = round(summary["ELR_mean"], 4)
    print(json.dumps({"seed": seed, "driven_columns": len(driven), **rows}), flush=True)
