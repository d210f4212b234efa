#!/bin/bash
# Round 43, FXS: the fast expert FX (models/mimic_general_fast, round 35's run at 2,300,000 steps) trained on by PPO as
# the mirror-symmetric actor it is shipped as (--symmetric, agents/symmetric_policy.py), with FX's data and settings
# (the training split's 10 dashes and 10 runs and DeepMimic's run; bench/rounds/r35/fx_cmd.sh) except that half its
# episodes are clean (--corrupted-fraction 0.5, as round 41's BXS2 carried the backward expert on) and without FX's
# privileged critic, which --symmetric does not take (the critic is warm-started as BX's was for BXS). Probe (stop 85,
# validation only, 4 draws of seeds 1990000+ x 2 rollouts of dash_happy_001's five style-shifted versions behind SQ at
# IMU strength 1): FX mirror-averaged, as shipped, 0.928 (faster 0.781); its plain actor, as PPO trained it, 0.905
# (faster 0.672). --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on
# a machine without runs/r43/ppo_fxs it carries on from models/mimic_general_fast/symmetric_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
FAST=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('dash', 'run'))))")
bash bench/rounds/ppo_run.sh runs/r43/ppo_fxs models/mimic_general_fast/symmetric_run runs/r43/ppo_fxs.log --clips $FAST deepmimic:run --eval-clips 'library:data/library#dataset-1_dash_happy_001' 'library:data/library#dataset-1_run_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_fast --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2080000
