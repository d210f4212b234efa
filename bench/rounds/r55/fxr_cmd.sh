#!/bin/bash
# Round 55 (written stop 94; a run, not yet a registered candidate): FXR, the raw set's fast expert trained on raw IMU
# takes. The raw rows' set (models/mimic_general_raw_set) sends every take faster than 2.0 m/s (and not above 3.0 m/s,
# the dash expert's) to mimic_general_fast_symmetric (FXS, round 43), trained behind the IMU denoiser's slow corrections
# only; rounds 49-54 trained the backward, sideways, default, dash and turning members on raw takes (the backward, dash
# and turning ones led and joined the set), so the fast role is the last not yet tried so. FXR is FXS trained on by PPO
# as its symmetric actor with round 43's data and settings (bench/rounds/r43/fxs_cmd.sh: the training split's dashes and
# runs and DeepMimic's run, half its episodes clean) but its IMU takes tracked as given: no --denoise and no
# --denoise-slow, the legs still evened and parted, grounded and swing-lifted as the raw rows track them. --total-steps
# only bounds the run. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without
# runs/r55/ppo_fxr it carries on from models/mimic_general_fast_symmetric/raw_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
FAST=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('dash', 'run'))))")
bash bench/rounds/ppo_run.sh runs/r55/ppo_fxr models/mimic_general_fast_symmetric/raw_run runs/r55/ppo_fxr.log --clips $FAST deepmimic:run --eval-clips 'library:data/library#dataset-1_dash_happy_001' 'library:data/library#dataset-1_run_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_fast_symmetric --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2410000
