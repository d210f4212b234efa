#!/bin/bash
# Round 31, end of stop 74: stop LW's run (train_ppo.py saves a checkpoint on SIGTERM) and keep its newest checkpoint,
# deflated, with the run's records in models/mimic_general_long_window/lw_run/, from which bench/rounds/r31/lw_cmd.sh
# carries it on on a machine without runs/r31/ppo_lw.
set -eo pipefail
cd "$(dirname "$0")/../../.."
RUN="--run-dir runs/r31/ppo_lw( |\$)"
pkill -TERM -f -- "$RUN" || true
while pgrep -f -- "$RUN" > /dev/null; do sleep 5; done
rm -rf models/mimic_general_long_window/lw_run
.venv/bin/python -c "from pathlib import Path; from agents.ship import copy_resumable_run
copy_resumable_run(Path('runs/r31/ppo_lw'), Path('models/mimic_general_long_window/lw_run'))"
ls -la models/mimic_general_long_window/lw_run/checkpoints
