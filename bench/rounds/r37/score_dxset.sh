#!/bin/bash
# Round 37, as registered: DX's newest checkpoint at 23:40 UTC (bench/rounds/r37/dx_cmd.sh's run; candidate.sh stops
# it with a checkpoint), made the dash policy (3.0 m/s) of the shipped set (models/mimic_general_expert_set, SXSET);
# DXSET scored against it behind SQ on validation clean and the style-shifted draws 1860000+, confirmed on 1870000+ if
# it leads (bench/rounds/score_shifted.sh), and if it leads both, its held-out rows once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r37
BASE=models/mimic_general_expert_set
bash bench/rounds/score_shifted.sh --base-only "$BASE" EXPERTSET2 EXPERTSET2_SQ DXSET 1860000 1870000 round37_select_DXSET
bash bench/rounds/r28/candidate.sh runs/r37/ppo_dx 2340 DX
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r37/DXSET "dash=$(cat runs/r28/DX_candidate.txt)" \
  dash_speed_mps=3.0
echo runs/r37/DXSET > runs/r28/DXSET_candidate.txt
bash bench/rounds/score_then_hold_out.sh "$BASE" EXPERTSET2 EXPERTSET2_SQ DXSET 1860000 1870000 round37_select_DXSET
