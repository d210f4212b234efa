#!/bin/bash
# Round 54 (stop 94): TXR, the raw set's turning expert trained on raw IMU takes. The raw rows' set
# (models/mimic_general_raw_set) sends every take whose pelvis heading turns faster than 0.3 rad/s to
# mimic_general_turning (TX, rounds 37-38), trained behind the IMU denoiser's slow corrections only; the fast and
# turning roles are the two not yet tried with a member trained on raw takes (rounds 49-52 tried the backward,
# sideways, default and dash ones; the backward and dash ones joined the set).
# TXR is TX trained on by PPO with TX's own command (bench/rounds/r37/tx_cmd.sh: DeepMimic's two training turns,
# mirrored, 3/4 of the episodes IMU-corrupted, the privileged critic) but its IMU takes tracked as given: no --denoise
# and no --denoise-slow, the legs still evened and parted, grounded and swing-lifted as the raw rows track them.
# --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine
# without runs/r54/ppo_txr it carries on from models/mimic_general_turning/raw_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
bash bench/rounds/ppo_run.sh runs/r54/ppo_txr models/mimic_general_turning/raw_run runs/r54/ppo_txr.log --clips deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 --eval-clips deepmimic:walker/turn_right0 --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_turning --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 2380000
