#!/bin/bash
# Builds, in the local checkout, the folders a lent machine's scripts carry (kept out of git through
# .git/info/exclude), and slims what travels with the working tree (at most 64 MiB; models/ alone is
# about 200 MB).
# usage: bash bench/device/prepare_carry.sh wheels            # .whl/: py3.12 wheels the machine lacks
#        bash bench/device/prepare_carry.sh devpkgs SPLIT...  # .devpkgs/: stand-in pybullet_data and lib/
#        bash bench/device/prepare_carry.sh hide MODEL...     # untrack every other models/ folder (index only)
#        bash bench/device/prepare_carry.sh restore           # undo hide
# devpkgs: pybullet_data holds only DeepMimic's motion files (getDataPath() returns its own folder); lib/
# is data/library's manifest and the humanoid_1seg takes of the given splits (e.g. val test).
# hide removes the other models from the index only (the files stay on disk, a run's `models/X/run/`
# too) and ignores them, so they do not travel; never commit while they are hidden: restore first.
set -eu -o pipefail
PY=${PY:-.venv/bin/python}
exclude() { grep -qxF "$1" .git/info/exclude 2>/dev/null || echo "$1" >> .git/info/exclude; }
case ${1:-} in
wheels)
  exclude /.whl/
  $PY -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
    --platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64 \
    --platform manylinux2014_x86_64 --platform manylinux1_x86_64 -d .whl \
    mujoco==4.0.0 mujoco-core==4.0.0 mujoco-studio==4.0.0 glfw==2.11.0 pyopengl==3.1.10 websockets \
    gymnasium==1.4.0 stable-baselines3==2.9.2 farama-notifications==0.0.6
  du -sh .whl ;;
devpkgs)
  shift; [ $# -ge 1 ] || { echo "devpkgs needs the library splits to carry (e.g. val test)" >&2; exit 2; }
  exclude /.devpkgs/
  rm -rf .devpkgs && mkdir -p .devpkgs/lib/humanoid_1seg .devpkgs/pybullet_data/data
  cp data/library/manifest.json .devpkgs/lib/
  $PY - "$@" <<'PYEOF'
import shutil, sys
from reference_motion.library import expand_clips
for split in sys.argv[1:]:
    for clip in expand_clips([f"library:data/library/{split}"]):
        shutil.copy(f"data/library/humanoid_1seg/{clip.split('#')[1]}.npz", ".devpkgs/lib/humanoid_1seg/")
PYEOF
  cp -r "$($PY -c 'import pybullet_data; print(pybullet_data.getDataPath())')/data/motions" .devpkgs/pybullet_data/data/
  printf '"""Stand-in for pybullet_data on a lent machine: DeepMimic'"'"'s motion files only."""\nimport os\n\n\ndef getDataPath():\n    return os.path.dirname(__file__)\n' \
    > .devpkgs/pybullet_data/__init__.py
  du -sh .devpkgs ;;
hide)
  shift; [ $# -ge 1 ] || { echo "hide needs the models that travel (e.g. imu_denoiser_dm mimic_general_stance)" >&2; exit 2; }
  keep=$(printf '%s|' "$@"); keep=${keep%|}
  git ls-files models | grep -v -E "^models/($keep)/" | grep -v -E "^models/[^/]+/run/" > /tmp/hidden_models.txt || true
  git ls-files models | grep -E "^models/[^/]+/run/" >> /tmp/hidden_models.txt || true
  git rm -q --cached --pathspec-from-file=/tmp/hidden_models.txt
  exclude '/models/*'; for m in "$@"; do exclude "!/models/$m/"; done; exclude '/models/*/run/'
  echo "tracked files that travel: $(git ls-files -z | xargs -0 du -cb | tail -1)" ;;
restore)
  git reset -q -- models
  grep -v -E '^!?/models/' .git/info/exclude > .git/info/exclude.new || true
  mv .git/info/exclude.new .git/info/exclude
  git status --short models | head -3 ;;
*)
  sed -n 2,13p "$0"; exit 2 ;;
esac
