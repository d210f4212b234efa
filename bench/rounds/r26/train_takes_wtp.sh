#!/bin/bash
# Round 26: WTP on its training takes (reported beside, as round 25 did for WLST): clean, and behind the
# denoiser's slow corrections at IMU strength 1 with seed 1140000; 2 rollouts per take, side by side.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
export MUJOCO_GL=egl OMP_NUM_THREADS=1
W=runs/r26/ppo_wtp/checkpoints/step_1250016.zip
QT=models/imu_denoiser_soles_quint_mirror
.venv/bin/python agents/evaluate.py --policy $W --mirror-average --even-legs --part-legs --ground --swing-lift --clips library:data/library/train --episodes 2 --per-clip --json bench/results/round26_train_clean_WTP.json > runs/r26/train_clean_WTP.log 2>&1 &
.venv/bin/python agents/evaluate.py --policy $W --mirror-average --denoise $QT --denoise-slow 0.5 --even-legs --part-legs --ground --swing-lift --clips library:data/library/train --episodes 2 --per-clip --corrupt imu --strength 1 --seed 1140000 --json bench/results/round26_train_imu1_WTP_1140000.json > runs/r26/train_imu_WTP.log 2>&1
wait
