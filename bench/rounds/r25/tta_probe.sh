#!/bin/bash
# Round 25 probe: WLST behind QT, action averaged over K noisy copies of the normalised observation, 20 validation draws 1120000+.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r25
export MUJOCO_GL=egl OMP_NUM_THREADS=1
A="--policies models/mimic_general_slow --mirror-average --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --ground --swing-lift --clips library:data/library/val --draws 20 --first-seed 1120000 --stride 7 --episodes 2"
.venv/bin/python bench/imu_draws.py $A --json bench/results/round25_tta_draws_1120000_WLST.json > runs/r25/tta_base.log 2>&1
.venv/bin/python bench/rounds/r25/tta_draws.py 8 0.2 -- $A --json bench/results/round25_tta_draws_1120000_WLST_k8_s0.2.json > runs/r25/tta_k8_s02.log 2>&1
