#!/bin/bash
# Round 33, F: the first member of SQ's ensemble retrained (its command, bench/rounds/r24/den_stances_cmd.sh: seed 0,
# --sole-weight 4, --stances 1) on every take also played at 0.8x and 1.25x its pace (--speeds 0.8 1 1.25), so that it
# corrects faster takes as it does the others. Resumable (train-denoiser --run-dir).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r33 && MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python -m perception train-denoiser --clips library:data/library/train deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 deepmimic:dance_a deepmimic:dance_b deepmimic:kick deepmimic:punch deepmimic:spin deepmimic:spinkick deepmimic:jump deepmimic:backflip deepmimic:cartwheel deepmimic:crawl deepmimic:roll deepmimic:getup_facedown deepmimic:getup_faceup --run-dir runs/r33/denoiser_fast --out runs/r33/denoiser_fast/shipped --sole-weight 4 --stances 1 --speeds 0.8 1 1.25 --no-progress >> runs/r33/denoiser_fast.log 2>&1
