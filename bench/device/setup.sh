# Sourced by the lent machine's scripts (gpu_ab.sh, heading_eval.sh, score_candidates.sh, train_gait.sh),
# with PY naming the interpreter (default python3): where $PY lacks mujoco (the lent machine, not a
# local checkout), installs the carried .whl/ wheels into /tmp/site, puts them and .devpkgs/ (the
# stand-in pybullet_data) on the import path and copies .devpkgs/lib in as data/library; then one
# thread per process and no rendering. A local run keeps its own data/library.
PY=${PY:-python3}
if [ -d .whl ] && ! $PY -c "import mujoco" 2>/dev/null; then
  $PY -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
  export PYTHONPATH=/tmp/site:$PWD/.devpkgs:$PWD
  mkdir -p data && rm -rf data/library && cp -r .devpkgs/lib data/library
fi
export PYTHONUNBUFFERED=1 MUJOCO_GL=disable OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
