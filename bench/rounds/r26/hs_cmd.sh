#!/bin/bash
# Round 26, HS: a specialist for the training takes WLST loses (round 25's training-take diagnostics:
# clean ELR below 0.75, or IMU ELR below 0.8 on both seeds 1140000 and 1150000), fine-tuned from WLST on
# those takes alone (mirrored, three episodes in four IMU-corrupted and prepared as WLST's) at the
# single-take rate of "The training dashes" (fixed lr 1e-4, no KL following), 0.75 M steps.
# Waits for WW's run to end so that the two do not share the cores.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
while pgrep -f "run-dir runs/r25/ppo_wide" > /dev/null; do sleep 20; done
L=library:data/library#dataset-1_
MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py \
  --clips ${L}walk-right_sad_001 ${L}walk-back_feminine_001 ${L}dash_active_001 ${L}walk-left_sad_001 \
    ${L}dash_musical_001 ${L}dash_masculinity_001 ${L}run_active_001 ${L}walk-right_not-confident_001 \
    ${L}run_musical_001 ${L}walk-left_not-confident_001 ${L}walk-right_proud_001 ${L}run_chimpira_001 \
  --eval-clips ${L}dash_active_001 ${L}walk-left_sad_001 ${L}dash_musical_001 ${L}run_active_001 \
  --obs-frame reference --net 256,256 --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 \
  --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --checkpoint-every 125000 --eval-every 250000 \
  --eval-episodes 6 --eval-strength 1.0 --vec batched --n-envs 32 --n-steps 256 --physics-rate-hz 480 \
  --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 1e-4 --dynamics 0.15 0.3 0.15 \
  --pd-offset 3.5 --init-from models/mimic_general_slow/run/checkpoints/step_3750016.zip --total-steps 750000 \
  --stances 1 --workers 2 --torch-threads 2 --ground --swing-lift --denoise models/imu_denoiser_soles_quint_mirror \
  --denoise-slow 0.5 --even-legs --part-legs --judge clean_pose --lookahead 1 2 4 8 --lookbehind 1 2 4 8 \
  --run-dir runs/r26/ppo_hs > runs/r26/ppo_hs.log 2>&1
