#!/bin/bash
# Round 25: WSQ scored as registered in docs/results.md, "Round 24". Waits for the resumed run to end.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r25
while pgrep -f "run-dir runs/r24/ppo_stances" > /dev/null; do sleep 15; done
W=$(ls runs/r24/ppo_stances/checkpoints/step_*.zip | sort -V | tail -1)
echo "WSQ candidate: $W" > runs/r25/wsq_candidate.txt
SQ=models/imu_denoiser_stances_quint_mirror
QT=models/imu_denoiser_soles_quint_mirror
(bash bench/rounds/r24/score_slow.sh WSQ $W 1100000 $SQ --even-legs --part-legs; bash bench/rounds/r24/clean_slow.sh WSQ $W $SQ --even-legs --part-legs) &
(bash bench/rounds/r24/score_slow.sh WLST_SQ models/mimic_general_slow 1100000 $SQ --even-legs --part-legs; bash bench/rounds/r24/clean_slow.sh WLST_SQ models/mimic_general_slow $SQ --even-legs --part-legs; bash bench/rounds/r24/score_slow.sh WLST models/mimic_general_slow 1100000 $QT --even-legs --part-legs) &
wait
echo done >> runs/r25/wsq_candidate.txt
