#!/bin/bash
# usage: bench/rounds/score_then_hold_out.sh BASE CLEAN_NAME SHIFTED_NAME CANDIDATE SEED CONFIRM_SEED OUT
# A registered candidate scored against its baseline (bench/rounds/score_shifted.sh, the same arguments) and, if it
# replaces the baseline (bench/results/OUT.json's replaces_baseline), its held-out rows behind SQ, once
# (bench/rounds/r30/heldout.sh CANDIDATE slow).
set -eo pipefail
cd "$(dirname "$0")/../.."
bash bench/rounds/score_shifted.sh "$@"
if .venv/bin/python -c "import json, sys; sys.exit(not json.load(open(sys.argv[1]))['replaces_baseline'])" \
    "bench/results/$7.json" 2> /dev/null; then
  DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh "$4" slow
fi
