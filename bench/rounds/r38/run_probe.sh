#!/bin/bash
# Round 38, a probe (training clips only, reported, not a choice): DeepMimic's run (3.9 m/s, in FX's training, not in
# DX's) now goes to DX by the dash rule. The shipped set (DX for it) and FX alone perform it clean and under IMU
# strength 1 (seed 1960000), 10 rollouts each with the mirror averaged, behind the stances denoiser.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r38
export MUJOCO_GL=egl OMP_NUM_THREADS=1
for P in expert_set fast; do
  for C in clean imu; do
    EXTRA=(); [ $C = imu ] && EXTRA=(--corrupt imu --strength 1 --seed 1960000)
    .venv/bin/python agents/evaluate.py --policy "models/mimic_general_$P" --mirror-average \
      --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --ground \
      --swing-lift --clips deepmimic:run --episodes 10 --per-clip "${EXTRA[@]}" \
      --json "bench/results/round38_deepmimic_run_${C}_$P.json" > "runs/r38/run_probe_${C}_$P.log" 2>&1
  done
done
