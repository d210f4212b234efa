#!/bin/bash
# usage: bench/rounds/r30/confirm_pv10.sh ROW   (ROW: slow or raw)
# Round 30: PV10's registered confirmation draws for a row it led by the rule: 1440000+ behind the denoiser's slow
# corrections, 1450000+ raw, against PV's (bench/rounds/r30/score.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/PV10_candidate.txt)
case $1 in
  slow) bash bench/rounds/r30/score.sh slow PV10 "$W" 1440000 ;;
  raw)  bash bench/rounds/r30/score.sh raw PV10 "$W" 1450000 ;;
  *) echo "confirm_pv10.sh: ROW is slow or raw, got '$1'" >&2; exit 2 ;;
esac
echo "confirmed? $1 at $(date -u +%H:%M:%S)"
