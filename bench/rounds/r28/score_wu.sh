#!/bin/bash
# Round 28: WU scored as registered: its newest checkpoint at 21:05 UTC (or its last) is the candidate
# (bench/rounds/r28/candidate.sh stops the run, resumable); validation IMU draws 1320000+ behind the denoiser's
# slow corrections against WW's (bench/rounds/r27/score.sh), then validation raw draws 1340000+ against WW's
# (bench/rounds/r28/score_raw.sh), then the artefact-kind probe of the training takes on the candidate.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28
bash bench/rounds/r28/candidate.sh runs/r28/ppo_wu 2105 WU
W=$(cat runs/r28/WU_candidate.txt)
[ -n "$W" ] || { echo "score_wu.sh: no candidate" >&2; exit 1; }
bash bench/rounds/r27/score.sh WU "$W" 1320000
echo "scored 1320000+ at $(date -u +%H:%M:%S)"
bash bench/rounds/r28/score_raw.sh WU "$W" 1340000
echo "scored raw 1340000+ at $(date -u +%H:%M:%S)"
for s in 1310000 1311000 1312000 1313000; do
  NAME=WU POLICY="$W" bash bench/rounds/r28/kinds_probe.sh $s --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5
done
echo "kinds probe at $(date -u +%H:%M:%S)"
