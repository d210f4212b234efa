#!/bin/bash
# usage: bench/rounds/score_shifted.sh [--base-only] BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED CONFIRM_SEED OUT
# A registered policy candidate scored against a baseline, both behind SQ (the IMU rows' denoiser since round 32), by
# bench/select_policy.py's rule (--draws-per-policy 20): BASE (a checkpoint) with its validation clean file
# round24_val_clean_CLEAN_NAME.json and style-shifted draws round32_shifted_SEED_SHIFTED_NAME.json, against
# CANDIDATE's newest registered checkpoint (runs/r28/CANDIDATE_candidate.txt, waited for, written by
# bench/rounds/r28/candidate.sh), whose files are named CANDIDATE and CANDIDATE_SQ. Each file is made if missing and
# kept if made, so a second call carries on. The rule is written to bench/results/OUT_SEED.json; if the candidate
# leads, both are scored on CONFIRM_SEED and the rule with the confirmation draws is written to
# bench/results/OUT.json. With --base-only, only the baseline's files, for both seeds (they do not depend on the
# candidate: made while it trains). A candidate that replaces the baseline (OUT.json's replaces_baseline) has its
# held-out rows scored by hand, once: bench/rounds/r30/heldout.sh CANDIDATE slow.
# Each side's preparation: BASE_DENOISE_SLOW and CANDIDATE_DENOISE_SLOW, the seconds of SQ's slowed corrections
# (default 0.5, as every round before 46 scored both sides); set empty, SQ's full corrections (the shipped
# preparation since round 46). The baseline is named in the rule as its clean file names it.
set -eo pipefail
cd "$(dirname "$0")/../.."
BASE_ONLY=0
[ "$1" = --base-only ] && { BASE_ONLY=1; shift; }
BASE=$1; CLEAN=$2; SHIFTED=$3; CAND=$4; SEED=$5; CONFIRM=$6; OUT=$7
[ $# = 7 ] || { echo "score_shifted.sh: usage: score_shifted.sh [--base-only] BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED" \
  "CONFIRM_SEED OUT" >&2; exit 2; }
SQ=models/imu_denoiser_stances_quint_mirror
BASE_DENOISE_SLOW=${BASE_DENOISE_SLOW-0.5} CANDIDATE_DENOISE_SLOW=${CANDIDATE_DENOISE_SLOW-0.5}
rows() {  # rows SLOW POLICY CLEAN_NAME SHIFTED_NAME SEED...: a side's validation clean file and draw files, if missing
  local slow=$1 policy=$2 clean=$3 shifted=$4 seed
  shift 4
  [ -f "bench/results/round24_val_clean_$clean.json" ] ||
    DENOISE_SLOW=$slow bash bench/rounds/r24/clean_slow.sh "$clean" "$policy" "$SQ" --even-legs --part-legs
  for seed in "$@"; do
    [ -f "bench/results/round32_shifted_${seed}_$shifted.json" ] ||
      DENOISE_SLOW=$slow bash bench/rounds/r32/shifted.sh "$shifted" "$policy" "$seed" "$SQ"
  done
}
if [ $BASE_ONLY = 1 ]; then rows "$BASE_DENOISE_SLOW" "$BASE" "$CLEAN" "$SHIFTED" "$SEED" "$CONFIRM"; exit; fi
rows "$BASE_DENOISE_SLOW" "$BASE" "$CLEAN" "$SHIFTED" "$SEED"
while [ ! -f "runs/r28/${CAND}_candidate.txt" ]; do sleep 20; done
POLICY=$(cat "runs/r28/${CAND}_candidate.txt")
rows "$CANDIDATE_DENOISE_SLOW" "$POLICY" "$CAND" "${CAND}_SQ" "$SEED"
BASE_NAME=$(.venv/bin/python -c "import json, sys; print(json.load(open(sys.argv[1]))['policy'])" \
  "bench/results/round24_val_clean_$CLEAN.json")
rule() {  # rule OUT_FILE [--confirm FILES...]
  local out=$1; shift
  (cd bench && ../.venv/bin/python select_policy.py --baseline "$BASE_NAME" \
    --clean "results/round24_val_clean_$CLEAN.json" "results/round24_val_clean_$CAND.json" \
    --draws "results/round32_shifted_${SEED}_$SHIFTED.json" "results/round32_shifted_${SEED}_${CAND}_SQ.json" \
    --draws-per-policy 20 "$@" --json "results/$out")
}
rule "${OUT}_$SEED.json"
if bash bench/rounds/rule_says.sh "${OUT}_$SEED" leads_by_rule; then
  rows "$BASE_DENOISE_SLOW" "$BASE" "$CLEAN" "$SHIFTED" "$CONFIRM" &
  BASE_JOB=$!
  rows "$CANDIDATE_DENOISE_SLOW" "$POLICY" "$CAND" "${CAND}_SQ" "$CONFIRM"
  wait $BASE_JOB
  rule "$OUT.json" --confirm "results/round32_shifted_${CONFIRM}_$SHIFTED.json" "results/round32_shifted_${CONFIRM}_${CAND}_SQ.json"
fi
