#!/bin/bash
# Lent-machine A/B (README "On a lent machine"): resume the generalist with the learner on cuda vs cpu
# (8 shards each, side by side) for $1 s, then score both and the start on validation. Run from the
# repository root on the device with .whl/ (py3.12 wheels) and .devpkgs/ (pybullet_data stand-in,
# lib/ = data/library trimmed to train+val) carried.
set -u
SECS=${1:-300}
source bench/device/setup.sh
python3 -c "import mujoco, gymnasium, stable_baselines3, torch, numpy, sys; print(sys.version, numpy.__version__, mujoco.__version__, stable_baselines3.__version__, torch.__version__, torch.cuda.is_available())"
mkdir -p runs
for d in cuda cpu; do rm -rf runs/ab_$d; cp -r models/mimic_general/run runs/ab_$d; done
for d in cuda cpu; do
  timeout --foreground -s TERM $SECS python3 agents/train_ppo.py --run-dir runs/ab_$d --resume --vec sharded --n-envs 64 --workers 8 --device $d --torch-threads 1 --checkpoint-every 131072 --eval-every 100000000 --total-steps 15158592 --no-progress > $OUT/train_$d.log 2>&1 &
done
wait
mk() { rm -rf $2; mkdir -p $2; cp models/mimic_general/sidecar.json $2/; cp $1.zip $2/model.zip; cp ${1}_vecnormalize.pkl $2/model_vecnormalize.pkl; }
mk models/mimic_general/run/checkpoints/step_14699840 /tmp/pol_base
for d in cuda cpu; do Z=$(ls -t runs/ab_$d/checkpoints/*.zip | head -1); echo "$d newest $Z"; mk ${Z%.zip} /tmp/pol_$d; cp ${Z%.zip}* $OUT/; done
for p in base cuda cpu; do
  python3 agents/evaluate.py --policy /tmp/pol_$p --clips library:data/library/val --episodes 6 --json $OUT/eval_$p.json > $OUT/eval_$p.log 2>&1 &
done
wait
for p in base cuda cpu; do python3 -c "import json;d=json.load(open('$OUT/eval_$p.json'));s=d.get('summary',d);print('$p',{k:s[k] for k in ('ELR_mean','SR90','MRR_mean') if k in s})"; done
tail -3 $OUT/train_*.log
