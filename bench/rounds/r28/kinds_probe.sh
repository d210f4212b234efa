#!/bin/bash
# usage: bench/rounds/r28/kinds_probe.sh SEED [--denoise ...]   (WW; NAME=X POLICY=P before it for another policy)
# Round 28: which IMU artefact kinds still cost WW (models/mimic_general_wide, with the raw rows' preparation)
# on the ten takes of the library's train split (bench/rounds/r28/takes.txt; CMU's 02_09 among them, which WW's
# training excluded) it performs clean but loses under the suit (round 26's diagnostics, seed 1140000: clean ELR
# 0.92-1.00, IMU 0.34-0.89). Every kind at strength 1, and every kind but one, the others keeping
# their random numbers (evaluate.py --without); 4 rollouts per take. Writes
# bench/results/round28_kinds_NAME_{all,no_KIND}_SEED[_dn].json.
set -e
cd "$(dirname "$0")/../../.."
S=$1; shift
P=${POLICY:-models/mimic_general_wide}; M=${NAME:-WW}
SUF=""; [ "$#" -gt 0 ] && SUF=_dn
TAKES=$(sed 's/^/library:data\/library#/' bench/rounds/r28/takes.txt)
run() {  # [--without KIND]; the condition's name in C
  MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/evaluate.py --policy $P \
    --mirror-average --even-legs --part-legs --ground --swing-lift "$@" --clips $TAKES --episodes 4 \
    --corrupt imu --strength 1 --seed $S --json bench/results/round28_kinds_${M}_${C}_$S$SUF.json > /dev/null
}
KINDS="adduction skate drift noise height heading bias jitter root_drift"
i=0
for K in all $KINDS; do
  if [ $K = all ]; then C=all; (run "$@") & else C=no_$K; (run "$@" --without $K) & fi
  PIDS="$PIDS $!"; i=$((i+1))
  if [ $((i % 2)) = 0 ]; then for p in $PIDS; do wait $p; done; PIDS=""; fi  # a failed evaluation stops the probe
done
for p in $PIDS; do wait $p; done
