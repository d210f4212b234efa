#!/bin/bash
# Round 32, LS: LU trained on by PPO with its settings on training takes also played at 0.8x and 1.25x their pace
# (--speeds 0.8 1.0 1.25) and also carried with a random posture (--postures 1), beside the wider stances it already
# had (--stances 1): the ways the styles differ that round 32's style-shifted validation shows, now in training too.
# From LU's run checkpoint as committed (models/mimic_general_long_window/run/). Resumable:
# train_ppo.py --run-dir runs/r32/ppo_ls --resume.
# Stop 75: the run was killed for memory (23.3 GiB resident, all the machine had) at 745,472 steps; its last checkpoint,
# step 500,000, is shipped as models/mimic_general_style_shifts. On a machine without runs/r32/ppo_ls this carries on
# from the newest checkpoint kept in models/. Each of the 32 envs keeps its own LRU cache of reference tracks (a few MB
# each; envs share a track only when they hold the very same one), and LS has about four times LU's references, so,
# most likely, fewer are shared: resumed with --track-cache 300 its memory grew 0.7 GB a minute to 13 GB in 14 minutes (kept at
# 791,616 steps, stop 75); with --track-cache 80 it holds at 5.6 GB, at about 235 steps/s (tracks are rebuilt, each
# through the denoiser, more often; stop 75). Stop 76: each process now keeps the tracks and the prepared references
# they are built from for all its envs (envs/track_cache.py; --track-cache counts per process), so a dropped track is
# rebuilt without corrupting and denoising again: resumed with --track-cache 1200 --reference-cache 16000.
cd "$(dirname "$0")/../../.."
mkdir -p runs/r32
# the newest kept checkpoint: the run carried on past the shipped one (ls_run/, bench/rounds/keep_run.sh), else run/
for KEPT in models/mimic_general_style_shifts/ls_run models/mimic_general_style_shifts/run; do
  [ -d runs/r32/ppo_ls ] || [ ! -d $KEPT ] || cp -r $KEPT runs/r32/ppo_ls
done
if [ -f runs/r32/ppo_ls/args.json ]; then
  MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --run-dir runs/r32/ppo_ls --resume --track-cache 1200 --reference-cache 16000 \
    >> runs/r32/ppo_ls.log 2>&1
  exit
fi
MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --clips library:data/library/train deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 --exclude 'library:data/library#02_04' 'library:data/library#02_05' 'library:data/library#02_06' 'library:data/library#02_07' 'library:data/library#02_08' 'library:data/library#02_09' 'library:data/library#02_10' --eval-clips library:data/library/val --obs-frame reference --net 512,512 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --eval-every 500000 --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_long_window/run/checkpoints/step_4005888.zip --total-steps 4000000 --checkpoint-every 250000 --speeds 0.8 1.0 1.25 --postures 1 --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --run-dir runs/r32/ppo_ls > runs/r32/ppo_ls.log 2>&1
