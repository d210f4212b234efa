#!/bin/bash
# Round 30: PV10 (bench/rounds/r29/pv10_cmd.sh, --critic-lr-scale 10) carried on from its checkpoint at 144,480 steps,
# committed at the end of stop 72 in models/mimic_general_asymmetric/pv10_run/ (in git at 51ff2f0, removed since) and
# copied to runs/r29/ppo_pv10 before this ran.
cd "$(dirname "$0")/../../.." && MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --run-dir runs/r29/ppo_pv10 --resume >> runs/r29/ppo_pv10.log 2>&1
