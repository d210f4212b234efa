#!/bin/bash
# Round 30: PV10 scored as registered: its newest checkpoint at 02:35 UTC (or its last) is the candidate
# (bench/rounds/r28/candidate.sh stops the run, resumable); validation IMU draws 1420000+ behind the denoiser's
# slow corrections, then validation raw draws 1430000+, each against PV's (bench/rounds/r30/score.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/r28/candidate.sh runs/r29/ppo_pv10 0235 PV10
W=$(cat runs/r28/PV10_candidate.txt)
bash bench/rounds/r30/score.sh slow PV10 "$W" 1420000
echo "scored 1420000+ at $(date -u +%H:%M:%S)"
bash bench/rounds/r30/score.sh raw PV10 "$W" 1430000
echo "scored raw 1430000+ at $(date -u +%H:%M:%S)"
