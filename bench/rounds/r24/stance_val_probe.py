"""Kinematic check of IMU denoisers on validation's takes (never trained on) walked wider: each take
widened by 0 / 0.2 / 0.35 m (wider_stance), IMU-corrupted at strength 1 (seeds 1030000 + 10·take +
draw, two draws), denoised by each folder given; the feet's median gap against the widened take's,
and the leg hinges' RMS error (deg). usage: stance_val_probe.py DIR [DIR ...]"""
import sys
import numpy as np
sys.path.insert(0, ".")
from agents.evaluate import reference_clips
from envs.config import MimicConfig
from perception.weights import load_network
from perception.imu_denoiser import denoise
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.leg_gap import lateral_foot_gap
from reference_motion.leg_symmetry import LEG_HINGES
from reference_motion.stance import wider_stance
from reference_motion.humanoid.model import load_model
nets = {d: load_network(d, "denoiser") for d in sys.argv[1:]}
hm = load_model("humanoid_1seg")
cols = [hm.qpos_index(h) for h in LEG_HINGES] + [hm.qpos_index("r" + h[1:]) for h in LEG_HINGES]
all_hinges = slice(7, None)
clean = reference_clips(["library:data/library/val"], "humanoid_1seg", MimicConfig(), None, 1.0, 0)
gap = lambda m: np.median(lateral_foot_gap("humanoid_1seg", m.qpos))
for extra in (0.0, 0.2, 0.35):
    res = {d: [] for d in nets}
    raw = []
    for i, c in enumerate(clean):
        w = wider_stance(c, extra) if extra else c
        for draw in range(2):
            r = corrupt(w, ArtefactRecipe.imu(1.0), 1030000 + 10 * i + draw)
            raw.append(gap(r) - gap(w))
            for d, net in nets.items():
                o = denoise(net, r)
                res[d].append((gap(o) - gap(w), np.degrees(np.sqrt(np.mean((o.qpos[:, cols] - w.qpos[:, cols]) ** 2))),
                               np.degrees(np.sqrt(np.mean((o.qpos[:, all_hinges] - w.qpos[:, all_hinges]) ** 2)))))
    print(f"extra {extra:.2f}: raw gap error {np.mean(raw):+.3f} m", flush=True)
    for d, v in res.items():
        a = np.array(v)
        print(f"   {d}: gap error {a[:,0].mean():+.3f} ± {a[:,0].std(ddof=1)/np.sqrt(len(a)):.3f} m, leg rms {a[:,1].mean():.2f}, all hinges {a[:,2].mean():.2f} deg", flush=True)
