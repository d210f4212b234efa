#!/bin/bash
# usage: bench/rounds/r21/score.sh NAME POLICY SEED   (raw validation draws SEED+; with SEED=820000 also validation clean)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r21
export MUJOCO_GL=egl OMP_NUM_THREADS=1
N=$1; P=$2; S=$3
.venv/bin/python bench/imu_draws.py --policies $P --mirror-average --ground --swing-lift --clips library:data/library/val --draws 40 --first-seed $S --stride 7 --episodes 2 --no-denoise --json bench/results/round21_raw_draws_${S}_$N.json > runs/r21/draws_${S}_$N.log 2>&1
if [ "$S" = 820000 ] && [ "$N" != WP ]; then
.venv/bin/python agents/evaluate.py --policy $P --mirror-average --ground --swing-lift --clips library:data/library/val --episodes 20 --per-clip --json bench/results/round21_val_clean_$N.json > runs/r21/clean_$N.log 2>&1
fi
