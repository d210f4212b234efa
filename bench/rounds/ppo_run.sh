#!/bin/bash
# usage: [RESUME_WITH='FLAGS'] bench/rounds/ppo_run.sh RUN_DIR COMMITTED_RUN LOG TRAIN_ARGS...
# A round's PPO run: agents/train_ppo.py TRAIN_ARGS --run-dir RUN_DIR, or, where RUN_DIR already holds the run, that
# run resumed from its newest checkpoint (with RESUME_WITH's flags in place of the stored ones: e.g. a run begun on
# the device tool's many cores resumed on 2). On a machine without RUN_DIR, COMMITTED_RUN (a shipped model's run/, if
# it exists) is copied there first, so the run carries on from what was committed. Output is appended to LOG.
set -eo pipefail
cd "$(dirname "$0")/../.."
R=$1; C=$2; L=$3; shift 3
mkdir -p "$(dirname "$R")"
[ -d "$R" ] || [ ! -d "$C" ] || cp -r "$C" "$R"
export MUJOCO_GL=egl OMP_NUM_THREADS=1
if [ -f "$R/args.json" ]; then
  # shellcheck disable=SC2086  # RESUME_WITH holds several flags
  .venv/bin/python agents/train_ppo.py --run-dir "$R" --resume ${RESUME_WITH:-} >> "$L" 2>&1
else
  .venv/bin/python agents/train_ppo.py "$@" --run-dir "$R" >> "$L" 2>&1
fi
