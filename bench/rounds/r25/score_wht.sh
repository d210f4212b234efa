#!/bin/bash
# Round 25: WHT scored as registered. At 12:20 UTC (or when the run ends) the newest checkpoint is the
# candidate; the run is then stopped with a checkpoint; validation IMU draws 1160000+ for WHT and WLST
# behind the ensemble's slow corrections, and WHT's validation clean.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r25
while pgrep -f "run-dir runs/r25/ppo_hard" > /dev/null && [ "$(date -u +%H%M)" -lt 1220 ]; do sleep 20; done
W=$(ls runs/r25/ppo_hard/checkpoints/step_*.zip | sort -V | tail -1)
echo "WHT candidate: $W at $(date -u +%H:%M:%S)" > runs/r25/wht_candidate.txt
pkill -TERM -f "run-dir runs/r25/ppo_hard"
while pgrep -f "run-dir runs/r25/ppo_hard" > /dev/null; do sleep 5; done
QT=models/imu_denoiser_soles_quint_mirror
(bash bench/rounds/r24/score_slow.sh WHT $W 1160000 $QT --even-legs --part-legs; bash bench/rounds/r24/clean_slow.sh WHT $W $QT --even-legs --part-legs) &
bash bench/rounds/r24/score_slow.sh WLST models/mimic_general_slow 1160000 $QT --even-legs --part-legs
wait
echo scored >> runs/r25/wht_candidate.txt
