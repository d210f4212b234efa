#!/bin/bash
# Round 37, as registered (amended 22:59 UTC): TX's newest checkpoint at 23:40 UTC (bench/rounds/r37/tx_cmd.sh's run; candidate.sh stops
# it with a checkpoint), made the turn policy (0.3 rad/s) of the set of that time (DXSET if it replaced the shipped
# set, else models/mimic_general_expert_set). Validation holds no turn (bench/results/round37_route_turns_val.json:
# none of its takes turns faster than 0.017 rad/s, 0.021 at the 1.25x pace of the shifted draws), so TXSET performs it
# as its base does; the rule reads DeepMimic's two training turns instead: TXSET replaces its base if its ELR on them,
# IMU strength 1, 20 rollouts each, is higher on both seeds 1910000 and 1920000. If it replaces it, its held-out rows
# once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r37
export MUJOCO_GL=egl OMP_NUM_THREADS=1
bash bench/rounds/r28/candidate.sh runs/r37/ppo_tx 2340 TX
# DXSET's decision first: its rule, and its confirmation if it leads
while [ ! -f bench/results/round37_select_DXSET_1860000.json ]; do sleep 20; done
if bash bench/rounds/rule_says.sh round37_select_DXSET_1860000 leads_by_rule; then
  while [ ! -f bench/results/round37_select_DXSET.json ]; do sleep 20; done
fi
BASE=models/mimic_general_expert_set; BASE_NAME=EXPERTSET2
if bash bench/rounds/replaced.sh round37_select_DXSET; then BASE=runs/r37/DXSET; BASE_NAME=DXSET; fi
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r37/TXSET "turn=$(cat runs/r28/TX_candidate.txt)" \
  turn_rate_rad_s=0.3
echo runs/r37/TXSET > runs/r28/TXSET_candidate.txt
bash bench/rounds/score_turns.sh 37 "$BASE_NAME" "$BASE" TXSET runs/r37/TXSET 1910000 1920000
if bash bench/rounds/replaced.sh round37_select_TXSET; then
  DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh TXSET slow
fi
