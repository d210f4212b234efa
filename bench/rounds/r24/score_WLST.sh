#!/bin/bash
cd "$(dirname "$0")/../../.." && mkdir -p runs/r24
bash bench/rounds/r24/score_slow.sh WLST runs/r23/ppo_slow/checkpoints/step_3750016.zip 1010000 models/imu_denoiser_soles_quint_mirror --even-legs --part-legs
bash bench/rounds/r24/clean_slow.sh WLST runs/r23/ppo_slow/checkpoints/step_3750016.zip models/imu_denoiser_soles_quint_mirror --even-legs --part-legs
