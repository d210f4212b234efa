#!/bin/bash
# Round 26: WW scored as registered in round 25. The candidate is the run's final checkpoint (4.0 M steps)
# or, if the run has not ended by 14:45 UTC, its newest checkpoint then (the run is then stopped with a
# checkpoint). Validation IMU draws 1180000+ for WW and WLST behind the ensemble's slow corrections,
# WW's validation clean. If WW leads the rule, the confirmation draws 1190000+ follow (the same two
# score_slow.sh lines with seed 1190000).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
while pgrep -f "run-dir runs/r25/ppo_wide" > /dev/null && [ "$(date -u +%H%M)" -lt 1445 ]; do sleep 20; done
W=$(ls runs/r25/ppo_wide/checkpoints/step_*.zip | sort -V | tail -1)
echo "WW candidate: $W at $(date -u +%H:%M:%S)" > runs/r26/ww_candidate.txt
pkill -TERM -f "run-dir runs/r25/ppo_wide"
while pgrep -f "run-dir runs/r25/ppo_wide" > /dev/null; do sleep 5; done
QT=models/imu_denoiser_soles_quint_mirror
(bash bench/rounds/r24/score_slow.sh WW $W 1180000 $QT --even-legs --part-legs; bash bench/rounds/r24/clean_slow.sh WW $W $QT --even-legs --part-legs) &
bash bench/rounds/r24/score_slow.sh WLST models/mimic_general_slow 1180000 $QT --even-legs --part-legs
wait
echo "scored 1180000+ at $(date -u +%H:%M:%S)" >> runs/r26/ww_candidate.txt
