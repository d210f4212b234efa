#!/bin/bash
# Round 40, BXS: the backward expert BX (models/mimic_general_back, 1,441,120 steps) trained on by PPO as the
# mirror-symmetric actor it is shipped as (--symmetric: PPO's actor is the mean of the network's action and, mapped
# back, its action on the mirrored observation; agents/symmetric_policy.py), with BX's settings and data (the training
# split's 11 backward walks, also at 1.25x and 1.5x pace, two posture copies of each; bench/rounds/r35/bx_cmd.sh),
# two workers and two torch threads, and without BX's privileged critic (--symmetric does not take one: the critic is
# BX's plain one, as warm_start loads it). BX acts mirror-averaged in the shipped set, but PPO trained its plain actor, which
# performs validation's backward walk far worse (clean, 4 draws x 2 rollouts: 0.64 plain against 0.95 mirror-averaged).
# --total-steps only bounds the run. Resumable: train_ppo.py --run-dir runs/r40/ppo_bxs --resume.
# Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without it, it carries on from
# models/mimic_general_back/symmetric_run (committed at 1,213,856 steps).
set -eo pipefail
cd "$(dirname "$0")/../../.."
BACK=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('walk-back',))))")
bash bench/rounds/ppo_run.sh runs/r40/ppo_bxs models/mimic_general_back/symmetric_run runs/r40/ppo_bxs.log --clips $BACK --eval-clips 'library:data/library#dataset-1_walk-back_happy_001' --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_back --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2015000
