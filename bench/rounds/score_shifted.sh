#!/bin/bash
# usage: bench/rounds/score_shifted.sh [--base-only] BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED CONFIRM_SEED OUT
# A registered policy candidate scored against a baseline, both behind SQ (the IMU rows' denoiser since round 32), by
# bench/select_policy.py's rule (--draws-per-policy 20): BASE (a checkpoint) with its validation clean file
# round24_val_clean_CLEAN_NAME.json and style-shifted draws round32_shifted_SEED_SHIFTED_NAME.json (each made if
# missing), against CANDIDATE's newest registered checkpoint (runs/r28/CANDIDATE_candidate.txt, waited for, written by
# bench/rounds/r28/candidate.sh), whose files are named CANDIDATE and CANDIDATE_SQ. The rule is written to
# bench/results/OUT_SEED.json; if the candidate leads, both are scored on CONFIRM_SEED and the rule with the
# confirmation draws is written to bench/results/OUT.json. With --base-only, only the baseline's files, for both seeds
# (they do not depend on the candidate: made while it trains). A candidate that replaces the baseline (OUT.json's
# replaces_baseline) has its held-out rows scored by hand, once: bench/rounds/r30/heldout.sh CANDIDATE slow.
set -eo pipefail
cd "$(dirname "$0")/../.."
BASE_ONLY=0
[ "$1" = --base-only ] && { BASE_ONLY=1; shift; }
BASE=$1; CLEAN=$2; SHIFTED=$3; CAND=$4; SEED=$5; CONFIRM=$6; OUT=$7
[ $# = 7 ] || { echo "score_shifted.sh: usage: score_shifted.sh [--base-only] BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED" \
  "CONFIRM_SEED OUT" >&2; exit 2; }
SQ=models/imu_denoiser_stances_quint_mirror
LABEL=" (mirror-averaged) + denoiser's hinge corrections slowed to 0.5 s + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm"
base_rows() {  # base_rows SEED...
  [ -f "bench/results/round24_val_clean_$CLEAN.json" ] ||
    bash bench/rounds/r24/clean_slow.sh "$CLEAN" "$BASE" "$SQ" --even-legs --part-legs
  for S in "$@"; do
    [ -f "bench/results/round32_shifted_${S}_$SHIFTED.json" ] || bash bench/rounds/r32/shifted.sh "$SHIFTED" "$BASE" "$S" "$SQ"
  done
}
if [ $BASE_ONLY = 1 ]; then base_rows "$SEED" "$CONFIRM"; exit; fi
base_rows "$SEED"
while [ ! -f "runs/r28/${CAND}_candidate.txt" ]; do sleep 20; done
POLICY=$(cat "runs/r28/${CAND}_candidate.txt")
bash bench/rounds/r24/clean_slow.sh "$CAND" "$POLICY" "$SQ" --even-legs --part-legs &
CLEAN_JOB=$!
bash bench/rounds/r32/shifted.sh "${CAND}_SQ" "$POLICY" "$SEED" "$SQ"
wait $CLEAN_JOB
rule() {  # rule OUT_FILE [--confirm FILES...]
  local out=$1; shift
  (cd bench && ../.venv/bin/python select_policy.py --baseline "$BASE$LABEL" \
    --clean "results/round24_val_clean_$CLEAN.json" "results/round24_val_clean_$CAND.json" \
    --draws "results/round32_shifted_${SEED}_$SHIFTED.json" "results/round32_shifted_${SEED}_${CAND}_SQ.json" \
    --draws-per-policy 20 "$@" --json "results/$out")
}
rule "${OUT}_$SEED.json"
if bash bench/rounds/rule_says.sh "${OUT}_$SEED" leads_by_rule; then
  base_rows "$CONFIRM" &
  BASE_JOB=$!
  bash bench/rounds/r32/shifted.sh "${CAND}_SQ" "$POLICY" "$CONFIRM" "$SQ"
  wait $BASE_JOB
  rule "$OUT.json" --confirm "results/round32_shifted_${CONFIRM}_$SHIFTED.json" "results/round32_shifted_${CONFIRM}_${CAND}_SQ.json"
fi
