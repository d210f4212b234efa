#!/bin/bash
# usage: bench/rounds/r24/heldout_slow.sh NAME POLICY DENOISER [FLAGS...]  (held-out rows behind DENOISER's slow corrections, once, seeds 1000-4000)
# DENOISE_SLOW (seconds, default 0.5) sets the slow corrections' Gaussian; set empty, the denoiser's full corrections (round 46).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r24
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; D=$3; shift 3
DENOISE_SLOW=${DENOISE_SLOW-0.5}
for S in ${SEEDS:-1000 2000 3000 4000}; do
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --denoise $D ${DENOISE_SLOW:+--denoise-slow "$DENOISE_SLOW"} "$@" --ground --swing-lift --clips library:data/library/test --episodes 5 --per-clip --corrupt imu --strength 1 --seed $S --json bench/results/round24_test_imu1_slow_${N}_$S.json > runs/r24/test_slow_${N}_$S.log 2>&1
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --denoise $D ${DENOISE_SLOW:+--denoise-slow "$DENOISE_SLOW"} "$@" --ground --swing-lift --clips deepmimic:walker/0walk_forward deepmimic:walker/turn_left1 deepmimic:walker/turn_right1 --episodes 20 --per-clip --corrupt imu --strength 1 --seed $S --json bench/results/round24_walkers_imu1_slow_${N}_$S.json > runs/r24/walkers_slow_${N}_$S.log 2>&1
done
