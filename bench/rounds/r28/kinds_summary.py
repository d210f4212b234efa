"""Round 28: summarises bench/rounds/r28/kinds_probe.sh. For each artefact kind, the mean ELR with every kind but
that one, and its paired gain over every kind (per take and seed: mean +- standard error).

usage: python bench/rounds/r28/kinds_summary.py NAME [_dn]   (NAME: WW, or the probe's NAME; _dn: behind the denoiser)
"""
import collections
import glob
import json
import sys

import numpy as np

name = sys.argv[1]
suffix = sys.argv[2] if len(sys.argv) > 2 else ""
by_condition = collections.defaultdict(dict)  # condition -> seed -> {take: ELR}
for path in glob.glob(f"bench/results/round28_kinds_{name}_*{suffix}.json"):
    stem = path.split(f"round28_kinds_{name}_")[1][:-len(".json")]
    if stem.endswith("_dn") != bool(suffix):
        continue
    condition, seed = stem[:len(stem) - len(suffix)].rsplit("_", 1)
    by_condition[condition][seed] = {c["clip"]: c["ELR"] for c in json.load(open(path))["per_clip"]}


def table(condition: str, seeds: list[str]) -> np.ndarray:
    """ELR per (seed, take), takes in name order."""
    return np.array([[by_condition[condition][s][t] for t in sorted(by_condition[condition][s])] for s in seeds])


every = by_condition["all"]
print("seeds", sorted(every), "every kind %.3f" % table("all", sorted(every)).mean())
for condition in sorted(by_condition):
    if condition == "all":
        continue
    seeds = sorted(s for s in by_condition[condition] if s in every)
    gain = (table(condition, seeds) - table("all", seeds)).ravel()
    print("%-14s %.3f gain %+.3f ± %.3f" % (condition, table(condition, seeds).mean(), gain.mean(),
                                            gain.std(ddof=1) / np.sqrt(len(gain))))
