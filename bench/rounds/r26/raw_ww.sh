#!/bin/bash
# Round 26: WW on raw IMU takes (no denoiser; legs evened and parted, grounded, swing-lifted, mirror-averaged)
# against WLE (models/mimic_general_legs alike), validation raw draws 1220000+ and WW's raw validation clean.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
W=runs/r25/ppo_wide/checkpoints/step_4005120.zip
(bash bench/rounds/r23/score_any.sh WW $W 1220000 --even-legs --part-legs; bash bench/rounds/r23/clean_any.sh WW $W --even-legs --part-legs) &
bash bench/rounds/r23/score_any.sh WLE models/mimic_general_legs 1220000 --even-legs --part-legs
wait
