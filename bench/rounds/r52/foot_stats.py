"""Round 52 probe: a planted sole's mean tilt per stance on the clean takes of a library split, and the tilt the IMU suit
adds at the same stances (stances found on the corrupted take, after --even-legs --part-legs), before and after
foot_level.level_feet: with bias and drift only, and with every kind.

usage: python bench/rounds/r52/foot_stats.py SPLIT SEED   (prints JSON; degrees)"""
import sys, json
import numpy as np
sys.path.insert(0, "."); sys.path.insert(0, "bench/rounds/r52")
from agents.evaluate import reference_clips
from envs.config import MimicConfig
from envs.preparation import prepared
from reference_motion.motion_library import library_set
from reference_motion.humanoid.model import load_model
from foot_level import FootLevel, sole_tilt, stance_windows, level_feet
from reference_motion.leg_symmetry import LegSymmetry
from reference_motion.leg_gap import LegGap
split, seed = sys.argv[1], int(sys.argv[2])
srcs = library_set(f"library:data/library/{split}")
clean = reference_clips(srcs, "humanoid_1seg", MimicConfig(), None, 1.0, 0)
hm = load_model("humanoid_1seg")
lv = FootLevel()
def per_stance(m, windows_from=None):
    kin = hm.forward_kinematics(m.qpos)
    wins = stance_windows(kin, m.fps, lv) if windows_from is None else windows_from
    return wins, [[np.degrees(sole_tilt(kin, m.model, s)[a:b].mean(0)) for a, b in wins[s]] for s in range(2)]
cl = [[], []]
for m in clean:
    _, t = per_stance(m)
    for s in range(2): cl[s] += t[s]
res = {"clean": {f"side{s}": dict(n=len(cl[s]), mean=np.mean(cl[s], 0).round(2).tolist(), sd=np.std(cl[s], 0).round(2).tolist()) for s in range(2)}}
for kind, wo in (("driftbias", ["noise", "jitter", "adduction", "heading", "root_drift", "skate", "height"]), ("imu", [])):
    cor = reference_clips(srcs, "humanoid_1seg", MimicConfig(), "imu", 1.0, seed, without=wo)
    cor = [prepared(c, None, symmetry=LegSymmetry(), legs=LegGap()) for c in cor]
    err, after, found = [[], []], [[], []], 0
    for m0, m1 in zip(clean, cor):
        wins, t1 = per_stance(m1)
        _, t0 = per_stance(m0, wins)
        _, t2 = per_stance(level_feet(m1, lv), wins)
        for s in range(2):
            found += len(wins[s])
            err[s] += [a - b for a, b in zip(t1[s], t0[s])]; after[s] += [a - b for a, b in zip(t2[s], t0[s])]
    e = np.concatenate([np.array(err[0]).reshape(-1, 2), np.array(err[1]).reshape(-1, 2)])
    f = np.concatenate([np.array(after[0]).reshape(-1, 2), np.array(after[1]).reshape(-1, 2)])
    res[kind] = dict(stances=found, suit_rms=np.sqrt((e ** 2).mean(0)).round(2).tolist(), levelled_rms=np.sqrt((f ** 2).mean(0)).round(2).tolist())
print(json.dumps(res, indent=1))
