#!/bin/bash
# Round 54, as registered (stop 94): TXR (bench/rounds/r54/txr_cmd.sh), its newest checkpoint at 15:40 UTC (candidate.sh
# stops the run with a checkpoint), made the turn member of the raw rows' choice (models/mimic_general_raw_set, whose
# turn member is TX, mimic_general_turning) in place of TX: TXRSET. Validation holds no turn, so as in rounds 37-38
# the rule reads DeepMimic's two training turns, here both sets tracking them raw with the raw rows' preparation
# (DENOISER= bench/rounds/score_turns.sh): TXRSET replaces the raw set if its ELR on them, IMU strength 1, 20
# rollouts each, is higher on both seeds 2390000 and 2400000. If it replaces it, its held-out raw rows once
# (bench/rounds/r30/heldout.sh TXRSET raw: seeds 1000-4000, the test split and the DeepMimic walkers).
# As run in stop 94: since then models/mimic_general_raw_set holds TXR itself, so a second run would score TXR against
# itself and overwrite the round's files; the files it wrote are committed.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r54
bash bench/rounds/r28/candidate.sh runs/r54/ppo_txr 1540 TXR
.venv/bin/python bench/rounds/derived_set.py models/mimic_general_raw_set runs/sets/TXRSET \
  "turn=$(cat runs/r28/TXR_candidate.txt)"
echo runs/sets/TXRSET > runs/r28/TXRSET_candidate.txt
DENOISER= bash bench/rounds/score_turns.sh 54 RAWSET11 models/mimic_general_raw_set TXRSET runs/sets/TXRSET \
  2390000 2400000
if bash bench/rounds/replaced.sh round54_select_TXRSET; then
  bash bench/rounds/r30/heldout.sh TXRSET raw
fi
