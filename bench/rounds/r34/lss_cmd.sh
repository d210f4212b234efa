#!/bin/bash
# Round 34, LSS: LS (round 32) at 0.5 M steps, the shipped mimic_general_style_shifts, trained on by PPO with LS's
# settings and data but behind SQ (models/imu_denoiser_stances_quint_mirror), the denoiser it is scored and shipped
# behind since round 32, in place of QT, which LS trained behind. --total-steps 2000000 (LS's run asked for 4000000)
# only bounds the run: round 34's candidate is its newest checkpoint at 14:55 UTC (step_500000).
# Resumable: train_ppo.py --run-dir runs/r34/ppo_lss --resume.
# Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without it, it carries on from
# mimic_general_style_shifts_sq/run.
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/ppo_run.sh runs/r34/ppo_lss models/mimic_general_style_shifts_sq/run runs/r34/ppo_lss.log --clips library:data/library/train deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 --exclude 'library:data/library#02_04' 'library:data/library#02_05' 'library:data/library#02_06' 'library:data/library#02_07' 'library:data/library#02_08' 'library:data/library#02_09' 'library:data/library#02_10' --eval-clips library:data/library/val --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 500000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_style_shifts/run/checkpoints/step_500000.zip --total-steps 2000000 --checkpoint-every 250000 --speeds 0.8 1.0 1.25 --postures 1 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10
