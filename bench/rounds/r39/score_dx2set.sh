#!/bin/bash
# Round 39, as registered: DX carried on (bench/rounds/r37/dx_cmd.sh's run from step 667,200), its newest checkpoint at
# 06:12 UTC (candidate.sh stops the run with a checkpoint), made the dash policy of the shipped set
# (models/mimic_general_expert_set, TX2SET) in place of round 37's step_600000: DX2SET. Scored against the shipped set
# behind SQ on validation clean (the shipped set's file EXPERTSET4, made this round) and fresh style-shifted draws
# 1990000+, confirmed on 2010000+ if it leads (bench/rounds/score_shifted.sh). Its held-out rows, if it leads both, are
# scored once by hand (bench/rounds/r30/heldout.sh DX2SET slow), this stop or the next.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r39
BASE=models/mimic_general_expert_set
bash bench/rounds/r28/candidate.sh runs/r37/ppo_dx 0612 DX2 &
CANDIDATE_JOB=$!
bash bench/rounds/score_shifted.sh --base-only "$BASE" EXPERTSET4 EXPERTSET5_SQ DX2SET 1990000 1990000 round39_select_DX2SET
wait $CANDIDATE_JOB
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r39/DX2SET "dash=$(cat runs/r28/DX2_candidate.txt)"
echo runs/r39/DX2SET > runs/r28/DX2SET_candidate.txt
bash bench/rounds/score_shifted.sh "$BASE" EXPERTSET4 EXPERTSET5_SQ DX2SET 1990000 2010000 round39_select_DX2SET
