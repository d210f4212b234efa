#!/bin/bash
# Round 51 (written stop 91, not yet started; a run, not yet a registered candidate): DXR, the dash expert trained for
# raw IMU takes. With the backward and sideways experts trained on raw takes (rounds 49 and 50), the raw set's members
# still trained behind the denoiser only are the default, fast, dash and turning ones; on round 49's raw draws
# (2260000+ and 2270000+) the dash member's two versions lose 0.18 of ELR summed (the dash played faster 0.82, with a
# posture 0.91). DXR is DXS (models/mimic_general_dash_symmetric, round 44's run) trained on by PPO as its symmetric
# actor with round 44's data and settings (bench/rounds/r44/dxs_cmd.sh: the training split's dashes and runs faster
# than 3.0 m/s, half its episodes clean, paces 0.9x-1.25x) but its IMU takes tracked as given, as BXR and SXR were: no
# --denoise and no --denoise-slow, the legs still evened and parted, grounded and swing-lifted as the raw rows track
# them. --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine
# without runs/r51/ppo_dxr it carries on from models/mimic_general_dash_symmetric/raw_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
DASHES=$(.venv/bin/python bench/rounds/takes_faster_than.py library:data/library/train dash,run 3.0)
bash bench/rounds/ppo_run.sh runs/r51/ppo_dxr models/mimic_general_dash_symmetric/raw_run runs/r51/ppo_dxr.log --clips $DASHES --eval-clips 'library:data/library#dataset-1_dash_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_dash_symmetric --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.9 1.0 1.1 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2310000
