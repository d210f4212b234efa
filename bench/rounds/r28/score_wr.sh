#!/bin/bash
# Round 28: WR scored as registered: its newest checkpoint at 21:45 UTC is the candidate (bench/rounds/r28/candidate.sh
# stops the run, resumable), scored against WW on validation's raw IMU draws 1360000+ (bench/rounds/r28/score_raw.sh).
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28
bash bench/rounds/r28/candidate.sh runs/r28/ppo_wr 2145 WR
W=$(cat runs/r28/WR_candidate.txt)
[ -n "$W" ] || { echo "score_wr.sh: no candidate" >&2; exit 1; }
bash bench/rounds/r28/score_raw.sh WR "$W" 1360000
echo "scored raw 1360000+ at $(date -u +%H:%M:%S)"
