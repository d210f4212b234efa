#!/bin/bash
# Round 31, LW (for a later stop): LU's ablation, the same reference window of 1 2 4 8 16 32 control steps each way but PV10's
# judge (--judge clean_pose, paid for the clean pose on the tracked path, skate included), to tell whether LU's held-out loss on
# the hardest unseen-style takes came with the window or with the judge. Carries on where runs/r31/ppo_lw is; on a
# machine without it, from the checkpoint committed at the end of stop 74 (models/mimic_general_long_window/lw_run/).
cd "$(dirname "$0")/../../.." && mkdir -p runs/r31
[ -d runs/r31/ppo_lw ] || [ ! -d models/mimic_general_long_window/lw_run ] || cp -r models/mimic_general_long_window/lw_run runs/r31/ppo_lw
if [ -f runs/r31/ppo_lw/args.json ]; then
  MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --run-dir runs/r31/ppo_lw --resume >> runs/r31/ppo_lw.log 2>&1
else
  MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --clips library:data/library/train deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 --exclude 'library:data/library#02_04' 'library:data/library#02_05' 'library:data/library#02_06' 'library:data/library#02_07' 'library:data/library#02_08' 'library:data/library#02_09' 'library:data/library#02_10' --eval-clips library:data/library/val --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --eval-every 500000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_fast_critic --total-steps 4000000 --checkpoint-every 250000 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge clean_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --run-dir runs/r31/ppo_lw > runs/r31/ppo_lw.log 2>&1
fi
