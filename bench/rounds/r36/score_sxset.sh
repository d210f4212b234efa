#!/bin/bash
# Round 36, as registered (amended 20:40 UTC): SX's newest checkpoint at 21:00 UTC (bench/rounds/r36/sx_cmd.sh's run;
# candidate.sh stops it with a checkpoint), made the sideways policy (0.2 m/s) of the set of that time, BXSET as
# shipped (models/mimic_general_expert_set); SXSET scored against it behind SQ on validation clean and the
# style-shifted draws 1810000+, confirmed on 1820000+ if it leads (bench/rounds/score_shifted.sh), and if it leads
# both, its held-out rows once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r36
BASE=models/mimic_general_expert_set
bash bench/rounds/score_shifted.sh --base-only "$BASE" EXPERTSET EXPERTSET_SQ SXSET 1810000 1820000 round36_select_SXSET
bash bench/rounds/r28/candidate.sh runs/r36/ppo_sx 2100 SX
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r36/SXSET "sideways=$(cat runs/r28/SX_candidate.txt)" \
  sideways_speed_mps=0.2
echo runs/r36/SXSET > runs/r28/SXSET_candidate.txt
bash bench/rounds/score_then_hold_out.sh "$BASE" EXPERTSET EXPERTSET_SQ SXSET 1810000 1820000 round36_select_SXSET
