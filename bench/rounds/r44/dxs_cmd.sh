#!/bin/bash
# Round 44, DXS: the dash expert DX (models/mimic_general_dash, round 37's run) trained on by PPO as the
# mirror-symmetric actor it is shipped as (--symmetric, agents/symmetric_policy.py), with DX's data and settings (the
# training split's dashes and runs faster than 3.0 m/s; bench/rounds/r37/dx_cmd.sh) except that half its episodes are
# clean (--corrupted-fraction 0.5, as rounds 41 and 43 carried the backward and fast experts on), that its takes are
# also played at 1.25x their pace (DX: 0.9x-1.1x; validation's dash at 1.25x pace is the version DX serves and loses:
# 0.817 in bench/results/round32_shifted_2060000_BXS2RSET_SQ.json), and without DX's privileged critic, which
# --symmetric does not take (the critic is warm-started from DX's policy as FX's was for FXS). Probe (stop 85,
# validation only): DX mirror-averaged, as shipped, 0.941 on dash_happy_001's five style-shifted versions behind SQ at
# IMU strength 1; its plain actor 0.921. --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh: a second
# call resumes the run; on a machine without runs/r44/ppo_dxs it carries on from
# models/mimic_general_dash/symmetric_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
DASHES=$(.venv/bin/python bench/rounds/takes_faster_than.py library:data/library/train dash,run 3.0)
bash bench/rounds/ppo_run.sh runs/r44/ppo_dxs models/mimic_general_dash/symmetric_run runs/r44/ppo_dxs.log --clips $DASHES --eval-clips 'library:data/library#dataset-1_dash_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_dash --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.9 1.0 1.1 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2110000
