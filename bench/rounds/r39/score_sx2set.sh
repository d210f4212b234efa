#!/bin/bash
# Round 39, as registered: SX carried on (bench/rounds/r36/sx_cmd.sh's run from step 1,887,200), its newest checkpoint
# at 05:20 UTC (candidate.sh stops the run with a checkpoint), made the sideways policy of the shipped set
# (models/mimic_general_expert_set, TX2SET) in place of round 36's step_1500000: SX2SET. Scored against the shipped
# set behind SQ on validation clean and the style-shifted draws 1970000+, confirmed on 1980000+ if it leads
# (bench/rounds/score_shifted.sh), and if it leads both, its held-out rows once. The shipped set's files are made anew
# under EXPERTSET4 (they do not depend on the candidate: made while the run trains).
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r39
BASE=models/mimic_general_expert_set
bash bench/rounds/r28/candidate.sh runs/r36/ppo_sx 0520 SX2 &
CANDIDATE_JOB=$!
bash bench/rounds/score_shifted.sh --base-only "$BASE" EXPERTSET4 EXPERTSET4_SQ SX2SET 1970000 1980000 round39_select_SX2SET
wait $CANDIDATE_JOB
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r39/SX2SET "sideways=$(cat runs/r28/SX2_candidate.txt)"
echo runs/r39/SX2SET > runs/r28/SX2SET_candidate.txt
bash bench/rounds/score_then_hold_out.sh "$BASE" EXPERTSET4 EXPERTSET4_SQ SX2SET 1970000 1980000 round39_select_SX2SET
