#!/bin/bash
# usage: bench/rounds/score_member.sh RUN_DIR HHMM NAME ROLE SEED CONFIRM_SEED OUT
# A registered candidate member of the shipped policy set: RUN_DIR's newest checkpoint at HHMM UTC (bench/rounds/r28/
# candidate.sh, which then stops the run with a checkpoint) made the set's ROLE policy (default, backward, dash, fast,
# sideways or turn) in place of the shipped one: NAMESET (runs/sets/NAMESET/policy_set.json, bench/rounds/derived_set.py).
# Scored against the shipped set (models/mimic_general_expert_set) on validation clean (the shipped set's file
# EXPERTSET9) and style-shifted draws SEED+, confirmed on CONFIRM_SEED+ if it leads (bench/rounds/score_shifted.sh: the
# rules bench/results/OUT_SEED.json and OUT.json), both sides behind SQ's full corrections, the shipped preparation
# since round 46 (SHIPPED_DENOISE_SLOW, empty; score_shifted.sh's BASE_ and CANDIDATE_DENOISE_SLOW; since round 48
# the shipped set's policy_set.json slows its dash member's corrections itself, and a set derived from it keeps that
# unless ROLE is dash: derived_set.py drops a replaced role's slowing, so a new dash member tracks behind the full ones).
# The shipped set's files of both seeds (EXPERTSET9, EXPERTSET9_SQ) are made while the run trains, if missing. If it
# leads both, its held-out rows are scored once, by hand:
# DENOISE_SLOW= DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh NAMESET slow.
# The shipped set's file names (SHIPPED_CLEAN, SHIPPED_SHIFTED) are for FSDSET as shipped since round 48 (its round's
# own files are named after runs/sets/FSDSET, so the shipped directory's are made anew; FULLSET and FULLSET_SQ were the
# set's in round 46's preparation, EXPERTSET8 and EXPERTSET8_SQ DXSSET's behind the slow corrections, EXPERTSET7 and
# EXPERTSET7_SQ FXSSET's, EXPERTSET6 and EXPERTSET6_SQ BXS2RSET's, EXPERTSET4 and EXPERTSET5_SQ TX2SET's): once
# another set or preparation replaces it, they need new names here (score_shifted.sh keeps a file of the same name).
# With DENOISER set empty (DENOISER= bash bench/rounds/score_member.sh ...), the raw rows' member instead: the raw
# rows' choice models/mimic_general_raw_set (since round 49; its dash member DXR since round 51, its turn member TXR
# since round 54, its fast member FXR since round 55) is the base and baseline, both sides scored with no denoiser
# in front (score_shifted.sh's raw scoring; its files RAWSET13 and RAWSET13_RAW, made anew for the set with FXR;
# RAWSET12 and RAWSET12_RAW were the set's with TXR and FXS, round 55; RAWSET11 and RAWSET11_RAW were the set
# with TX, named after runs/sets/DXRSET in round 51; RAWSET10 and RAWSET10_RAW the set's with BXR and the
# denoiser-trained dash expert, rounds 50-52), and the held-out rows, if it leads both:
# bash bench/rounds/r30/heldout.sh NAMESET raw.
set -eo pipefail
[ $# = 7 ] || { echo "score_member.sh: usage: score_member.sh RUN_DIR HHMM NAME ROLE SEED CONFIRM_SEED OUT" >&2; exit 2; }
RUN=$1; HHMM=$2; NAME=$3; ROLE=$4; SEED=$5; CONFIRM=$6; OUT=$7
case $ROLE in default|backward|dash|fast|sideways|turn) ;;
  *) echo "score_member.sh: ROLE is one of default, backward, dash, fast, sideways, turn; got '$ROLE'" >&2; exit 2;; esac
[[ $HHMM =~ ^[0-2][0-9][0-5][0-9]$ ]] || { echo "score_member.sh: HHMM expected, got '$HHMM'" >&2; exit 2; }
cd "$(dirname "$0")/../.." && mkdir -p runs/r28 runs/sets
BASE=models/mimic_general_expert_set
SHIPPED_CLEAN=EXPERTSET9 SHIPPED_SHIFTED=EXPERTSET9_SQ SHIPPED_DENOISE_SLOW=
if [ -n "${DENOISER+set}" ] && [ -z "$DENOISER" ]; then  # the raw rows: both sides with no denoiser in front
  BASE=models/mimic_general_raw_set SHIPPED_CLEAN=RAWSET13 SHIPPED_SHIFTED=RAWSET13_RAW
fi
export BASE_DENOISE_SLOW=$SHIPPED_DENOISE_SLOW CANDIDATE_DENOISE_SLOW=$SHIPPED_DENOISE_SLOW
bash bench/rounds/r28/candidate.sh "$RUN" "$HHMM" "$NAME" &
CANDIDATE_JOB=$!
bash bench/rounds/score_shifted.sh --base-only "$BASE" "$SHIPPED_CLEAN" "$SHIPPED_SHIFTED" "${NAME}SET" "$SEED" "$CONFIRM" "$OUT"
wait $CANDIDATE_JOB
.venv/bin/python bench/rounds/derived_set.py "$BASE" "runs/sets/${NAME}SET" "$ROLE=$(cat "runs/r28/${NAME}_candidate.txt")"
echo "runs/sets/${NAME}SET" > "runs/r28/${NAME}SET_candidate.txt"
bash bench/rounds/score_shifted.sh "$BASE" "$SHIPPED_CLEAN" "$SHIPPED_SHIFTED" "${NAME}SET" "$SEED" "$CONFIRM" "$OUT"
