#!/bin/bash
# Round 29: PV scored as registered: its newest checkpoint at 23:45 UTC (or its last) is the candidate
# (bench/rounds/r28/candidate.sh stops the run, resumable); validation IMU draws 1380000+ behind the denoiser's
# slow corrections against WW's (bench/rounds/r27/score.sh), then validation raw draws 1390000+ against WW's
# (bench/rounds/r28/score_raw.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/r28/candidate.sh runs/r29/ppo_pv 2345 PV
W=$(cat runs/r28/PV_candidate.txt)
bash bench/rounds/r27/score.sh PV "$W" 1380000
echo "scored 1380000+ at $(date -u +%H:%M:%S)"
bash bench/rounds/r28/score_raw.sh PV "$W" 1390000
echo "scored raw 1390000+ at $(date -u +%H:%M:%S)"
