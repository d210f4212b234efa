#!/bin/bash
# usage: bench/rounds/r23/heldout.sh NAME POLICY  [FLAGS...] (held-out raw rows, once, seeds 1000-4000; FLAGS before --part-legs, e.g. --even-legs)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; shift 2
for S in 1000 2000 3000 4000; do
.venv/bin/python agents/evaluate.py --policy $P --mirror-average "$@" --part-legs --ground --swing-lift --clips library:data/library/test --episodes 5 --per-clip --corrupt imu --strength 1 --seed $S --json bench/results/round23_test_imu1_raw_${N}_$S.json > runs/r23/test_${N}_$S.log 2>&1
.venv/bin/python agents/evaluate.py --policy $P --mirror-average "$@" --part-legs --ground --swing-lift --clips deepmimic:walker/0walk_forward deepmimic:walker/turn_left1 deepmimic:walker/turn_right1 --episodes 20 --per-clip --corrupt imu --strength 1 --seed $S --json bench/results/round23_walkers_imu1_raw_${N}_$S.json > runs/r23/walkers_${N}_$S.log 2>&1
done
