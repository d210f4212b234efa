#!/bin/bash
# Round 36, FX2: round 35's FX run carried on past its 3.0 M bound to 4.0 M steps, with every other setting as
# stored in its args.json (bench/rounds/r35/fx_cmd.sh), niced so that the round's scoring beside it keeps its cores.
# On a machine without runs/r35/ppo_fx, the committed run (models/mimic_general_fast/run) is copied there first.
# A second call resumes it again. The round's candidate is its newest checkpoint at the registered time.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r35
R=runs/r35/ppo_fx
[ -d "$R" ] || cp -r models/mimic_general_fast/run "$R"
export MUJOCO_GL=egl OMP_NUM_THREADS=1
nice -n 10 .venv/bin/python agents/train_ppo.py --run-dir "$R" --resume --total-steps 4000000 >> runs/r35/ppo_fx.log 2>&1
