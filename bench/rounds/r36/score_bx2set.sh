#!/bin/bash
# Round 36, as registered: BX's run carried on (nice -n 10 bash bench/rounds/r35/bx_cmd.sh, from the committed
# models/mimic_general_back_wip/run, now models/mimic_general_back/run), its newest checkpoint at 20:30 UTC (BX2),
# made the backward policy of the set of that time, once score_fx2set.sh has finished: FX2SET if it replaced its baseline, otherwise BXSET if BXSET replaced
# FXSET, otherwise FXSET (models/mimic_general_fast_set). BX2SET scored against that set behind SQ on validation clean
# and the style-shifted draws 1790000+, confirmed on 1800000+ if it leads (bench/rounds/score_shifted.sh), and if it
# leads both, its held-out rows once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r36
bash bench/rounds/r28/candidate.sh runs/r35/ppo_bx 2030 BX2
while pgrep -f "bench/rounds/r36/score_(bx|fx2)set.sh" > /dev/null; do sleep 20; done  # the set of that time
if bash bench/rounds/replaced.sh round36_select_FX2SET; then
  BASE=runs/r36/FX2SET; CLEAN=FX2SET; SHIFTED=FX2SET_SQ
elif bash bench/rounds/replaced.sh round36_select_BXSET; then
  BASE=runs/r36/BXSET; CLEAN=BXSET; SHIFTED=BXSET_SQ
else
  BASE=models/mimic_general_fast_set; CLEAN=FXSET_SHIPPED; SHIFTED=FXSET_SQ
fi
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r36/BX2SET "backward=$(cat runs/r28/BX2_candidate.txt)"
echo runs/r36/BX2SET > runs/r28/BX2SET_candidate.txt
bash bench/rounds/score_then_hold_out.sh "$BASE" "$CLEAN" "$SHIFTED" BX2SET 1790000 1800000 round36_select_BX2SET
