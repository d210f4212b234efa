#!/bin/bash
# Stop 96: does PPO with 3 epochs per rollout, in the 64-env sharded batch (the fastest row of
# bench/ppo_throughput.py), learn walk from scratch as fast per frame as the default (6 epochs, 32 envs in
# one batch)? bench/time_to_sr90.py on seeds 0 and 1, the two settings alternated, then the throughput
# table with its 3-epoch row, all on otherwise idle cores.
set -eo pipefail
cd "$(dirname "$0")/../../.."
export MUJOCO_GL=egl OMP_NUM_THREADS=1
for seed in 0 1; do
  .venv/bin/python bench/time_to_sr90.py --run-dir runs/r57/e6_b32 --seed $seed --max-steps 1000000 \
    --json bench/results/time_to_sr90_e6_b32_seed$seed.json
  .venv/bin/python bench/time_to_sr90.py --run-dir runs/r57/e3_sb64 --seed $seed --max-steps 1000000 --epochs 3 \
    --vec sharded-batched --n-envs 64 --json bench/results/time_to_sr90_e3_sb64_seed$seed.json
done
.venv/bin/python bench/ppo_throughput.py --rounds 2 --json bench/results/ppo_throughput_stop96.json
# Then (stop 96, after the above): 3 epochs at twice the learning rate, to see whether a larger step per
# epoch buys back the frames the fewer epochs cost.
for seed in 0 1; do
  .venv/bin/python bench/time_to_sr90.py --run-dir runs/r57/e3_sb64_lr2e-4 --seed $seed --max-steps 1000000 --epochs 3 \
    --lr 2e-4 --vec sharded-batched --n-envs 64 --json bench/results/time_to_sr90_e3_sb64_lr2e-4_seed$seed.json
done
# And the default's 6 epochs at that same rate, so that each setting is compared at 2e-4 too.
for seed in 0 1; do
  .venv/bin/python bench/time_to_sr90.py --run-dir runs/r57/e6_b32_lr2e-4 --seed $seed --max-steps 1000000 --lr 2e-4 \
    --json bench/results/time_to_sr90_e6_b32_lr2e-4_seed$seed.json
done
