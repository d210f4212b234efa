#!/bin/bash
# usage: bench/rounds/r23/score_any.sh NAME POLICY SEED [FLAGS...]   (validation raw IMU draws, 40 x 2 rollouts per take)
# FLAGS: the preparation besides --mirror-average --ground --swing-lift, e.g. --part-legs --even-legs
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; S=$3; shift 3
.venv/bin/python bench/imu_draws.py --policies $P --mirror-average "$@" --ground --swing-lift --no-denoise --clips library:data/library/val --draws 40 --first-seed $S --stride 7 --episodes 2 --json bench/results/round23_draws_${S}_$N.json > runs/r23/draws_${S}_$N.log 2>&1
