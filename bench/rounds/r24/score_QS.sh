#!/bin/bash
cd "$(dirname "$0")/../../.." && mkdir -p runs/r24
bash bench/rounds/r24/score_slow.sh WLS models/mimic_general_legs 1040000 models/imu_denoiser_soles_quint_mirror --even-legs --part-legs
bash bench/rounds/r24/score_slow.sh QS runs/r24/legs_QS 1040000 runs/r24/QS --even-legs --part-legs
bash bench/rounds/r24/clean_slow.sh QS runs/r24/legs_QS runs/r24/QS --even-legs --part-legs
