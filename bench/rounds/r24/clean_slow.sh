#!/bin/bash
# usage: bench/rounds/r24/clean_slow.sh NAME POLICY DENOISER [FLAGS...]   (validation clean, 20 episodes per take, the slowed denoiser on the clean takes too)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r24
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; D=$3; shift 3
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --denoise $D --denoise-slow 0.5 "$@" --ground --swing-lift --clips library:data/library/val --episodes 20 --per-clip --json bench/results/round24_val_clean_$N.json > runs/r24/clean_$N.log 2>&1
