#!/bin/bash
# usage: bench/rounds/r23/clean_any.sh NAME POLICY [FLAGS...]   (validation clean, 20 episodes per take)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; shift 2
.venv/bin/python agents/evaluate.py --policy $P --mirror-average "$@" --ground --swing-lift --clips library:data/library/val --episodes 20 --per-clip --json bench/results/round23_val_clean_$N.json > runs/r23/clean_$N.log 2>&1
