#!/bin/bash
# usage: bench/rounds/r28/candidate.sh RUN_DIR HHMM NAME
# A registered candidate of a training run: its newest checkpoint at HHMM UTC (or its last, if the run ends first).
# The run is then stopped with a checkpoint (resumable: train_ppo.py --run-dir RUN_DIR --resume), and the
# checkpoint's path is written to runs/r28/NAME_candidate.txt, which the round's scoring reads.
set -e
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28
R=$1; T=$2; N=$3
while pgrep -f "run-dir $R" > /dev/null && [ "$(date -u +%H%M)" -lt "$T" ]; do sleep 20; done
W=$(ls "$R"/checkpoints/step_*.zip | sort -V | tail -1)
pkill -TERM -f "run-dir $R" || true
while pgrep -f "run-dir $R" > /dev/null; do sleep 5; done
echo "$W" > runs/r28/${N}_candidate.txt
echo "$N candidate: $W at $(date -u +%H:%M:%S)"
