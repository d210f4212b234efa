#!/bin/bash
# Round 50 (written stop 90, not yet started; a run, not yet a registered candidate): SXR, the sideways expert trained
# for raw IMU takes. After the backward walk, the raw rows' set (RAWSET: the shipped set with no denoiser in front)
# loses most on validation's sideways walks (walk-left wider 0.896 and faster 0.906, walk-right faster 0.916, averaged
# over round 47's draws 2190000+ and 2200000+), which go to the sideways expert SX (models/mimic_general_sideways),
# trained behind the denoiser's slow corrections only. SXR is SX trained on by PPO as the symmetric actor with round
# 45's data and settings (bench/rounds/r45/sxs_cmd.sh: half its episodes clean) but its IMU takes tracked as given, as
# round 49's BXR was for the backward expert: no --denoise and no --denoise-slow, the legs still evened and parted,
# grounded and swing-lifted as the raw rows track them. --total-steps only bounds the run. Run by
# bench/rounds/ppo_run.sh: a second call resumes the run; on a machine without runs/r50/ppo_sxr it carries on from
# models/mimic_general_sideways/raw_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
SIDEWAYS=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('walk-left', 'walk-right'))))")
bash bench/rounds/ppo_run.sh runs/r50/ppo_sxr models/mimic_general_sideways/raw_run runs/r50/ppo_sxr.log --clips $SIDEWAYS --eval-clips 'library:data/library#dataset-1_walk-left_happy_001' 'library:data/library#dataset-1_walk-right_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_sideways --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2280000
