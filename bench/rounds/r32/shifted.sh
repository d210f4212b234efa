#!/bin/bash
# usage: bench/rounds/r32/shifted.sh NAME POLICY SEED DENOISER
# Round 32: validation's IMU draws seen through the styles' differences (bench/imu_draws.py --style-shifts: each of
# the seven happy takes as given, walked wider, at 0.8x and 1.25x its pace and carried with another posture, drawn
# anew for each draw), behind DENOISER's slow corrections with the IMU rows' preparation, 20 draws x 2 rollouts of
# every version (the seeds' stride is the 35 versions); writes bench/results/round32_shifted_SEED_NAME.json.
# DENOISE_SLOW (seconds, default 0.5) sets the slow corrections' Gaussian; set empty, the denoiser's full corrections
# (round 46). DENOISER given empty (""): no denoiser, the takes tracked as given (--no-denoise; DENOISE_SLOW ignored).
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r32
export MUJOCO_GL=egl OMP_NUM_THREADS=1
[ $# = 4 ] || { echo "shifted.sh: usage: shifted.sh NAME POLICY SEED DENOISER (\"\" for none)" >&2; exit 2; }
N=$1; P=$2; S=$3; D=$4
DENOISE_SLOW=${DENOISE_SLOW-0.5}
if [ -n "$D" ]; then DENOISING=(--denoise "$D" ${DENOISE_SLOW:+--denoise-slow "$DENOISE_SLOW"}); else DENOISING=(--no-denoise); fi
.venv/bin/python bench/imu_draws.py --policies "$P" --mirror-average "${DENOISING[@]}" --even-legs \
  --part-legs --ground --swing-lift --clips library:data/library/val --style-shifts --draws 20 --first-seed "$S" \
  --episodes 2 --json "bench/results/round32_shifted_${S}_$N.json" > "runs/r32/shifted_${S}_$N.log" 2>&1
