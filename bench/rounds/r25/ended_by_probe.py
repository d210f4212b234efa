"""Probe: how WLST's clean rollouts on its hardest training takes end (fallen / lagging), and the
body's progress along the path at the end (covered / reference distance from the start)."""
import json, sys, collections
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
policy = load_policy(sys.argv[1])
takes = sys.argv[3:]
clips = reference_clips([f"library:data/library#{t}" for t in takes], "humanoid_1seg", MimicConfig(), None, 1.0, 0)
tracked, judged = tracked_and_judged(clips, None, symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(), lift=SwingLift())
mirror = not sys.argv[2].endswith("p")
summary, runs = evaluate_tracking(policy, tracked, judged, episodes=int(sys.argv[2].rstrip("p")) * len(takes), mirror_average=mirror)
out = collections.defaultdict(list)
for r in runs:
    sim, ref = r.simulated.qpos[:, :3], r.reference.qpos[:, :3]
    gone = np.linalg.norm(sim[-1, :2] - sim[0, :2]); want = np.linalg.norm(ref[-1, :2] - ref[0, :2])
    out[r.clip].append((round(r.elr, 2), r.ended_by, round(float(sim[-1, 2]), 2), round(float(gone / max(want, 1e-6)), 2)))
for k, v in out.items():
    print(k, v)
print(summary)
