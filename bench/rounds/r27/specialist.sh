#!/bin/bash
# usage: bench/rounds/r27/specialist.sh TAKE   (e.g. dataset-1_walk-left_sad_001)
# Round 27: a single-take specialist fine-tuned from WW (models/mimic_general_wide) on one lost training take,
# clean and mirrored, its reference prepared as WW's were (legs evened and parted, grounded, swing-lifted) and
# judged against the take as given; WW's env settings otherwise; lr 1e-4 for 750 k steps as the dash specialists
# of mimic_dash_set were. It teaches that take to WW's next student (agents/distill.py).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r27
T=$1
MUJOCO_GL=egl OMP_NUM_THREADS=1 exec .venv/bin/python agents/train_ppo.py --clips "library:data/library#$T" \
  --eval-clips "library:data/library#$T" --obs-frame reference --net 512,512 --mirror \
  --checkpoint-every 250000 --eval-every 250000 --eval-episodes 5 --vec batched --n-envs 32 --n-steps 256 \
  --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 1e-4 \
  --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_wide/model.zip --total-steps 750000 \
  --stances 1 --workers 1 --torch-threads 1 --ground --swing-lift --even-legs --part-legs --judge given \
  --lookahead 1 2 4 8 --lookbehind 1 2 4 8 --run-dir runs/r27/spec_$T > runs/r27/spec_$T.log 2>&1
