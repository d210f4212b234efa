"""Held-out rows: a candidate against a baseline, paired per take and seed (usage: A_PATTERN B_PATTERN)."""
import json
import sys
import numpy as np
a_pat, b_pat = sys.argv[1], sys.argv[2]  # e.g. round23_{set}_imu1_raw_WLE_{seed} round22_{set}_imu1_raw_WLC_{seed}
for st in ("test", "walkers"):
    a_m, b_m, diffs, srs = [], [], [], []
    for s in (1000, 2000, 3000, 4000):
        a = json.load(open(f"bench/results/{a_pat.format(set=st, seed=s)}.json"))
        b = json.load(open(f"bench/results/{b_pat.format(set=st, seed=s)}.json"))
        a_m.append(a["ELR_mean"]); b_m.append(b["ELR_mean"]); srs.append((a["SR90"], b["SR90"]))
        pa = {c["clip"]: c["ELR"] for c in a["per_clip"]}
        pb = {c["clip"]: c["ELR"] for c in b["per_clip"]}
        diffs += [pa[c] - pb[c] for c in pa]
    d = np.array(diffs)
    print(f"{st}: {' / '.join(f'{x:.3f}' for x in a_m)} = {np.mean(a_m):.3f} (SR90 {np.mean([x for x, _ in srs]):.2f}) "
          f"against {np.mean(b_m):.3f} (SR90 {np.mean([y for _, y in srs]):.2f}): {d.mean():+.3f} ± {d.std(ddof=1) / np.sqrt(len(d)):.3f} "
          f"over {len(d)} take-draws, above/below {(d > 0).sum()}/{(d < 0).sum()}")
