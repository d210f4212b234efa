"""Policy probe on validation's takes walked wider: each take widened by EXTRA m (wider_stance),
IMU-corrupted at strength 1 (seed FIRST + 7·draw + take), prepared as WLS prepares takes behind each
denoiser given (slowed 0.5 s, legs evened and parted, grounded, swing-lifted) and tracked by
mimic_general_legs's symmetric actor, judged against the widened IMU take as given.
usage: wide_policy_probe.py EXTRA FIRST DRAWS OUT.json DENOISER [DENOISER ...]"""
import json
import sys
import numpy as np
sys.path.insert(0, ".")
import envs  # noqa: F401
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import MimicConfig
from perception.imu_denoiser import slowed
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.stance import wider_stance
from reference_motion.swing_lift import SwingLift
extra, first, n_draws, out = float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
policy = load_policy("models/mimic_general_legs")
clean = reference_clips(["library:data/library/val"], "humanoid_1seg", MimicConfig(), None, 1.0, 0)
wide = [wider_stance(c, extra) if extra else c for c in clean]
result = {"extra_m": extra, "first_seed": first, "draws": n_draws, "rows": {}}
for d in sys.argv[5:]:
    net = slowed(load_network(d, "denoiser"), 0.5)
    elr = []
    for j in range(n_draws):
        takes = [corrupt(w, ArtefactRecipe.imu(1.0), first + 7 * j + i) for i, w in enumerate(wide)]
        tracked, judged = tracked_and_judged(takes, net, symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(),
                                             lift=SwingLift())
        elr.append(evaluate_tracking(policy, tracked, judged, episodes=2, mirror_average=True)[0]["ELR_mean"])
        print(d, j, round(elr[-1], 3), flush=True)
    result["rows"][d] = elr
    print(f"{d}: ELR {np.mean(elr):.3f}", flush=True)
names = list(result["rows"])
for other in names[1:]:
    diff = np.array(result["rows"][other]) - np.array(result["rows"][names[0]])
    print(f"{other} against {names[0]}: {diff.mean():+.3f} ± {diff.std(ddof=1) / np.sqrt(len(diff)):.3f}")
json.dump(result, open(out, "w"), indent=1)
