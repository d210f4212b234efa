#!/bin/bash
# usage: bench/rounds/r34/den_fast_seed.sh SEED (1-4)
# Round 34, QF5: SQ's member SEED retrained with its own command (bench/rounds/r24/den_stances_cmd.sh with --seed SEED;
# member 1 also --patience 20, as it was trained) plus --speeds 0.8 1 1.25, as round 33's F retrained member 0
# (bench/rounds/r33/den_fast_cmd.sh). Resumable (train-denoiser --run-dir).
set -eo pipefail
SEED=$1
case "$SEED" in 1) EXTRA="--patience 20" ;; 2|3|4) EXTRA="" ;; *) echo "den_fast_seed.sh: SEED must be 1-4" >&2; exit 2 ;; esac
cd "$(dirname "$0")/../../.." && mkdir -p runs/r34
MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python -m perception train-denoiser --clips library:data/library/train \
  deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 deepmimic:dance_a \
  deepmimic:dance_b deepmimic:kick deepmimic:punch deepmimic:spin deepmimic:spinkick deepmimic:jump deepmimic:backflip \
  deepmimic:cartwheel deepmimic:crawl deepmimic:roll deepmimic:getup_facedown deepmimic:getup_faceup \
  --run-dir runs/r34/denoiser_fast_s$SEED --out runs/r34/denoiser_fast_s$SEED/shipped --sole-weight 4 --stances 1 \
  --seed $SEED $EXTRA --speeds 0.8 1 1.25 --no-progress >> runs/r34/denoiser_fast_s$SEED.log 2>&1
