#!/bin/bash
# Round 49 (stop 89; a run, not yet a registered candidate): BXR, the backward expert trained for raw IMU takes. The
# raw rows' set since round 47 (RAWSET: the shipped set with no denoiser in front) loses most on validation's backward
# walk (0.82-0.86 over its five versions on the draws 2190000+ and 2200000+, against 0.93 and more behind the
# denoiser), and its backward expert BXS2R (models/mimic_general_back_symmetric) was trained behind the denoiser's
# slow corrections only. BXR is BXS2R trained on by PPO as the symmetric actor with BXS2R's data and settings
# (bench/rounds/r40/bxs_cmd.sh, --corrupted-fraction 0.5 as round 41) but its IMU takes tracked as given: no
# --denoise and no --denoise-slow, the legs still evened and parted, grounded and swing-lifted as the raw rows track
# them. --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine
# without runs/r49/ppo_bxr it carries on from models/mimic_general_back_symmetric/raw_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
BACK=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('walk-back',))))")
bash bench/rounds/ppo_run.sh runs/r49/ppo_bxr models/mimic_general_back_symmetric/raw_run runs/r49/ppo_bxr.log --clips $BACK --eval-clips 'library:data/library#dataset-1_walk-back_happy_001' --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_back_symmetric --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2250000
