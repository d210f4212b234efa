#!/bin/bash
# Round 30, for a later stop: PV10 (shipped as models/mimic_general_fast_critic at 4.0 M steps) trained on with its
# settings to 8.0 M steps, from the shipped policy's run/ copied to runs/r30/ppo_pv10c; resumable as it goes
# (train_ppo.py --run-dir runs/r30/ppo_pv10c --resume). Not registered.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r30
[ -d runs/r30/ppo_pv10c ] || cp -r models/mimic_general_fast_critic/run runs/r30/ppo_pv10c
MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --run-dir runs/r30/ppo_pv10c --resume --total-steps 8000000 >> runs/r30/ppo_pv10c.log 2>&1
