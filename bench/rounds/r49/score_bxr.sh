#!/bin/bash
# usage: bench/rounds/r49/score_bxr.sh
# Round 49, as registered (stop 90): BXR (bench/rounds/r49/bxr_cmd.sh, resumed from step 716,512), its newest
# checkpoint at 20:00 UTC (bench/rounds/r28/candidate.sh stops the run with a checkpoint), made the backward member of
# the shipped set tracking IMU takes with no denoiser in front (the raw rows' choice since round 47, RAWSET):
# BXRSET (runs/sets/BXRSET, bench/rounds/derived_set.py). Both sides raw, with the raw rows' preparation
# (--mirror-average --even-legs --part-legs --ground --swing-lift), scored by bench/rounds/score_shifted.sh with
# DENOISER empty: validation clean (round23_val_clean_{RAWSET9,BXRSET}.json; the shipped directory's file is made
# anew, its policy_set.json having changed since round 47's RAWSET file) and validation's style-shifted draws
# 2260000+ (round32_shifted_2260000_{RAWSET9_RAW,BXRSET_RAW}.json), confirmed on 2270000+ if it leads (the rules
# bench/results/round49_select_BXRSET_2260000.json and round49_select_BXRSET.json). The shipped set's files are made
# while BXR trains. The candidate's three files are then made side by side on the two cores (score_shifted.sh makes
# one side's files one after another): its confirmation draws are made whether or not it leads and read only if it
# does. Nothing else is chosen on these draws. If it leads both, its held-out rows are scored once, by hand:
# bash bench/rounds/r30/heldout.sh BXRSET raw.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/sets
BASE=models/mimic_general_expert_set
SEED=2260000 CONFIRM=2270000 OUT=round49_select_BXRSET
export DENOISER=
bash bench/rounds/r28/candidate.sh runs/r49/ppo_bxr 2000 BXR &
CANDIDATE_JOB=$!
bash bench/rounds/score_shifted.sh --base-only "$BASE" RAWSET9 RAWSET9_RAW BXRSET "$SEED" "$CONFIRM" "$OUT" &
BASE_JOB=$!
wait $CANDIDATE_JOB
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/sets/BXRSET "backward=$(cat runs/r28/BXR_candidate.txt)"
bash bench/rounds/r23/clean_any.sh BXRSET runs/sets/BXRSET --even-legs --part-legs &
CLEAN_JOB=$!
bash bench/rounds/r32/shifted.sh BXRSET_RAW runs/sets/BXRSET "$CONFIRM" "" &
CONFIRM_JOB=$!
bash bench/rounds/r32/shifted.sh BXRSET_RAW runs/sets/BXRSET "$SEED" ""
wait $CLEAN_JOB
wait $CONFIRM_JOB
wait $BASE_JOB
echo runs/sets/BXRSET > runs/r28/BXRSET_candidate.txt
exec bash bench/rounds/score_shifted.sh "$BASE" RAWSET9 RAWSET9_RAW BXRSET "$SEED" "$CONFIRM" "$OUT"
