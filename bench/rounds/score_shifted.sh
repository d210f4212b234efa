#!/bin/bash
# usage: bench/rounds/score_shifted.sh [--base-only] BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED CONFIRM_SEED OUT
# A registered policy candidate scored against a baseline, both behind SQ (the IMU rows' denoiser since round 32) or
# both raw (DENOISER empty, below), by
# bench/select_policy.py's rule (--draws-per-policy 20): BASE (a checkpoint) with its validation clean file
# round24_val_clean_CLEAN_NAME.json and style-shifted draws round32_shifted_SEED_SHIFTED_NAME.json, against
# CANDIDATE's newest registered checkpoint (runs/r28/CANDIDATE_candidate.txt, waited for, written by
# bench/rounds/r28/candidate.sh), whose files are named CANDIDATE and CANDIDATE_SQ (CANDIDATE_RAW raw). Each file is
# made if missing and kept if made (behind the same denoiser and slowing, else it stops), so a second call carries on;
# the two sides' files are made side by side. The rule
# is written to bench/results/OUT_SEED.json; if the candidate leads, both are scored on CONFIRM_SEED and the rule with
# the confirmation draws is written to bench/results/OUT.json. With --base-only, only the baseline's files, for both
# seeds (they do not depend on the candidate: made while it trains). A candidate that replaces the baseline (OUT.json's
# replaces_baseline) has its held-out rows scored by hand, once: DENOISER=models/imu_denoiser_stances_quint_mirror
# [DENOISE_SLOW= for SQ's full corrections] bash bench/rounds/r30/heldout.sh CANDIDATE slow, or raw: ... CANDIDATE raw.
# Each side's preparation: BASE_DENOISE_SLOW and CANDIDATE_DENOISE_SLOW, the seconds of SQ's slowed corrections
# (default 0.5, as every round before 46 scored both sides); set empty, SQ's full corrections (the shipped
# preparation since round 46). DENOISER set empty scores both sides raw, with no denoiser in front (the rows "no
# denoiser"): validation clean files round23_val_clean_NAME.json (bench/rounds/r23/clean_any.sh) and the candidate's
# draws named CANDIDATE_RAW. The baseline is named in the rule as its clean file names it.
set -eo pipefail
cd "$(dirname "$0")/../.."
BASE_ONLY=0
[ "$1" = --base-only ] && { BASE_ONLY=1; shift; }
BASE=$1; CLEAN=$2; SHIFTED=$3; CAND=$4; SEED=$5; CONFIRM=$6; OUT=$7
[ $# = 7 ] || { echo "score_shifted.sh: usage: score_shifted.sh [--base-only] BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED" \
  "CONFIRM_SEED OUT" >&2; exit 2; }
SQ=models/imu_denoiser_stances_quint_mirror
DENOISER=${DENOISER-$SQ}
case $DENOISER in
  "$SQ") CLEAN_ROUND=24 TAG=SQ ;;
  "") CLEAN_ROUND=23 TAG=RAW BASE_DENOISE_SLOW= CANDIDATE_DENOISE_SLOW= ;;
  *) echo "score_shifted.sh: DENOISER is $SQ (the default) or empty (raw), got '$DENOISER'" >&2; exit 2 ;;
esac
BASE_DENOISE_SLOW=${BASE_DENOISE_SLOW-0.5} CANDIDATE_DENOISE_SLOW=${CANDIDATE_DENOISE_SLOW-0.5}
clean_file() { echo "bench/results/round${CLEAN_ROUND}_val_clean_$1.json"; }  # clean_file NAME
kept() {  # kept FILE SLOW: FILE was made (status 1 if not), behind this call's denoiser and SLOW (else it stops here)
  [ -f "$1" ] || return 1
  .venv/bin/python -c "import json, sys
f, denoiser, slow = sys.argv[1:]
d = json.load(open(f))
got, want = (d.get('denoiser'), d.get('denoise_slow_s')), (denoiser or None, float(slow) if slow else None)
sys.exit(got != want and f'score_shifted.sh: {f} was made behind the denoiser {got[0]} slowed {got[1]}, this call '
         f'asks for {want[0]} slowed {want[1]}: give its files other names')" "$1" "$DENOISER" "$2" || exit 2
}
rows() {  # rows SLOW POLICY CLEAN_NAME SHIFTED_NAME SEED...: a side's validation clean file and draw files, if missing
  # (the clean file is made beside the draw files, so a side whose other side's files are kept uses both cores)
  local slow=$1 policy=$2 clean=$3 shifted=$4 seed clean_job=
  shift 4
  if ! kept "$(clean_file "$clean")" "$slow"; then
    if [ -n "$DENOISER" ]; then
      DENOISE_SLOW=$slow bash bench/rounds/r24/clean_slow.sh "$clean" "$policy" "$DENOISER" --even-legs --part-legs &
    else
      bash bench/rounds/r23/clean_any.sh "$clean" "$policy" --even-legs --part-legs &
    fi
    clean_job=$!
  fi
  for seed in "$@"; do
    kept "bench/results/round32_shifted_${seed}_$shifted.json" "$slow" ||
      DENOISE_SLOW=$slow bash bench/rounds/r32/shifted.sh "$shifted" "$policy" "$seed" "$DENOISER"
  done
  [ -z "$clean_job" ] || wait "$clean_job"
}
if [ $BASE_ONLY = 1 ]; then rows "$BASE_DENOISE_SLOW" "$BASE" "$CLEAN" "$SHIFTED" "$SEED" "$CONFIRM"; exit; fi
rows "$BASE_DENOISE_SLOW" "$BASE" "$CLEAN" "$SHIFTED" "$SEED" &
BASE_JOB=$!
while [ ! -f "runs/r28/${CAND}_candidate.txt" ]; do sleep 20; done
POLICY=$(cat "runs/r28/${CAND}_candidate.txt")
rows "$CANDIDATE_DENOISE_SLOW" "$POLICY" "$CAND" "${CAND}_$TAG" "$SEED"
wait $BASE_JOB
BASE_NAME=$(.venv/bin/python -c "import json, sys; print(json.load(open(sys.argv[1]))['policy'])" "$(clean_file "$CLEAN")")
rule() {  # rule OUT_FILE [--confirm FILES...]
  local out=$1; shift
  (cd bench && ../.venv/bin/python select_policy.py --baseline "$BASE_NAME" \
    --clean "../$(clean_file "$CLEAN")" "../$(clean_file "$CAND")" \
    --draws "results/round32_shifted_${SEED}_$SHIFTED.json" "results/round32_shifted_${SEED}_${CAND}_$TAG.json" \
    --draws-per-policy 20 "$@" --json "results/$out")
}
rule "${OUT}_$SEED.json"
if bash bench/rounds/rule_says.sh "${OUT}_$SEED" leads_by_rule; then
  rows "$BASE_DENOISE_SLOW" "$BASE" "$CLEAN" "$SHIFTED" "$CONFIRM" &
  BASE_JOB=$!
  rows "$CANDIDATE_DENOISE_SLOW" "$POLICY" "$CAND" "${CAND}_$TAG" "$CONFIRM"
  wait $BASE_JOB
  rule "$OUT.json" --confirm "results/round32_shifted_${CONFIRM}_$SHIFTED.json" \
    "results/round32_shifted_${CONFIRM}_${CAND}_$TAG.json"
fi
