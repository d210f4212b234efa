#!/bin/bash
# Round 35, BX: a backward expert, FX's way (bench/rounds/r35/fx_cmd.sh) for the takes PolicySet's backward rule
# routes. LSS (its run's step_500000, on this machine in runs/r34/ppo_lss) trained on by PPO with LSS's settings, on
# the training split's 11 backward walks alone, also at 1.25x and 1.5x pace as LSS trained on them, with two posture
# copies of each reference; one worker and one torch thread, beside FX's run. --total-steps only bounds the run.
# Resumable: train_ppo.py --run-dir runs/r35/ppo_bx --resume.
# Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without it, it carries on from mimic_general_back/run (BX, shipped in round 36).
set -eo pipefail
cd "$(dirname "$0")/../../.."
BACK=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('walk-back',))))")
bash bench/rounds/ppo_run.sh runs/r35/ppo_bx models/mimic_general_back/run runs/r35/ppo_bx.log --clips $BACK --eval-clips 'library:data/library#dataset-1_walk-back_happy_001' --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from runs/r34/ppo_lss/checkpoints/step_500000.zip --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 1 --torch-threads 1 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 1755000
