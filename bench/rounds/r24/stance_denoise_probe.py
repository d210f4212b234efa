"""Does the IMU denoiser keep a wide stance? Training walks widened (wider_stance), IMU-corrupted,
denoised: median lateral foot gap of each, and the leg hinges' RMS error against the widened take."""
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
net = load_network("models/imu_denoiser_soles_quint_mirror", "denoiser")
hm = load_model("humanoid_1seg")
cols = [hm.qpos_index(h) for h in LEG_HINGES] + [hm.qpos_index("r" + h[1:]) for h in LEG_HINGES]
cfg = MimicConfig()
specs = [f"library:data/library#dataset-1_walk_{s}_001" for s in ("active", "angry", "childish", "feminine", "proud", "sad", "not-confident", "musical")]
clean = reference_clips(specs, "humanoid_1seg", cfg, None, 1.0, 0)
recipe = ArtefactRecipe.imu(1.0)
for extra in (0.0, 0.2, 0.35):
    rows = []
    for i, c in enumerate(clean):
        w = wider_stance(c, extra) if extra else c
        for seed in (0, 1):
            r = corrupt(w, recipe, 5000 + 10 * i + seed)
            d = denoise(net, r)
            gaps = [np.median(lateral_foot_gap("humanoid_1seg", m.qpos)) for m in (w, r, d)]
            errs = [np.degrees(np.sqrt(np.mean((m.qpos[:, cols] - w.qpos[:, cols]) ** 2))) for m in (r, d)]
            rows.append(gaps + errs)
    a = np.array(rows)
    print(f"extra {extra:.2f}: gap clean {a[:,0].mean():.3f} raw {a[:,1].mean():.3f} denoised {a[:,2].mean():.3f} m "
          f"(denoised-clean {np.mean(a[:,2]-a[:,0]):+.3f} ± {np.std(a[:,2]-a[:,0])/np.sqrt(len(a)):.3f}); leg rms raw {a[:,3].mean():.2f} den {a[:,4].mean():.2f} deg", flush=True)
