# Two entry points for a fresh clone (Python 3.11): `make demo` and `make test`.
PYTHON ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
export MUJOCO_GL ?= egl

.PHONY: setup demo test models

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	# torch first, pinned: on these machines 2.13.0 resolves to a local CPU build
	$(PY) -m pip install --quiet torch==2.13.0
	$(PY) -m pip install --quiet -e ".[dev]"

setup: $(PY)

# Main job on built-in data: retarget DeepMimic walk, corrupt it with IMU artefacts, measure both
# and render them side by side (later issues turn this into the clean-a-clip demo).
demo: setup
	mkdir -p out
	$(PY) -m reference_motion quality deepmimic:walk --json | tee out/walk_quality.json
	$(PY) -m reference_motion quality deepmimic:walk --corrupt imu --strength 0.5 --seed 1 --json | tee out/walk_imu_quality.json
	$(PY) -m reference_motion render deepmimic:walk --corrupt imu --strength 0.5 --seed 1 --with-clean --out out/walk_clean_vs_imu.mp4

test: setup
	$(PY) -m pytest -q

models: setup
	$(PY) -m reference_motion.humanoid.builder
