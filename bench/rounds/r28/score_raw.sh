#!/bin/bash
# usage: bench/rounds/r28/score_raw.sh NAME POLICY SEED
# Scores a candidate POLICY against the shipped WW (models/mimic_general_wide) on raw IMU takes, as round 26 scored
# WW against WLE: validation raw IMU draws from SEED (40 x 2 rollouts per take; no denoiser, legs evened and
# parted, grounded, swing-lifted, mirror-averaged) for both, the candidate's raw validation clean, and the selection
# rule (bench/results/round28_select_raw_NAME_SEED.json). WW's raw validation clean is run again from the shipped
# directory, so that its label is the baseline's (round23_val_clean_WW.json ran its checkpoint in runs/r25).
set -eo pipefail
cd "$(dirname "$0")/../../.."
N=$1; P=$2; S=$3
WW=models/mimic_general_wide
of() { [ -f "$1" ] && grep -qF "\"$2 (mirror-averaged)" "$1"; }
(of bench/results/round23_draws_${S}_WW.json $WW && echo "WW's raw draws $S exist: reused" || bash bench/rounds/r23/score_any.sh WW $WW $S --even-legs --part-legs) &
BASELINE=$!
of bench/results/round23_draws_${S}_$N.json "$P" && echo "$N's raw draws $S exist: reused" || bash bench/rounds/r23/score_any.sh $N "$P" $S --even-legs --part-legs
of bench/results/round23_val_clean_$N.json "$P" && echo "$N's raw validation clean exists: reused" || bash bench/rounds/r23/clean_any.sh $N "$P" --even-legs --part-legs
wait $BASELINE  # its failure stops the scoring (set -e)
of bench/results/round23_val_clean_WW_shipped.json $WW || bash bench/rounds/r23/clean_any.sh WW_shipped $WW --even-legs --part-legs
cd bench && ../.venv/bin/python select_policy.py \
  --baseline "$WW (mirror-averaged) + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm" \
  --clean results/round23_val_clean_WW_shipped.json results/round23_val_clean_$N.json \
  --draws results/round23_draws_${S}_WW.json results/round23_draws_${S}_$N.json \
  --draws-per-policy 40 --json results/round28_select_raw_${N}_${S}.json
