# Two entry points for a fresh clone (Python 3.11): `make demo` and `make test`.
PYTHON ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
export MUJOCO_GL ?= egl

.PHONY: setup demo test mjcf

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	# torch first, pinned: on these machines 2.13.0 resolves to a local CPU build
	$(PY) -m pip install --quiet torch==2.13.0
	$(PY) -m pip install --quiet -e ".[dev]"

setup: $(PY)

# the `video` extra (MediaPipe) for the video front end; `make test` installs it so CI runs the video test
$(VENV)/.video-extra: $(PY)
	$(PY) -m pip install --quiet -e ".[dev,video]"
	touch $@

# Main job on built-in data: a held-out clip (walker/turn_left1, never seen in training), corrupted with
# IMU artefacts (seed 1000, never used in training), cleaned the way the README recommends for an IMU-suit take
# (`--preset imu`: the IMU denoiser, then the policy set validation chose, zero-shot): before/after metrics, the
# cleaned motion (.npz, .bvh) and a side-by-side video (reference | cleaned, re-anchors framed in red) in out/.
# Then the same take's foot skate removed by the vGRF-guided cleanup (UnderPressure §6): .npz, .bvh and a speed plot.
# DEMO_WITH chooses how clean.py cleans, e.g. per-clip adaptation of the first generalist (the demo until stop 93):
#   make demo DEMO_WITH="--policy models/mimic_general --adapt-budget-s 150 --adapt-steps 143360"
DEMO_WITH ?= --preset imu
demo: setup
	mkdir -p out
	$(PY) agents/clean.py deepmimic:walker/turn_left1 $(DEMO_WITH) --corrupt imu --strength 1 \
		--seed 1000 --min-frames 600 --out out/turn_left1_cleaned.npz \
		--bvh out/turn_left1_cleaned.bvh --video out/turn_left1_imu_vs_cleaned.mp4 --json out/turn_left1_metrics.json
	$(PY) -m perception cleanup deepmimic:walker/turn_left1 --corrupt imu --strength 1 --seed 1000 \
		--min-frames 600 --out out/turn_left1_noskate.npz --bvh out/turn_left1_noskate.bvh \
		--plot out/turn_left1_noskate.png --json out/turn_left1_noskate.json

test: setup $(VENV)/.video-extra
	$(PY) -m pytest -q

mjcf: setup
	$(PY) -m reference_motion.humanoid.builder
