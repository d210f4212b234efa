#!/bin/bash
# WLE (mimic_general_legs --even-legs --part-legs) on validation's raw IMU takes, with every artefact kind but one (probe seeds 670000+, as round 22's probe)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
export MUJOCO_GL=egl OMP_NUM_THREADS=1
for K in none skate drift bias noise adduction; do
for S in 670000 670100 670200; do
W=""; [ "$K" != none ] && W="--without $K"
.venv/bin/python agents/evaluate.py --policy models/mimic_general_legs --mirror-average --even-legs --part-legs --ground --swing-lift --clips library:data/library/val --episodes 4 --per-clip --corrupt imu $W --strength 1 --seed $S --json bench/results/round23_loo_WLE_no_${K}_$S.json > runs/r23/loo_${K}_$S.log 2>&1
done
done
