#!/bin/bash
# Round 37: DX (bench/rounds/r37/dx_cmd.sh) trained on the device tool's machine (16 cores and a GPU) for
# TRAIN_S seconds (default 470), its newest checkpoint and the run's records sent back under $OUT as dx.tgz in parts
# of 15 MB (cat dx.tgz.part_* | tar xz). The machine lacks mujoco, gymnasium and stable-baselines3: their Python 3.12
# wheels travel in .whl (README of the device tool). It has no EGL loader, so MuJoCo's rendering is switched off
# (MUJOCO_GL=disable, set in the .venv/bin/python stand-in because ppo_run.sh sets MUJOCO_GL=egl).
cd "$(dirname "$0")/../../.."
[ -n "$OUT" ] && [ ! -e .venv ] || { echo "device_dx.sh: for the device tool's machine (\$OUT set, no .venv)" >&2; exit 2; }
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site:$PWD
mkdir -p .venv/bin && printf '#!/bin/sh\nMUJOCO_GL=disable exec python3 "$@"\n' > .venv/bin/python && chmod +x .venv/bin/python
.venv/bin/python -c "import mujoco, gymnasium, stable_baselines3, envs" || exit 1
nproc; nvidia-smi -L
DEVICE=1 bash bench/rounds/r37/dx_cmd.sh & P=$!
for _ in $(seq $(( ${TRAIN_S:-470} / 5 ))); do sleep 5; kill -0 $P 2>/dev/null || break; done
pkill -TERM -f agents/train_ppo.py; wait $P
tail -40 runs/r37/ppo_dx.log
L=$(ls -t runs/r37/ppo_dx/checkpoints/*.zip | head -1) || exit 1; B=${L%.zip}
tar czf /tmp/dx.tgz --ignore-failed-read runs/r37/ppo_dx/args.json runs/r37/ppo_dx/wall.json \
  runs/r37/ppo_dx/evaluations.jsonl "$L" "${B}_sidecar.json" "${B}_vecnormalize.pkl" runs/r37/ppo_dx/tb
split -b 15M /tmp/dx.tgz "$OUT/dx.tgz.part_"
cp runs/r37/ppo_dx.log "$OUT/"
ls -la "$OUT"
