#!/bin/bash
# Round 35, FX: a fast expert in the manner of PHC's primitives (Luo et al. 2023: a new primitive trained on the
# motions the policy fails, composed with the earlier ones). LSS (round 34's mimic_general_style_shifts_sq, its run's
# step_500000, on this machine in runs/r34/ppo_lss) trained on by PPO with LSS's settings, but on the training split's
# dashes and runs alone (and DeepMimic's run), with two posture copies of each reference instead of one. Composed
# with LSS by the take's speed (agents/policy_set.py's fast rule, models/mimic_general_fast_set). --total-steps only bounds the run: the round's candidate is its
# newest checkpoint at the registered time. Run by bench/rounds/ppo_run.sh: a second call resumes the run; on a machine
# without it, it carries on from mimic_general_fast/run.
set -eo pipefail
cd "$(dirname "$0")/../../.."
FAST=$(.venv/bin/python -c "from reference_motion.motion_library import library_set
print(' '.join(library_set('library:data/library/train', ('dash', 'run'))))")
bash bench/rounds/ppo_run.sh runs/r35/ppo_fx models/mimic_general_fast/run runs/r35/ppo_fx.log --clips $FAST deepmimic:run --eval-clips 'library:data/library#dataset-1_dash_happy_001' 'library:data/library#dataset-1_run_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from runs/r34/ppo_lss/checkpoints/step_500000.zip --total-steps 3000000 --checkpoint-every 100000 --speeds 0.8 1.0 1.25 --postures 2 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 1735000
