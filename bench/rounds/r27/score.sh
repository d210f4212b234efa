#!/bin/bash
# usage: bench/rounds/r27/score.sh NAME POLICY SEED
# Scores a candidate POLICY against the shipped WW (models/mimic_general_wide) as rounds 24-26 did: validation IMU
# draws from SEED (40 x 2 rollouts per take) for both, behind the quint denoiser's slow corrections with the legs
# evened and parted, plus the candidate's validation clean; then the selection rule
# (bench/results/round27_select_NAME_SEED.json). WW's validation clean is bench/results/round24_val_clean_WW_shipped.json.
set -e
cd "$(dirname "$0")/../../.."
N=$1; P=$2; S=$3
QT=models/imu_denoiser_soles_quint_mirror
FLAGS="--even-legs --part-legs"
WW=models/mimic_general_wide
# a result file is reused only if it is of this policy (a NAME of an earlier round may name another checkpoint)
of() { [ -f "$1" ] && grep -qF "\"$2 (mirror-averaged)" "$1"; }
of bench/results/round24_draws_${S}_WW.json $WW && echo "WW's draws $S exist: reused" || bash bench/rounds/r24/score_slow.sh WW $WW $S $QT $FLAGS &
of bench/results/round24_draws_${S}_$N.json $P && echo "$N's draws $S exist: reused" || bash bench/rounds/r24/score_slow.sh $N $P $S $QT $FLAGS
of bench/results/round24_val_clean_$N.json $P && echo "$N's validation clean exists: reused" || bash bench/rounds/r24/clean_slow.sh $N $P $QT $FLAGS
wait
cd bench && ../.venv/bin/python select_policy.py \
  --baseline "$WW (mirror-averaged) + denoiser's hinge corrections slowed to 0.5 s + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm" \
  --clean results/round24_val_clean_WW_shipped.json results/round24_val_clean_$N.json \
  --draws results/round24_draws_${S}_WW.json results/round24_draws_${S}_$N.json \
  --draws-per-policy 40 --json results/round27_select_${N}_${S}.json
