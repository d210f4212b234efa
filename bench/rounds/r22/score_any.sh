#!/bin/bash
# usage: bench/rounds/r22/score_any.sh NAME POLICY SEED [FLAGS...]   (validation IMU draws, 40 x 2 rollouts per take)
# FLAGS: the preparation, e.g. --no-denoise --part-legs, or --denoise models/imu_denoiser_soles_quint_mirror
cd "$(dirname "$0")/../../.." && mkdir -p runs/r22
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; S=$3; shift 3
.venv/bin/python bench/imu_draws.py --policies $P --mirror-average "$@" --ground --swing-lift --clips library:data/library/val --draws 40 --first-seed $S --stride 7 --episodes 2 --json bench/results/round22_draws_${S}_$N.json > runs/r22/draws_${S}_$N.log 2>&1
