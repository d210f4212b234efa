#!/bin/bash
# usage: [BASE=NAME BASE_POLICY=CHECKPOINT] bench/rounds/r30/confirm.sh NAME ROW SEED   (ROW: slow or raw)
# The registered confirmation draws from SEED of a candidate NAME (its checkpoint in runs/r28/NAME_candidate.txt) on a
# row it led by the rule, against the baseline bench/rounds/r30/score.sh takes (PV, or BASE / BASE_POLICY). Round 30's
# SOUP: BASE=PV10 BASE_POLICY=runs/r29/ppo_pv10/checkpoints/step_4002912.zip ... SOUP slow 1480000; round 31's LU:
# the same baseline, LU slow 1510000 (raw, against PV: SOUP raw 1490000, LU raw 1530000, neither needed).
set -eo pipefail
cd "$(dirname "$0")/../../.."
[ $# -eq 3 ] || { echo "confirm.sh: NAME ROW SEED expected, got '$*'" >&2; exit 2; }
W=$(cat "runs/r28/$1_candidate.txt")
bash bench/rounds/r30/score.sh "$2" "$1" "$W" "$3"
echo "confirmed? $2 at $(date -u +%H:%M:%S)"
