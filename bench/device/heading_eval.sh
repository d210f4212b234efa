#!/bin/bash
# Lent-machine measurement of the "reference" observation frame (README "Observing in the reference's
# heading"): on 16 cores at once, the adapted protocol (bench/adapted_cleaning.py --denoise, 300 s per
# take, one process per take: each take has a core to itself, as in the 2-core protocol) and the
# zero-shot evaluations of the library's test split and the held-out DeepMimic walkers in both frames,
# side by side. Carried as in gpu_ab.sh: .whl/ (py3.12 wheels of mujoco, mujoco-core, mujoco-studio,
# glfw, pyopengl, gymnasium, stable-baselines3, farama-notifications) and .devpkgs/ (the stand-in
# pybullet_data, lib/ = data/library's humanoid_1seg takes and manifest).
# $1: adaptation budget (s, default 300); $2: rollouts per test take (default 5); $3: the takes
# (default "0 ... 9"). POLICY=DIR adapts another policy, OBS_FRAME=world|reference observing in that frame;
# ADAPTED_ONLY=1 runs the adapted protocol alone (the world-axes run of the README: ADAPTED_ONLY=1
# OBS_FRAME=world, run then with a copy of the generalist whose sidecar said world).
# Writes $OUT/adapted.json (every take) and $OUT/evaluations.json (ELR and SR90 of each evaluation).
set -u
ADAPT_S=${1:-300}; EPISODES=${2:-5}; TAKES=${3:-0 1 2 3 4 5 6 7 8 9}
OUT=${OUT:-/tmp/heading_eval}; WORK=$(mktemp -d); mkdir -p $OUT
PY=${PY:-python3}
source bench/device/setup.sh
POLICY=${POLICY:-models/mimic_general}
for i in $TAKES; do
  $PY bench/adapted_cleaning.py --policy $POLICY ${OBS_FRAME:+--obs-frame $OBS_FRAME} --only $i --denoise --adapt-budget-s $ADAPT_S \
    --json $WORK/adapted_$i.json > $WORK/adapted_$i.log 2>&1 &
done
if [ -z "${ADAPTED_ONLY:-}" ]; then
  WALKERS="deepmimic:walker/0walk_forward deepmimic:walker/turn_left1 deepmimic:walker/turn_right1"
  EVAL="$PY agents/evaluate.py --policy $POLICY"
  for f in reference world; do
    $EVAL --obs-frame $f --clips library:data/library/test --episodes $EPISODES --json $WORK/eval_test_clean_$f.json > /dev/null 2>&1 &
    $EVAL --obs-frame $f --clips library:data/library/test --episodes $EPISODES --corrupt imu --strength 1 --json $WORK/eval_test_imu_$f.json > /dev/null 2>&1 &
    $EVAL --obs-frame $f --clips $WALKERS --episodes $((EPISODES * 4)) --json $WORK/eval_walkers_clean_$f.json > /dev/null 2>&1 &
    $EVAL --obs-frame $f --clips $WALKERS --episodes $((EPISODES * 4)) --corrupt imu --strength 1 --seed 1000 --json $WORK/eval_walkers_imu_$f.json > /dev/null 2>&1 &
  done
fi
wait
$PY - $WORK $OUT/evaluations.json <<'PYEOF'
import json, sys
from pathlib import Path
rows = {p.stem[5:]: {k: json.loads(p.read_text())[k] for k in ("ELR_mean", "ELR_std", "SR90", "MRR_mean", "clips", "corrupt", "obs_frame")}
        for p in sorted(Path(sys.argv[1]).glob("eval_*.json"))}
for name, r in rows.items():
    print(f"{name:<28} ELR {r['ELR_mean']:.3f}  SR90 {r['SR90']:.3f}")
Path(sys.argv[2]).write_text(json.dumps(rows, indent=1))
PYEOF
$PY bench/adapted_cleaning.py --merge $WORK/adapted_*.json
$PY bench/adapted_cleaning.py --merge $WORK/adapted_*.json --json $OUT/adapted.json > /dev/null
tail -n 3 $(ls $WORK/adapted_*.log | head -1)
