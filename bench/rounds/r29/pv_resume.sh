#!/bin/bash
# Round 29: PV resumed at 22:45 UTC after it was stopped at 1.18 M steps (22:43) to make room for a variant that was
# then not run; from here on it trains with the mended code of 32b5e92 (docs/results.md, round 29).
cd "$(dirname "$0")/../../.." && MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/train_ppo.py --run-dir runs/r29/ppo_pv --resume >> runs/r29/ppo_pv.log 2>&1
