#!/bin/bash
# Round 31: LU scored as registered: its newest checkpoint at 05:35 UTC (or its last) is the candidate
# (bench/rounds/r28/candidate.sh stops the run, resumable); validation IMU draws 1500000+ behind the denoiser's slow
# corrections against PV10, then validation raw draws 1520000+ against PV (bench/rounds/r30/score.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/r28/candidate.sh runs/r31/ppo_lu 0535 LU
W=$(cat runs/r28/LU_candidate.txt)
BASE=PV10 BASE_POLICY=runs/r29/ppo_pv10/checkpoints/step_4002912.zip bash bench/rounds/r30/score.sh slow LU "$W" 1500000
echo "scored 1500000+ at $(date -u +%H:%M:%S)"
bash bench/rounds/r30/score.sh raw LU "$W" 1520000
echo "scored raw 1520000+ at $(date -u +%H:%M:%S)"
