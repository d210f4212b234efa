"""Does the IMU denoiser keep a take's carriage? Validation's takes carried with random postures
(posture_copies: stoop, crouch, stance, neck and elbow bends), IMU-corrupted, denoised: hinge RMS
against the postured clean take, beside the takes as carried. usage: posture_probe.py DIR [DIR ...]"""
import sys
import numpy as np
sys.path.insert(0, ".")
from agents.evaluate import reference_clips
from envs.config import MimicConfig
from perception.weights import load_network
from perception.imu_denoiser import denoise
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.library import posture_copies
nets = {d: load_network(d, "denoiser") for d in sys.argv[1:]}
clean = reference_clips(["library:data/library/val"], "humanoid_1seg", MimicConfig(), None, 1.0, 0)
postured = posture_copies(clean, 2, 1090000)
for name, takes in (("as carried", clean), ("postured", postured)):
    res = {d: [] for d in nets}; raw = []
    for i, w in enumerate(takes):
        r = corrupt(w, ArtefactRecipe.imu(1.0), 1090000 + 10 * i)
        raw.append(np.degrees(np.sqrt(np.mean((r.qpos[:, 7:] - w.qpos[:, 7:]) ** 2))))
        for d, net in nets.items():
            o = denoise(net, r)
            res[d].append(np.degrees(np.sqrt(np.mean((o.qpos[:, 7:] - w.qpos[:, 7:]) ** 2))))
    print(f"{name}: raw {np.mean(raw):.2f} deg; " + "; ".join(f"{d} {np.mean(v):.2f}" for d, v in res.items()), flush=True)
