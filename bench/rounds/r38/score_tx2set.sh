#!/bin/bash
# Round 38, as registered: TX carried on (bench/rounds/r37/tx_cmd.sh's run from step 491,520), its newest checkpoint
# at 02:45 UTC (candidate.sh stops the run with a checkpoint), made the turn policy of the shipped set
# (models/mimic_general_expert_set, TXSET) in place of round 37's step_400000: TX2SET. Validation holds no turn, so
# as in round 37 the rule reads DeepMimic's two training turns: TX2SET replaces the shipped set if its ELR on them, IMU
# strength 1, 20 rollouts each, is higher on both seeds 1940000 and 1950000 (bench/rounds/score_turns.sh). If it
# replaces it, its held-out rows once (seeds 1000-4000, the test split and the DeepMimic walkers).
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r38
bash bench/rounds/r28/candidate.sh runs/r37/ppo_tx 0245 TX2
.venv/bin/python bench/rounds/derived_set.py models/mimic_general_expert_set runs/r38/TX2SET \
  "turn=$(cat runs/r28/TX2_candidate.txt)"
echo runs/r38/TX2SET > runs/r28/TX2SET_candidate.txt
bash bench/rounds/score_turns.sh 38 EXPERTSET3 models/mimic_general_expert_set TX2SET runs/r38/TX2SET 1940000 1950000
if bash bench/rounds/replaced.sh round38_select_TX2SET; then
  DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh TX2SET slow
fi
