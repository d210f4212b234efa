import sys
import numpy as np
sys.path.insert(0, ".")
from agents.evaluate import reference_clips
from envs.config import MimicConfig
from perception.weights import load_network
from perception.imu_denoiser import denoise
from reference_motion.leg_gap import part_legs
from reference_motion.leg_symmetry import LEG_HINGES, even_legs, leg_asymmetry
from reference_motion.humanoid.model import load_model
net = load_network("models/imu_denoiser_soles_quint_mirror", "denoiser")
hm = load_model("humanoid_1seg")
cols = [hm.qpos_index(h) for h in LEG_HINGES] + [hm.qpos_index("r" + h[1:]) for h in LEG_HINGES]
cfg = MimicConfig()
clean = reference_clips(["library:data/library/val"], "humanoid_1seg", cfg, None, 1.0, 0)
g, e, ad = [], [], []
for seed in (690001, 690101, 690201):
    for m, c in zip(reference_clips(["library:data/library/val"], "humanoid_1seg", cfg, "imu", 1.0, seed), clean):
        d = part_legs(denoise(net, m))
        for out, mo in ((g, d), (e, even_legs(d))):
            out.append(np.sqrt(np.mean((mo.qpos[:, cols] - c.qpos[:, cols]) ** 2)))
        ad.append(leg_asymmetry(d) - leg_asymmetry(c))
print("denoised leg rms", np.degrees(np.mean(g)), "evened", np.degrees(np.mean(e)), "asym err std deg", np.degrees(np.std(ad, 0)).round(2))
