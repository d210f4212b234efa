#!/bin/bash
# Round 26: WW led validation's rule and its confirmation draws, so the held-out rows behind the denoiser once
# (seeds 1000-4000, the test split and the DeepMimic walkers), two seeds at a time on the two cores.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
W=runs/r25/ppo_wide/checkpoints/step_4005120.zip
QT=models/imu_denoiser_soles_quint_mirror
SEEDS="1000 2000" bash bench/rounds/r24/heldout_slow.sh WW $W $QT --even-legs --part-legs &
SEEDS="3000 4000" bash bench/rounds/r24/heldout_slow.sh WW $W $QT --even-legs --part-legs
wait
