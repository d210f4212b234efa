#!/bin/bash
# usage: bench/rounds/r31/confirm_lu.sh ROW   (ROW: slow or raw)
# Round 31: LU's registered confirmation draws for a row it led by the rule: 1510000+ behind the denoiser's slow
# corrections against PV10, 1530000+ raw against PV (bench/rounds/r30/score.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/LU_candidate.txt)
case $1 in
  slow) BASE=PV10 BASE_POLICY=runs/r29/ppo_pv10/checkpoints/step_4002912.zip bash bench/rounds/r30/score.sh slow LU "$W" 1510000 ;;
  raw)  bash bench/rounds/r30/score.sh raw LU "$W" 1530000 ;;
  *) echo "confirm_lu.sh: ROW is slow or raw, got '$1'" >&2; exit 2 ;;
esac
echo "confirmed? $1 at $(date -u +%H:%M:%S)"
