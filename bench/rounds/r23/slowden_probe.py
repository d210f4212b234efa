"""ELR probe: WLE (mimic_general_legs, --even-legs --part-legs --ground --swing-lift) on validation's raw
IMU takes with the IMU denoiser's correction of the hinges added low-passed (its slow part only)."""
import sys
import numpy as np
from scipy.ndimage import gaussian_filter1d
sys.path.insert(0, ".")
import envs  # noqa
from agents.evaluate import reference_clips, tracked_and_judged
from agents.evaluation import evaluate_tracking
from agents.policy import load_policy
from envs.config import MimicConfig
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.grounding import Grounding
from reference_motion.leg_gap import LegGap
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.swing_lift import SwingLift

sigma_s, first = float(sys.argv[1]), int(sys.argv[2])
net = load_network("models/imu_denoiser_soles_quint_mirror", "denoiser")
pol = load_policy("models/mimic_general_legs")
elr = []
for j in range(40):
    given = reference_clips(["library:data/library/val"], "humanoid_1seg", MimicConfig(), "imu", 1.0, first + 7 * j)
    takes = []
    for m in given:
        q = m.qpos.copy()
        if sigma_s > 0:
            correction = denoise(net, m).qpos[:, 7:] - m.qpos[:, 7:]
            q[:, 7:] += gaussian_filter1d(correction, sigma_s * m.fps, axis=0, mode="nearest")
        elif sigma_s < 0:  # the whole hinge correction, unsmoothed (the height still left to --ground)
            q[:, 7:] = denoise(net, m).qpos[:, 7:]
        takes.append(m.with_qpos(q))
    tracked, _ = tracked_and_judged(takes, None, symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(),
                                    lift=SwingLift())
    elr.append(evaluate_tracking(pol, tracked, given, episodes=2, mirror_average=True)[0]["ELR_mean"])
    print(j, round(elr[-1], 3), flush=True)
np.save(f"runs/r23/slowden_{sigma_s}_{first}.npy", np.array(elr))
print("sigma", sigma_s, "ELR", np.mean(elr))
