#!/bin/bash
# usage: bench/rounds/r30/confirm_soup.sh ROW   (ROW: slow or raw)
# Round 30: SOUP's registered confirmation draws for a row it led by the rule: 1480000+ behind the denoiser's slow
# corrections against PV10, 1490000+ raw against PV (bench/rounds/r30/score.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/SOUP_candidate.txt)
case $1 in
  slow) BASE=PV10 BASE_POLICY=runs/r29/ppo_pv10/checkpoints/step_4002912.zip bash bench/rounds/r30/score.sh slow SOUP "$W" 1480000 ;;
  raw)  bash bench/rounds/r30/score.sh raw SOUP "$W" 1490000 ;;
  *) echo "confirm_soup.sh: ROW is slow or raw, got '$1'" >&2; exit 2 ;;
esac
echo "confirmed? $1 at $(date -u +%H:%M:%S)"
