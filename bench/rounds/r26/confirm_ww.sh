#!/bin/bash
# Round 26: WW led the rule on 1180000+, so the registered confirmation draws 1190000+ for WW and WLST.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
W=runs/r25/ppo_wide/checkpoints/step_4005120.zip
QT=models/imu_denoiser_soles_quint_mirror
bash bench/rounds/r24/score_slow.sh WW $W 1190000 $QT --even-legs --part-legs &
bash bench/rounds/r24/score_slow.sh WLST models/mimic_general_slow 1190000 $QT --even-legs --part-legs
wait
echo "confirmed 1190000+ at $(date -u +%H:%M:%S)" >> runs/r26/ww_candidate.txt
