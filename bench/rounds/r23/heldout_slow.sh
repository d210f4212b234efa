#!/bin/bash
# usage: bench/rounds/r23/heldout_slow.sh NAME POLICY [FLAGS...]  (held-out rows behind the denoiser's slow corrections, once, seeds 1000-4000)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; shift 2
for S in 1000 2000 3000 4000; do
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5 "$@" --ground --swing-lift --clips library:data/library/test --episodes 5 --per-clip --corrupt imu --strength 1 --seed $S --json bench/results/round23_test_imu1_slow_${N}_$S.json > runs/r23/test_slow_${N}_$S.log 2>&1
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5 "$@" --ground --swing-lift --clips deepmimic:walker/0walk_forward deepmimic:walker/turn_left1 deepmimic:walker/turn_right1 --episodes 20 --per-clip --corrupt imu --strength 1 --seed $S --json bench/results/round23_walkers_imu1_slow_${N}_$S.json > runs/r23/walkers_slow_${N}_$S.log 2>&1
done
