#!/bin/bash
# Round 37's registered probe, run in round 38: DX (models/mimic_general_dash, step_600000) performs the training
# split's 10 dashes clean, 2 rollouts each with its mirror averaged, behind the stances denoiser, as FX's probe in
# round 37 (active 0.30, musical 0.35, masculinity 0.56, the other seven 1.00). Training takes only: reported, not a
# choice.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r38
export MUJOCO_GL=egl OMP_NUM_THREADS=1
CLIPS=()
for S in active angry childish chimpira feminine masculinity musical not-confident proud sad; do
  CLIPS+=("library:data/library#dataset-1_dash_${S}_001")
done
.venv/bin/python agents/evaluate.py --policy models/mimic_general_dash --mirror-average \
  --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --ground --swing-lift \
  --clips "${CLIPS[@]}" --episodes 2 --per-clip --json bench/results/round38_train_dashes_clean_DX.json \
  > runs/r38/dx_probe.log 2>&1
