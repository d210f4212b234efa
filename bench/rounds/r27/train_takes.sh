#!/bin/bash
# usage: bench/rounds/r27/train_takes.sh NAME POLICY
# A policy on its training takes, side by side (as rounds 25-26 reported them): clean, and behind the denoiser's
# slow corrections at IMU strength 1 with seed 1140000, 2 rollouts per take; then the five taught takes (the lost
# dashes and runs of bench/rounds/r27/ks_set) clean with 8 rollouts each.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r27
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; W=$2
QT=models/imu_denoiser_soles_quint_mirror
PREP="--mirror-average --even-legs --part-legs --ground --swing-lift"
.venv/bin/python agents/evaluate.py --policy $W $PREP --clips library:data/library/train --episodes 2 --per-clip --json bench/results/round27_train_clean_$N.json > runs/r27/train_clean_$N.log 2>&1 &
.venv/bin/python agents/evaluate.py --policy $W $PREP --denoise $QT --denoise-slow 0.5 --clips library:data/library/train --episodes 2 --per-clip --corrupt imu --strength 1 --seed 1140000 --json bench/results/round27_train_imu1_${N}_1140000.json > runs/r27/train_imu_$N.log 2>&1
wait
T="library:data/library#dataset-1_dash_active_001 library:data/library#dataset-1_dash_musical_001 library:data/library#dataset-1_dash_masculinity_001 library:data/library#dataset-1_run_active_001 library:data/library#dataset-1_run_musical_001"
.venv/bin/python agents/evaluate.py --policy $W $PREP --clips $T --episodes 8 --per-clip --json bench/results/round27_taught_clean_$N.json > runs/r27/taught_clean_$N.log 2>&1
