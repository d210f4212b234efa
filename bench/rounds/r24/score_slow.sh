#!/bin/bash
# usage: bench/rounds/r24/score_slow.sh NAME POLICY SEED DENOISER [FLAGS...]   (validation IMU draws behind DENOISER's slow corrections, 40 x 2 rollouts per take)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r24
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; S=$3; D=$4; shift 4
.venv/bin/python bench/imu_draws.py --policies $P --mirror-average --denoise $D --denoise-slow 0.5 "$@" --ground --swing-lift --clips library:data/library/val --draws 40 --first-seed $S --stride 7 --episodes 2 --json bench/results/round24_draws_${S}_$N.json > runs/r24/draws_${S}_$N.log 2>&1
