#!/bin/bash
# Round 30: SOUP (runs/r30/soup, the mean of PV's and PV10's weights by agents/average_policies.py) scored as
# registered: validation IMU draws 1460000+ behind the denoiser's slow corrections against PV10, then validation raw
# draws 1470000+ against PV (bench/rounds/r30/score.sh); runs/r28/SOUP_candidate.txt names it for the later scripts.
set -eo pipefail
cd "$(dirname "$0")/../../.."
[ -f runs/r30/soup/model.zip ] || .venv/bin/python agents/average_policies.py runs/r29/ppo_pv/checkpoints/step_3500000.zip \
  runs/r29/ppo_pv10/checkpoints/step_4002912.zip --out runs/r30/soup
echo runs/r30/soup > runs/r28/SOUP_candidate.txt
BASE=PV10 BASE_POLICY=runs/r29/ppo_pv10/checkpoints/step_4002912.zip bash bench/rounds/r30/score.sh slow SOUP runs/r30/soup 1460000
echo "scored 1460000+ at $(date -u +%H:%M:%S)"
bash bench/rounds/r30/score.sh raw SOUP runs/r30/soup 1470000
echo "scored raw 1470000+ at $(date -u +%H:%M:%S)"
