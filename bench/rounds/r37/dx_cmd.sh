#!/bin/bash
# Round 37, DX: a dash expert for the takes that go faster than 3.0 m/s (median root speed). Round 37's probe of the
# shipped set on its own training takes (bench/results/round37_train_imu1_EXPERTSET2_*.json) found FX losing three
# of its ten training dashes (active, musical, masculinity) clean and under IMU alike, each falling 0.6-1.3 s in, while
# it performs the other dashes and its runs. DX is FX (models/mimic_general_fast) trained on by PPO with FX's settings
# on the training split's takes whose median root speed is above 3.0 m/s alone (7 dashes, 2 runs), played at 0.9x-1.1x
# their pace (FX: 0.8x-1.25x), two posture copies of each. --total-steps only bounds the run.
# On a machine with many cores and a GPU (the device tool) DEVICE=1 steps 64 envs in one shard per core, learning on
# the GPU, 128 steps each per update (the same 8192 frames per update); without it, FX's 32 envs x 256 steps on 2
# threads. Run by bench/rounds/ppo_run.sh: a second call resumes the run, on either machine.
set -eo pipefail
cd "$(dirname "$0")/../../.."
FAST=$(.venv/bin/python bench/rounds/takes_faster_than.py library:data/library/train dash,run 3.0)
if [ -n "$DEVICE" ]; then
  PAR="--vec sharded-batched --n-envs 64 --n-steps 128 --workers $(nproc) --device auto"
else
  PAR="--vec batched --n-envs 32 --n-steps 256 --workers 2 --torch-threads 2 --device cpu"
fi
export RESUME_WITH="$PAR"  # a run begun on the other kind of machine carries on with this one's settings
bash bench/rounds/ppo_run.sh runs/r37/ppo_dx models/mimic_general_dash/run runs/r37/ppo_dx.log --clips $FAST --eval-clips 'library:data/library#dataset-1_dash_happy_001' --obs-frame reference --net 512,512 --mirror --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 6 --track-cache 1200 --reference-cache 16000 --eval-every 250000 --eval-episodes 6 --eval-strength 1.0 $PAR --physics-rate-hz 480 --still-feet-weight 2 --steer-gain 1 --action-limit 1.5 --no-progress --lr 2e-5 --target-kl 0.01 --dynamics 0.15 0.3 0.15 --pd-offset 3.5 --init-from models/mimic_general_fast --total-steps 3000000 --checkpoint-every 100000 --speeds 0.9 1.0 1.1 --postures 2 --stances 1 --ground --swing-lift --denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --judge unslid_pose --lookahead 1 2 4 8 16 32 --lookbehind 1 2 4 8 16 32 --privileged-critic --critic-lr-scale 10 --seed 1845000
