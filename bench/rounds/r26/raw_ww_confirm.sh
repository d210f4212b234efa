#!/bin/bash
# Round 26: WW led the raw rule on 1220000+, so its registered confirmation draws 1230000+ against WLE, then
# (if the rule with them says it replaces WLE) the raw held-out rows once: bench/rounds/r23/heldout.sh WW W --even-legs.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r23
W=runs/r25/ppo_wide/checkpoints/step_4005120.zip
bash bench/rounds/r23/score_any.sh WW $W 1230000 --even-legs --part-legs &
bash bench/rounds/r23/score_any.sh WLE models/mimic_general_legs 1230000 --even-legs --part-legs
wait
# It did (confirmation +0.022 ± 0.006, bench/results/round26_select_raw_WW.json): the raw held-out rows once.
bash bench/rounds/r23/heldout.sh WW $W --even-legs
