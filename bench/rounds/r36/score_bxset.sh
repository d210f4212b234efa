#!/bin/bash
# Round 36, as registered in round 35: BX (the backward expert, its committed candidate step_1441120) made the
# backward policy of FXSET, the set of that time (models/mimic_general_fast_set: LSS by default, FX above 2.0 m/s);
# BXSET scored against FXSET behind SQ on validation clean and the style-shifted draws 1750000+, confirmed on
# 1760000+ if it leads (bench/rounds/score_shifted.sh), and if it leads both, its held-out rows once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r36
# BX as shipped (round 36): the actor of step_1441120, which the round scored from the committed checkpoint
# models/mimic_general_back_wip/run/checkpoints/step_1441120.zip (since removed); the same per take on validation clean
BX=models/mimic_general_back
BASE=models/mimic_general_fast_set
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r36/BXSET "backward=$BX"
echo runs/r36/BXSET > runs/r28/BXSET_candidate.txt
# FXSET's validation clean file is made anew for the shipped set (round 35's, round24_val_clean_FXSET.json, names the set
# by its path then, runs/r35/FXSET, and the rule matches the files' policies by name)
bash bench/rounds/score_then_hold_out.sh "$BASE" FXSET_SHIPPED FXSET_SQ BXSET 1750000 1760000 round36_select_BXSET
