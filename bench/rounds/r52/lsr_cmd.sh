#!/bin/bash
# Round 52 (stop 92): LSR, the raw set's default member trained on raw IMU takes. The raw rows' set
# (models/mimic_general_raw_set) sends every take that is not backward, sideways, fast, a dash or a turn to
# mimic_general_style_shifts_sq (LSS, round 34), trained behind the IMU denoiser's slow corrections only; rounds 49 and
# 50 trained the backward and sideways experts on raw takes, and stop 92's probe (docs/results.md, "Round 52") finds
# validation's forward walks losing to the suit's drift under LSS. LSR is LSS trained on by PPO with LSS's own command
# (bench/rounds/r34/lss_cmd.sh: the training split, DeepMimic's walk, run and training turns, 3/4 of the episodes
# IMU-corrupted, the privileged critic) but its IMU takes tracked as given: no --denoise and no --denoise-slow, the legs
# still evened and parted, grounded and swing-lifted as the raw rows track them. --total-steps only bounds the run.
# Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without runs/r52/ppo_lsr it carries on
# from models/mimic_general_style_shifts_sq/raw_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/ppo_run.sh runs/r52/ppo_lsr models/mimic_general_style_shifts_sq/raw_run runs/r52/ppo_lsr.log --clips library:data/library/train deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 --exclude 'library:data/library#02_04' 'library:data/library#02_05' 'library:data/library#02_06' 'library:data/library#02_07' 'library:data/library#02_08' 'library:data/library#02_09' 'library:data/library#02_10' --eval-clips library:data/library/val --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 500000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_style_shifts_sq --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 1 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 2320000
