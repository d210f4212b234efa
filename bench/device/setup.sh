# Sourced by the lent machine's scripts (heading_eval.sh, score_candidates.sh) after they set PY:
# where $PY lacks mujoco, installs the carried .whl/ wheels into /tmp/site, puts them and .devpkgs/
# (the stand-in pybullet_data) on the import path and copies .devpkgs/lib in as data/library; then
# one thread per process and no rendering.
if [ -d .whl ] && ! $PY -c "import mujoco" 2>/dev/null; then
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
  export PYTHONPATH=/tmp/site:$PWD/.devpkgs:$PWD
  mkdir -p data && rm -rf data/library && cp -r .devpkgs/lib data/library
fi
export PYTHONUNBUFFERED=1 MUJOCO_GL=disable OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
