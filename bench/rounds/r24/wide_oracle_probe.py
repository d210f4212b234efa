"""As wide_policy_probe.py, but each take's legs parted to the widened clean take's own median foot gap
(an oracle of the stance width): how much of the width's cost is the denoiser's narrowing.
usage: wide_oracle_probe.py EXTRA FIRST DRAWS DENOISER"""
import sys
import numpy as np
sys.path.insert(0, ".")
import envs  # noqa: F401
from agents.evaluate import reference_clips
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import MimicConfig
from envs.preparation import prepared
from perception.imu_denoiser import slowed
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap, lateral_foot_gap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.stance import wider_stance
from reference_motion.swing_lift import SwingLift
extra, first, n_draws, d = float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
policy = load_policy("models/mimic_general_legs")
clean = reference_clips(["library:data/library/val"], "humanoid_1seg", MimicConfig(), None, 1.0, 0)
wide = [wider_stance(c, extra) if extra else c for c in clean]
gaps = [float(np.median(lateral_foot_gap("humanoid_1seg", w.qpos))) for w in wide]
net = slowed(load_network(d, "denoiser"), 0.5)
elr = []
for j in range(n_draws):
    takes = [corrupt(w, ArtefactRecipe.imu(1.0), first + 7 * j + i) for i, w in enumerate(wide)]
    tracked = [prepared(t, net, symmetry=LegSymmetry(), legs=LegGap(min_gap_m=g), grounding=Grounding(), lift=SwingLift())
               for t, g in zip(takes, gaps)]
    elr.append(evaluate_tracking(policy, tracked, takes, episodes=2, mirror_average=True)[0]["ELR_mean"])
print(f"oracle gap, {d}, extra {extra}: ELR {np.mean(elr):.3f}  per draw {' '.join(f'{e:.2f}' for e in elr)}")
