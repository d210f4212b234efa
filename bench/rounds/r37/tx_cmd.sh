#!/bin/bash
# Round 37, TX: a turning expert. The shipped set performs DeepMimic's training turn walker/turn_right0 at 0.70 clean
# and 0.58-0.68 under IMU (round 37's probe; turn_left0 0.96-1.00): LSS, the default, trains on it as one take of
# about 90. TX is LSS (models/mimic_general_style_shifts_sq) trained on by PPO with LSS's settings (SX's way,
# bench/rounds/r36/sx_cmd.sh) on DeepMimic's two training turns alone (walker/turn_left0, walker/turn_right0, mirrored:
# both sides of each), two posture copies of each. --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh:
# a second call resumes the run; on a machine without it, it carries on from mimic_general_turning/run.
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/ppo_run.sh runs/r37/ppo_tx models/mimic_general_turning/run runs/r37/ppo_tx.log --clips deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 --eval-clips deepmimic:walker/turn_right0 --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_style_shifts_sq --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 1895000
