"""Can the pelvis' sway tell a take's stance width? LIPM: the centre of pressure p = x - (h/g) x''
(lateral, heading frame, path trend removed) sits under the stance foot; its left-stance minus
right-stance medians against the median lateral foot gap. Clean training walks, widened copies,
and the same IMU-corrupted (the estimate reads the corrupted take; truth from the clean one)."""
import sys
import numpy as np
from scipy.ndimage import uniform_filter1d, gaussian_filter1d
sys.path.insert(0, ".")
from agents.evaluate import reference_clips
from envs.config import MimicConfig
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.leg_gap import lateral_foot_gap
from reference_motion.stance import wider_stance
from reference_motion.footskate import planted_points, foot_channels
from reference_motion.humanoid.model import load_model
from reference_motion import rotations as rot
hm = load_model("humanoid_1seg")

def lipm_gap(m, sigma_s=0.05):
    kin = hm.forward_kinematics(m.qpos)
    fps = m.fps
    xy = gaussian_filter1d(kin.com[:, :2], sigma_s * fps, axis=0)
    yaw = np.unwrap(rot.yaw(m.qpos[:, 3:7]))
    yaw = uniform_filter1d(yaw, int(fps), mode="nearest")
    left = np.stack([-np.sin(yaw), np.cos(yaw)], 1)
    acc = np.gradient(np.gradient(xy, axis=0), axis=0) * fps**2
    h = kin.com[:, 2].mean()
    p = xy - h / 9.81 * acc
    rel = p - uniform_filter1d(xy, int(fps), axis=0, mode="nearest")
    lat = np.sum(rel * left, 1)
    pl = planted_points(kin, fps)
    L = pl[:, foot_channels("left")].any(1); R = pl[:, foot_channels("right")].any(1)
    lo, ro = L & ~R, R & ~L
    if lo.sum() < 5 or ro.sum() < 5:
        return np.nan, np.nan
    return np.median(lat[lo]) - np.median(lat[ro]), 2 * np.std(lat)

cfg = MimicConfig()
styles = ("active", "angry", "childish", "feminine", "proud", "sad", "not-confident", "musical", "chimpira", "masculinity")
specs = [f"library:data/library#dataset-1_{k}_{s}_001" for k in ("walk", "walk-left", "walk-back") for s in styles]
clean = reference_clips(specs, "humanoid_1seg", cfg, None, 1.0, 0)
rows = []
for i, c in enumerate(clean):
    for extra in (0.0, 0.2, 0.35):
        w = wider_stance(c, extra) if extra else c
        true = np.median(lateral_foot_gap("humanoid_1seg", w.qpos))
        r = corrupt(w, ArtefactRecipe.imu(1.0), 7000 + 10 * i)
        rows.append((i % 10, i // 10, extra, true, *lipm_gap(w), *lipm_gap(r), np.median(lateral_foot_gap("humanoid_1seg", r.qpos))))
a = np.array(rows)
names = ["clean contact", "clean 2std", "imu contact", "imu 2std", "imu raw gap"]
for kind in range(3):
    k = a[a[:, 1] == kind]
    print(("walk", "walk-left", "walk-back")[kind])
    for e in (0.0, 0.2, 0.35):
        s = k[k[:, 2] == e]
        print(f"  extra {e}: true {np.nanmean(s[:,3]):.3f}  " + "  ".join(f"{n} {np.nanmean(s[:,4+j]):.3f}" for j, n in enumerate(names)))
for j, n in enumerate(names):
    ok = np.isfinite(a[:, 4 + j])
    print(n, "corr with true", np.corrcoef(a[ok, 3], a[ok, 4 + j])[0, 1].round(3))
# within extra == 0: does the estimate rank takes' natural widths?
s = a[a[:, 2] == 0]
for j, n in enumerate(names):
    ok = np.isfinite(s[:, 4 + j])
    print("extra0", n, "corr", np.corrcoef(s[ok, 3], s[ok, 4 + j])[0, 1].round(3))
