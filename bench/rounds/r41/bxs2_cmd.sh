#!/bin/bash
# Round 41, BXS2: round 40's BXS (the backward expert trained on by PPO as its mirror-symmetric actor) carried on from
# its last checkpoint (1,213,856 steps) with half its episodes clean in place of a quarter (--corrupted-fraction 0.5,
# BXS trained at 0.75) and a new seed (2040000); every other setting is BXS's (bench/rounds/r40/bxs_cmd.sh). BXS gained
# on the backward walk's hard IMU versions behind the denoiser and lost the clean take at its own pace (round 40).
# The run is a copy of BXS's run dir resumed with these two settings changed (train_ppo.py --resume: the stored
# settings except those the command sets). --total-steps (BXS's, 3,000,000) only bounds the run.
# Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without runs/r40/ppo_bxs it carries on
# from models/mimic_general_back/symmetric_run (BXS committed at 1,213,856 steps).
set -eo pipefail
cd "$(dirname "$0")/../../.."
mkdir -p runs/r41
[ -d runs/r41/ppo_bxs2 ] || [ ! -d runs/r40/ppo_bxs ] || cp -r runs/r40/ppo_bxs runs/r41/ppo_bxs2
export RESUME_WITH="--corrupted-fraction 0.5 --seed 2040000"
bash bench/rounds/ppo_run.sh runs/r41/ppo_bxs2 models/mimic_general_back/symmetric_run runs/r41/ppo_bxs2.log
