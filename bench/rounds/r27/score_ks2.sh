#!/bin/bash
# Round 27: KS2 scored as registered: its newest checkpoint at 18:25 UTC is the candidate; the run is stopped with a
# checkpoint (resumable); validation IMU draws 1290000+ against WW's (bench/rounds/r27/score.sh), then its training
# and taught takes (bench/rounds/r27/train_takes.sh).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r27
while pgrep -f "run-dir runs/r27/ppo_ks2" > /dev/null && [ "$(date -u +%H%M)" -lt 1825 ]; do sleep 20; done
W=$(ls runs/r27/ppo_ks2/checkpoints/step_*.zip | sort -V | tail -1)
echo "KS2 candidate: $W at $(date -u +%H:%M:%S)" > runs/r27/ks2_candidate.txt
pkill -TERM -f "run-dir runs/r27/ppo_ks2"
while pgrep -f "run-dir runs/r27/ppo_ks2" > /dev/null; do sleep 5; done
bash bench/rounds/r27/score.sh KS2 $W 1290000
echo "scored 1290000+ at $(date -u +%H:%M:%S)" >> runs/r27/ks2_candidate.txt
bash bench/rounds/r27/train_takes.sh KS2 $W
echo "training takes at $(date -u +%H:%M:%S)" >> runs/r27/ks2_candidate.txt
