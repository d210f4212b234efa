"""Probe: WLE on validation's raw takes with the drift's time-varying part removed (its take mean kept),
against every kind (seeds 670000+, 4 rollouts per take, as the leave-one-out probe)."""
import sys
import numpy as np
sys.path.insert(0, ".")
import envs  # noqa
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import MimicConfig
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.swing_lift import SwingLift

pol = load_policy("models/mimic_general_legs")
cfg = MimicConfig()
clean = reference_clips(["library:data/library/val"], "humanoid_1seg", cfg, None, 1.0, 0)
for seed in (670000, 670100, 670200):
    imu = reference_clips(["library:data/library/val"], "humanoid_1seg", cfg, "imu", 1.0, seed)
    drift = reference_clips(["library:data/library/val"], "humanoid_1seg", cfg, "drift", 1.0, seed)
    out = {}
    for mode in ("every kind", "drift constant", "drift varying only"):
        takes = []
        for m, d, c in zip(imu, drift, clean):
            part = d.qpos[:, 7:] - c.qpos[:, 7:]
            q = m.qpos.copy()
            if mode == "drift constant":
                q[:, 7:] -= part - part.mean(axis=0)
            elif mode == "drift varying only":
                q[:, 7:] -= part.mean(axis=0)
            takes.append(m.with_qpos(q))
        tracked, judged = tracked_and_judged(takes, None, symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(),
                                             lift=SwingLift())
        out[mode] = evaluate_tracking(pol, tracked, judged, episodes=4, mirror_average=True)[0]["ELR_mean"]
    print(seed, {k: round(v, 3) for k, v in out.items()}, flush=True)
