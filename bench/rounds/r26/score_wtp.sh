#!/bin/bash
# Round 26: WTP scored as registered (amended 15:19 UTC): its newest checkpoint at 15:50 UTC is the candidate;
# the run is stopped with a checkpoint; validation IMU draws 1260000+ for WTP (WW's are scored alike) behind the
# denoiser's slow corrections, and WTP's validation clean.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
while pgrep -f "run-dir runs/r26/ppo_wtp" > /dev/null && [ "$(date -u +%H%M)" -lt 1550 ]; do sleep 20; done
W=$(ls runs/r26/ppo_wtp/checkpoints/step_*.zip | sort -V | tail -1)
echo "WTP candidate: $W at $(date -u +%H:%M:%S)" > runs/r26/wtp_candidate.txt
pkill -TERM -f "run-dir runs/r26/ppo_wtp"
while pgrep -f "run-dir runs/r26/ppo_wtp" > /dev/null; do sleep 5; done
QT=models/imu_denoiser_soles_quint_mirror
(bash bench/rounds/r24/score_slow.sh WTP $W 1260000 $QT --even-legs --part-legs; bash bench/rounds/r24/clean_slow.sh WTP $W $QT --even-legs --part-legs) &
bash bench/rounds/r24/score_slow.sh WW models/mimic_general_wide 1260000 $QT --even-legs --part-legs
wait
echo "scored 1260000+ at $(date -u +%H:%M:%S)" >> runs/r26/wtp_candidate.txt
