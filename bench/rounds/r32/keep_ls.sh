#!/bin/bash
# Round 32, end of stop 75: stop LS's carried-on run (train_ppo.py saves a checkpoint on SIGTERM) and keep its newest
# checkpoint, deflated, with the run's records in models/mimic_general_style_shifts/ls_run/ (the shipped actor and its
# run/ stay at step 500,000), from which a later stop carries it on:
#   bash bench/rounds/r32/ls_cmd.sh (it copies ls_run/ to runs/r32/ppo_ls when that is missing)
set -eo pipefail
cd "$(dirname "$0")/../../.."
RUN="--run-dir runs/r32/ppo_ls( |\$)"
pkill -TERM -f -- "$RUN" || true
while pgrep -f -- "$RUN" > /dev/null; do sleep 5; done
rm -rf models/mimic_general_style_shifts/ls_run
.venv/bin/python -c "from pathlib import Path; from agents.ship import copy_resumable_run
copy_resumable_run(Path('runs/r32/ppo_ls'), Path('models/mimic_general_style_shifts/ls_run'))"
ls -la models/mimic_general_style_shifts/ls_run/checkpoints
