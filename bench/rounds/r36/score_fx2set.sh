#!/bin/bash
# Round 36, as registered: FX's run carried on (bench/rounds/r36/fx2_cmd.sh), its newest checkpoint at 20:15 UTC
# (FX2), made the fast policy of the set of that time: BXSET if round 36's BXSET replaced FXSET
# (bench/results/round36_select_BXSET.json's replaces_baseline), otherwise FXSET (models/mimic_general_fast_set).
# FX2SET scored against that set behind SQ on validation clean and the style-shifted draws 1770000+, confirmed on
# 1780000+ if it leads (bench/rounds/score_shifted.sh), and if it leads both, its held-out rows once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r36
bash bench/rounds/r28/candidate.sh runs/r35/ppo_fx 2015 FX2
while pgrep -f "bench/rounds/r36/score_bxset.sh" > /dev/null; do sleep 20; done  # the set of that time
if bash bench/rounds/replaced.sh round36_select_BXSET; then
  BASE=runs/r36/BXSET; CLEAN=BXSET; SHIFTED=BXSET_SQ
else
  BASE=models/mimic_general_fast_set; CLEAN=FXSET_SHIPPED; SHIFTED=FXSET_SQ  # score_bxset.sh's files of the shipped set
fi
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r36/FX2SET "fast=$(cat runs/r28/FX2_candidate.txt)"
echo runs/r36/FX2SET > runs/r28/FX2SET_candidate.txt
bash bench/rounds/score_then_hold_out.sh "$BASE" "$CLEAN" "$SHIFTED" FX2SET 1770000 1780000 round36_select_FX2SET
