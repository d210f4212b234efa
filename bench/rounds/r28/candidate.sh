#!/bin/bash
# usage: bench/rounds/r28/candidate.sh RUN_DIR HHMM NAME
# A registered candidate of a training run: its newest checkpoint at HHMM UTC (or its last, if the run
# ends first; a run not yet up is given 2 minutes to appear, so one started just before is not taken for ended). The
# run is then stopped with a checkpoint (resumable: train_ppo.py --run-dir RUN_DIR --resume), and the checkpoint's
# path is written to runs/r28/NAME_candidate.txt, which the round's scoring reads.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28
R=$1; T=$2; N=$3
[[ $T =~ ^[0-2][0-9][0-5][0-9]$ ]] || { echo "candidate.sh: HHMM expected, got '$T'" >&2; exit 2; }
RUN="--run-dir $R( |\$)"  # that run's train_ppo.py only, not a run dir that starts with the same name
for _ in $(seq 24); do pgrep -f -- "$RUN" > /dev/null && break; sleep 5; done  # a run started just before: up yet
# HHMM's time within 12 hours of now, either way (one just past is taken at once), so that a time registered
# before midnight for after it is waited for
NOW=$(date -u +%s); UNTIL=$(date -u -d "$(date -u +%F) ${T:0:2}:${T:2:2}" +%s)
(( UNTIL >= NOW - 43200 )) || UNTIL=$((UNTIL + 86400))
(( UNTIL <= NOW + 43200 )) || UNTIL=$((UNTIL - 86400))
while pgrep -f -- "$RUN" > /dev/null && [ "$(date -u +%s)" -lt "$UNTIL" ]; do sleep 20; done
W=$(ls "$R"/checkpoints/step_*.zip | sort -V | tail -1)
[ -n "$W" ] || { echo "candidate.sh: no checkpoint in $R/checkpoints" >&2; exit 1; }
pkill -TERM -f -- "$RUN" || true
while pgrep -f -- "$RUN" > /dev/null; do sleep 5; done
echo "$W" > "runs/r28/${N}_candidate.txt"
echo "$N candidate: $W at $(date -u +%H:%M:%S)"
