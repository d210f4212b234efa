#!/bin/bash
# Round 29: PV led both rows by the rule (behind the denoiser by its clean row alone, raw by its IMU draws too), so
# its registered confirmation draws: 1400000+ behind the denoiser's slow corrections, 1410000+ raw.
set -eo pipefail
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/PV_candidate.txt)
bash bench/rounds/r27/score.sh PV "$W" 1400000
echo "confirmed? 1400000+ at $(date -u +%H:%M:%S)"
bash bench/rounds/r28/score_raw.sh PV "$W" 1410000
echo "confirmed? raw 1410000+ at $(date -u +%H:%M:%S)"
