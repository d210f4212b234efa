#!/bin/bash
# Round 37, as registered (amended 22:59 UTC): TX's newest checkpoint at 23:40 UTC (bench/rounds/r37/tx_cmd.sh's run; candidate.sh stops
# it with a checkpoint), made the turn policy (0.3 rad/s) of the set of that time (DXSET if it replaced the shipped
# set, else models/mimic_general_expert_set). Validation holds no turn (bench/results/round37_route_turns_val.json:
# none of its takes turns faster than 0.017 rad/s, 0.021 at the 1.25x pace of the shifted draws), so TXSET performs it
# as its base does; the rule reads DeepMimic's two training turns instead: TXSET replaces its base if its ELR on them,
# IMU strength 1, 20 rollouts each, is higher on both seeds 1910000 and 1920000. If it replaces it, its held-out rows
# once.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28 runs/r37
export MUJOCO_GL=egl OMP_NUM_THREADS=1
bash bench/rounds/r28/candidate.sh runs/r37/ppo_tx 2340 TX
# DXSET's decision first: its rule, and its confirmation if it leads
while [ ! -f bench/results/round37_select_DXSET_1860000.json ]; do sleep 20; done
if bash bench/rounds/rule_says.sh round37_select_DXSET_1860000 leads_by_rule; then
  while [ ! -f bench/results/round37_select_DXSET.json ]; do sleep 20; done
fi
BASE=models/mimic_general_expert_set; BASE_NAME=EXPERTSET2
if bash bench/rounds/replaced.sh round37_select_DXSET; then BASE=runs/r37/DXSET; BASE_NAME=DXSET; fi
.venv/bin/python bench/rounds/derived_set.py "$BASE" runs/r37/TXSET "turn=$(cat runs/r28/TX_candidate.txt)" \
  turn_rate_rad_s=0.3
echo runs/r37/TXSET > runs/r28/TXSET_candidate.txt
turns() {  # turns NAME SET SEED
  .venv/bin/python agents/evaluate.py --policy "$2" --mirror-average --denoise models/imu_denoiser_stances_quint_mirror \
    --denoise-slow 0.5 --even-legs --part-legs --ground --swing-lift --clips deepmimic:walker/turn_left0 \
    deepmimic:walker/turn_right0 --episodes 20 --per-clip --corrupt imu --strength 1 --seed "$3" \
    --json "bench/results/round37_turns_imu1_$1_$3.json" > "runs/r37/turns_$1_$3.log" 2>&1
}
for S in 1910000 1920000; do
  turns "$BASE_NAME" "$BASE" $S & turns TXSET runs/r37/TXSET $S; wait
done
.venv/bin/python - "$BASE_NAME" <<'PY'
import json, sys
base = sys.argv[1]
rows = {s: {n: json.load(open(f"bench/results/round37_turns_imu1_{n}_{s}.json"))["ELR_mean"] for n in (base, "TXSET")}
        for s in (1910000, 1920000)}
replaces = all(r["TXSET"] > r[base] for r in rows.values())
json.dump({"baseline": base, "candidate": "TXSET", "ELR": rows, "replaces_baseline": replaces},
          open("bench/results/round37_select_TXSET.json", "w"), indent=1)
print(rows, "TXSET replaces" if replaces else "TXSET does not replace", base)
PY
if bash bench/rounds/replaced.sh round37_select_TXSET; then
  DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh TXSET slow
fi
