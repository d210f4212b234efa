#!/bin/bash
# usage: bench/rounds/r48/score_fsd.sh
# Round 48, FSDSET: the shipped policy set (models/mimic_general_expert_set) behind SQ's full corrections, as shipped
# since round 46, but with its dash member tracking its takes behind the slow corrections (0.5 s) it was trained
# behind (policy_set.json "denoise_slow_s": {"dash": 0.5}; runs/sets/FSDSET, bench/rounds/derived_set.py). Validation's
# round-46 draws had the dash played faster lose under the full corrections on both seeds (0.918 -> 0.847 and
# 0.880 -> 0.757) while every other take gained or held. The shipped directory has held FSDSET's field since this
# round, so the baseline is runs/sets/FULLSET (bench/rounds/r46/score_full.sh makes it: the shipped set without
# it) and FSDSET is derived from that. Scored against the shipped set of the time (files FULLSET, FULLSET_SQ)
# by bench/rounds/score_shifted.sh, both sides behind the full corrections, on validation clean and the style-shifted
# draws 2210000+, confirmed on 2220000+ if it leads (the rules bench/results/round48_select_FSDSET_2210000.json and
# round48_select_FSDSET.json). Nothing else is chosen on these draws. If it replaces the shipped set, its held-out
# rows are scored once, by hand: DENOISE_SLOW= DENOISER=models/imu_denoiser_stances_quint_mirror
# bash bench/rounds/r30/heldout.sh FSDSET slow.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/sets
BASE=runs/sets/FULLSET
.venv/bin/python bench/rounds/derived_set.py models/mimic_general_expert_set "$BASE" denoise_slow_s=
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/sets/FSDSET denoise_slow_s=dash:0.5
echo runs/sets/FSDSET > runs/r28/FSDSET_candidate.txt
BASE_DENOISE_SLOW= CANDIDATE_DENOISE_SLOW= exec bash bench/rounds/score_shifted.sh "$BASE" FULLSET FULLSET_SQ FSDSET \
  2210000 2220000 round48_select_FSDSET
