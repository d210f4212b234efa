#!/bin/bash
# usage: bench/rounds/r46/score_full.sh
# Round 46, FULLSET: the shipped policy set (models/mimic_general_expert_set, DXSSET since round 44) as it is, tracking
# each IMU take behind the denoiser SQ's full corrections (the hinge angles' and the pelvis height's) in place of their
# slow part (--denoise-slow 0.5, which every IMU row since round 23 and every expert's training used). Stop 88's probes
# on validation's probe seeds found the backward walk played faster lost mostly to the suit's slow hinge errors and
# much of it recovered by the full corrections (docs/results.md, "Round 45"). Scored against the set as shipped (its
# slow corrections: the files EXPERTSET8 and EXPERTSET8_SQ, made here if missing) by bench/select_policy.py's rule on
# validation clean and the style-shifted draws 2170000+, confirmed on 2180000+ if it leads (the rules
# bench/results/round46_select_FULLSET_2170000.json and round46_select_FULLSET.json); each seed's two draw files are
# made side by side, one per core, and a file already made is kept, so a second call carries on. Nothing else is
# chosen on these draws. If it replaces the shipped preparation, its held-out rows are scored once, by hand.
set -eo pipefail
cd "$(dirname "$0")/../../.."
BASE=models/mimic_general_expert_set SQ=models/imu_denoiser_stances_quint_mirror SEED=2170000 CONFIRM=2180000
SHIPPED_CLEAN=EXPERTSET8 SHIPPED_SHIFTED=EXPERTSET8_SQ OUT=round46_select_FULLSET
LABEL=" (mirror-averaged) + denoiser's hinge corrections slowed to 0.5 s + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm"
[ -f bench/results/round24_val_clean_$SHIPPED_CLEAN.json ] ||
  bash bench/rounds/r24/clean_slow.sh "$SHIPPED_CLEAN" "$BASE" "$SQ" --even-legs --part-legs
[ -f bench/results/round24_val_clean_FULLSET.json ] ||
  DENOISE_SLOW= bash bench/rounds/r24/clean_slow.sh FULLSET "$BASE" "$SQ" --even-legs --part-legs
draws() {  # draws SEED: the shipped preparation's and FULLSET's draw files of SEED, side by side
  local base_job=
  [ -f "bench/results/round32_shifted_${1}_$SHIPPED_SHIFTED.json" ] ||
    { bash bench/rounds/r32/shifted.sh "$SHIPPED_SHIFTED" "$BASE" "$1" "$SQ" & base_job=$!; }
  [ -f "bench/results/round32_shifted_${1}_FULLSET_SQ.json" ] || DENOISE_SLOW= bash bench/rounds/r32/shifted.sh FULLSET_SQ "$BASE" "$1" "$SQ"
  [ -z "$base_job" ] || wait "$base_job"
}
rule() {  # rule OUT_FILE [--confirm FILES...]
  local out=$1; shift
  (cd bench && ../.venv/bin/python select_policy.py --baseline "$BASE$LABEL" \
    --clean "results/round24_val_clean_$SHIPPED_CLEAN.json" results/round24_val_clean_FULLSET.json \
    --draws "results/round32_shifted_${SEED}_$SHIPPED_SHIFTED.json" "results/round32_shifted_${SEED}_FULLSET_SQ.json" \
    --draws-per-policy 20 "$@" --json "results/$out")
}
draws "$SEED"
rule "${OUT}_$SEED.json"
bash bench/rounds/rule_says.sh "${OUT}_$SEED" leads_by_rule || exit 0
draws "$CONFIRM"
rule "$OUT.json" --confirm "results/round32_shifted_${CONFIRM}_$SHIPPED_SHIFTED.json" "results/round32_shifted_${CONFIRM}_FULLSET_SQ.json"
