#!/bin/bash
# usage: bench/rounds/r30/score.sh ROW NAME POLICY SEED   (ROW: slow or raw)
# Round 30: scores a candidate POLICY against PV, shipped since round 29 as models/mimic_general_asymmetric and scored
# through its checkpoint runs/r29/ppo_pv/checkpoints/step_3500000.zip (the label of its validation clean files), as
# bench/rounds/r27/score.sh (slow: behind the quint denoiser's slow corrections) and bench/rounds/r28/score_raw.sh
# (raw) scored against WW: validation IMU draws from SEED (40 x 2 rollouts per take) for both, the candidate's
# validation clean, then the selection rule (bench/results/round30_select_ROW_NAME_SEED.json). BASE=NAME and
# BASE_POLICY=CHECKPOINT score against another baseline whose validation clean files exist under NAME (default PV).
set -eo pipefail
cd "$(dirname "$0")/../../.."
ROW=$1; N=$2; P=$3; S=$4
B=${BASE:-PV}; BP=${BASE_POLICY:-runs/r29/ppo_pv/checkpoints/step_3500000.zip}
FLAGS="--even-legs --part-legs"
QT=models/imu_denoiser_soles_quint_mirror
case $ROW in
  slow) R=round24; DRAWS="bench/rounds/r24/score_slow.sh"; CLEAN="bench/rounds/r24/clean_slow.sh"; EXTRA="$QT"
        LABEL=" (mirror-averaged) + denoiser's hinge corrections slowed to 0.5 s + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm" ;;
  raw)  R=round23; DRAWS="bench/rounds/r23/score_any.sh"; CLEAN="bench/rounds/r23/clean_any.sh"; EXTRA=""
        LABEL=" (mirror-averaged) + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm" ;;
  *) echo "score.sh: ROW is slow or raw, got '$ROW'" >&2; exit 2 ;;
esac
# a result file is reused only if it is of this policy (a NAME of an earlier round may name another checkpoint)
of() { [ -f "$1" ] && grep -qF "\"$2 (mirror-averaged)" "$1"; }
(of bench/results/${R}_draws_${S}_$B.json $BP && echo "$B's draws $S exist: reused" || bash $DRAWS $B $BP $S $EXTRA $FLAGS) &
BASELINE=$!
of bench/results/${R}_draws_${S}_$N.json "$P" && echo "$N's draws $S exist: reused" || bash $DRAWS $N "$P" $S $EXTRA $FLAGS
of bench/results/${R}_val_clean_$N.json "$P" && echo "$N's validation clean exists: reused" || bash $CLEAN $N "$P" $EXTRA $FLAGS
wait $BASELINE  # its failure stops the scoring (set -e)
cd bench && ../.venv/bin/python select_policy.py --baseline "$BP$LABEL" \
  --clean results/${R}_val_clean_$B.json results/${R}_val_clean_$N.json \
  --draws results/${R}_draws_${S}_$B.json results/${R}_draws_${S}_$N.json \
  --draws-per-policy 40 --json results/round30_select_${ROW}_${N}_${S}.json
