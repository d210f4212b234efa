#!/bin/bash
# Round 29: the artefact-kind probe of round 28 on PV's candidate, behind the denoiser's slow corrections, on the
# seeds WU's ran (1310000-1313000), to see whether what the stance skate and the drift cost has shrunk
# (python bench/rounds/r28/kinds_summary.py PV _dn).
set -eo pipefail
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/PV_candidate.txt)
for s in 1310000 1311000 1312000 1313000; do
  NAME=PV POLICY="$W" bash bench/rounds/r28/kinds_probe.sh $s --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5
  echo "seed $s at $(date -u +%H:%M:%S)"
done
