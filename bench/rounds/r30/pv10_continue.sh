#!/bin/bash
# Round 30, for a later stop: PV10 (shipped as models/mimic_general_fast_critic at 4.0 M steps) trained on with its
# settings to 8.0 M steps in runs/r30/ppo_pv10c, resumable as it goes (train_ppo.py --run-dir runs/r30/ppo_pv10c
# --resume). Not registered. On a machine without that run it starts from the checkpoint committed at the end of
# stop 73 (models/mimic_general_fast_critic/continued_run/), or else from the shipped policy's run/.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r30
if [ ! -d runs/r30/ppo_pv10c ]; then
  if [ -d models/mimic_general_fast_critic/continued_run ]; then cp -r models/mimic_general_fast_critic/continued_run runs/r30/ppo_pv10c
  else cp -r models/mimic_general_fast_critic/run runs/r30/ppo_pv10c; fi
fi
MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --run-dir runs/r30/ppo_pv10c --resume --total-steps 8000000 >> runs/r30/ppo_pv10c.log 2>&1
