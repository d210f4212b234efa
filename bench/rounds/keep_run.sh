#!/bin/bash
# usage: bench/rounds/keep_run.sh RUN_DIR DEST
# Stop the training run in RUN_DIR (train_ppo.py saves a checkpoint on SIGTERM) and keep its newest checkpoint, deflated,
# with the run's records in DEST under models/ (agents/ship.py copy_resumable_run), from which the round's command
# script carries it on on a machine without RUN_DIR. Used at the end of a stop, e.g.
#   bash bench/rounds/keep_run.sh runs/r31/ppo_lw models/mimic_general_long_window/lw_run   (round 31's LW)
#   bash bench/rounds/keep_run.sh runs/r32/ppo_ls models/mimic_general_style_shifts/ls_run  (round 32's LS)
set -eo pipefail
cd "$(dirname "$0")/../.."
R=$1; D=$2
[ -n "$R" ] && [ -n "$D" ] || { echo "keep_run.sh: usage: keep_run.sh RUN_DIR DEST" >&2; exit 2; }
RUN="--run-dir $R( |\$)"  # that run's train_ppo.py only, not a run dir that starts with the same name
pkill -TERM -f -- "$RUN" || true
while pgrep -f -- "$RUN" > /dev/null; do sleep 5; done
rm -rf "$D"
.venv/bin/python -c "import sys; from pathlib import Path; from agents.ship import copy_resumable_run
copy_resumable_run(Path(sys.argv[1]), Path(sys.argv[2]))" "$R" "$D"
ls -la "$D/checkpoints"
