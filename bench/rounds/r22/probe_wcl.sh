#!/bin/bash
# WCL (mimic_general_clean_pose --part-legs) on validation's raw IMU takes, with every artefact kind but one (probe seeds 670000+)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r22
export MUJOCO_GL=egl OMP_NUM_THREADS=1
for K in none adduction skate drift noise height heading bias jitter root_drift; do
for S in 670000 670100 670200; do
W=""; [ "$K" != none ] && W="--without $K"
.venv/bin/python agents/evaluate.py --policy models/mimic_general_clean_pose --mirror-average --part-legs --ground --swing-lift --clips library:data/library/val --episodes 4 --per-clip --corrupt imu $W --strength 1 --seed $S --json bench/results/round22_loo_WCL_no_${K}_$S.json > runs/r22/loo_${K}_$S.log 2>&1
done
done
