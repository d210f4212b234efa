#!/bin/bash
# Round 36, SX: a sideways expert, BX's way (bench/rounds/r35/bx_cmd.sh) for the takes PolicySet's sideways rule routes
# (median speed across the pelvis heading above 0.2 m/s). LSS (models/mimic_general_style_shifts_sq, its run's
# step_500000) trained on by PPO with LSS's settings, on the training split's 22 sideways walks (walk-left, walk-right)
# alone, with two posture copies of each reference. --total-steps only bounds the run.
# Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without it, it carries on from
# mimic_general_sideways/run (SX, shipped in round 36).
set -eo pipefail
cd "$(dirname "$0")/../../.."
SIDE=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('walk-left', 'walk-right'))))")
bash bench/rounds/ppo_run.sh runs/r36/ppo_sx models/mimic_general_sideways/run runs/r36/ppo_sx.log --clips $SIDE --eval-clips 'library:data/library#dataset-1_walk-left_happy_001' 'library:data/library#dataset-1_walk-right_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_style_shifts_sq --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 1815000
