#!/bin/bash
# Round 26: WT scored as registered: waits for its distillation to end, then validation IMU draws 1240000+ for WT
# and WW behind the denoiser's slow corrections, and WT's validation clean (and WW's again under its shipped name, which the rule's labels pair).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
while pgrep -f "out runs/r26/distill_wt" > /dev/null; do sleep 20; done
T=runs/r26/distill_wt/student
QT=models/imu_denoiser_soles_quint_mirror
(bash bench/rounds/r24/score_slow.sh WT $T 1240000 $QT --even-legs --part-legs; bash bench/rounds/r24/clean_slow.sh WT $T $QT --even-legs --part-legs) &
bash bench/rounds/r24/score_slow.sh WW models/mimic_general_wide 1240000 $QT --even-legs --part-legs
bash bench/rounds/r24/clean_slow.sh WW_shipped models/mimic_general_wide $QT --even-legs --part-legs  # the rule pairs labels
wait
echo "scored 1240000+ at $(date -u +%H:%M:%S)" > runs/r26/wt_scored.txt
