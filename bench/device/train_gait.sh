#!/bin/bash
# Lent-machine gait training (README "Gait reconstruction"): resume models/mimic_gait_ff/run (or a carried
# newer checkpoint in .devpkgs/gckpt/) for $1 s on 16 shards with the learner on the GPU; carried as in gpu_ab.sh
# (.devpkgs/lib holding humanoid_2seg of the 24 Bandai walks it trains and validates on).
set -u
SECS=${1:-500}
source bench/device/setup.sh
mkdir -p runs && ln -sfn library data/library_level
rm -rf runs/gait && cp -r models/mimic_gait_ff/run runs/gait
[ -d .devpkgs/gckpt ] && cp .devpkgs/gckpt/step_* runs/gait/checkpoints/ && cp .devpkgs/gckpt/args.json .devpkgs/gckpt/evaluations.jsonl runs/gait/ && cp .devpkgs/gckpt/wall.json runs/gait/ 2>/dev/null
[ -d .devpkgs/gckpt/best ] && cp -r .devpkgs/gckpt/best runs/gait/
ls runs/gait/checkpoints
timeout --foreground -s TERM $SECS python3 agents/train_ppo.py --run-dir runs/gait --resume --vec sharded --n-envs 64 --workers 16 --device cuda --torch-threads 1 --checkpoint-every 262144 --eval-every 500000 --eval-episodes 3 --no-progress > /tmp/train.log 2>&1
echo "train rc=$?"; grep -v "^$" /tmp/train.log | tail -8
mkdir -p $OUT/gckpt; Z=$(ls -t runs/gait/checkpoints/*.zip | head -1); cp $Z ${Z%.zip}_vecnormalize.pkl $OUT/gckpt/
cp runs/gait/evaluations.jsonl runs/gait/args.json runs/gait/wall.json $OUT/gckpt/ 2>/dev/null
[ -d runs/gait/best ] && cp -r runs/gait/best $OUT/gckpt/
tail -4 runs/gait/evaluations.jsonl | cut -c1-200
