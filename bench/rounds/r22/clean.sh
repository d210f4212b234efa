#!/bin/bash
# usage: bench/rounds/r22/clean.sh NAME [--part-legs]   (validation clean, 20 episodes per take)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r22
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; shift
.venv/bin/python agents/evaluate.py --policy models/mimic_general_window --mirror-average "$@" --ground --swing-lift --clips library:data/library/val --episodes 20 --per-clip --json bench/results/round22_val_clean_$N.json > runs/r22/clean_$N.log 2>&1
