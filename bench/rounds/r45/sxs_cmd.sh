#!/bin/bash
# Round 45, SXS: the sideways expert SX (models/mimic_general_sideways, round 36's run) trained on by PPO as the
# mirror-symmetric actor it is shipped as (--symmetric, agents/symmetric_policy.py), with SX's data and settings (the
# training split's walks to the left and to the right, played at 0.8x-1.25x their pace; its command in
# models/mimic_general_sideways/sidecar.json) except that half its episodes are clean (--corrupted-fraction 0.5, SX:
# 0.75), as rounds 41, 43 and 44 carried the backward, fast and dash experts on, and without SX's privileged critic,
# which --symmetric does not take (the critic is warm-started from SX's policy, as FX's was for FXS). The shipped set
# loses validation's sideways walks played faster (0.91-0.94 on FXSSET's draws 2090000+ and 2100000+), which go to SX.
# --total-steps only bounds the run. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine
# without runs/r45/ppo_sxs it carries on from models/mimic_general_sideways/symmetric_run where one is committed.
set -eo pipefail
cd "$(dirname "$0")/../../.."
SIDEWAYS=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('walk-left', 'walk-right'))))")
bash bench/rounds/ppo_run.sh runs/r45/ppo_sxs models/mimic_general_sideways/symmetric_run runs/r45/ppo_sxs.log --clips $SIDEWAYS --eval-clips 'library:data/library#dataset-1_walk-left_happy_001' 'library:data/library#dataset-1_walk-right_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.5 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_sideways --symmetric --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --seed 2140000
