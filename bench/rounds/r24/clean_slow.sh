#!/bin/bash
# usage: bench/rounds/r24/clean_slow.sh NAME POLICY DENOISER [FLAGS...]   (validation clean, 20 episodes per take, the slowed denoiser on the clean takes too)
# DENOISE_SLOW (seconds, default 0.5) sets the slow corrections' Gaussian; set empty, the denoiser's full corrections (round 46).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r24
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; D=$3; shift 3
DENOISE_SLOW=${DENOISE_SLOW-0.5}
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --denoise $D ${DENOISE_SLOW:+--denoise-slow "$DENOISE_SLOW"} "$@" --ground --swing-lift --clips library:data/library/val --episodes 20 --per-clip --json bench/results/round24_val_clean_$N.json > runs/r24/clean_$N.log 2>&1
