#!/bin/bash
# usage: bench/rounds/score_then_hold_out.sh BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED CONFIRM_SEED OUT
# A registered candidate scored against its baseline (bench/rounds/score_shifted.sh, the same arguments) and, if it
# replaces the baseline (bench/results/OUT.json's replaces_baseline), its held-out rows behind SQ, once
# (bench/rounds/r30/heldout.sh CANDIDATE slow).
set -eo pipefail
cd "$(dirname "$0")/../.."
bash bench/rounds/score_shifted.sh "$@"
if bash bench/rounds/replaced.sh "$7"; then
  DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh "$4" slow
fi
