#!/bin/bash
# Round 27: PC (the control) scored as registered: its last checkpoint against WW on validation IMU draws 1290000+.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r27
while pgrep -f "run-dir runs/r27/ppo_pc" > /dev/null; do sleep 10; done
W=$(ls runs/r27/ppo_pc/checkpoints/step_*.zip | sort -V | tail -1)
echo "PC: $W" > runs/r27/pc_candidate.txt
bash bench/rounds/r27/score.sh PC $W 1290000
