#!/bin/bash
# usage: bench/rounds/r22/score.sh NAME SEED [--part-legs]
cd "$(dirname "$0")/../../.." && mkdir -p runs/r22
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; S=$2; shift 2
.venv/bin/python bench/imu_draws.py --policies models/mimic_general_window --mirror-average "$@" --ground --swing-lift --clips library:data/library/val --draws 40 --first-seed $S --stride 7 --episodes 2 --no-denoise --json bench/results/round22_raw_draws_${S}_$N.json > runs/r22/draws_${S}_$N.log 2>&1
