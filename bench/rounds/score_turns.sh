#!/bin/bash
# usage: bench/rounds/score_turns.sh ROUND BASE_NAME BASE CAND_NAME CAND SEED1 SEED2
# The turn rule of round 37 on (validation holds no turn): the policy sets BASE and CAND perform DeepMimic's two
# training turns (walker/turn_left0, walker/turn_right0) behind the stances denoiser, IMU strength 1, 20 rollouts each,
# with seeds SEED1 and SEED2 (bench/results/roundROUND_turns_imu1_NAME_SEED.json, logs in runs/rROUND/); CAND replaces
# BASE if its ELR is higher with both seeds (bench/results/roundROUND_select_CAND_NAME.json, replaces_baseline).
# With DENOISER set empty (DENOISER= bash bench/rounds/score_turns.sh ...), both sets track the turns as the suit gave
# them, with the raw rows' preparation (no denoiser in front; since round 54); DENOISER unset is the stances denoiser's
# slow corrections, and any other value is refused.
set -eo pipefail
cd "$(dirname "$0")/../.."
[ $# -eq 7 ] || { echo "usage: score_turns.sh ROUND BASE_NAME BASE CAND_NAME CAND SEED1 SEED2" >&2; exit 2; }
R=$1; BASE_NAME=$2; BASE=$3; CAND_NAME=$4; CAND=$5; SEEDS=("$6" "$7")
export MUJOCO_GL=egl OMP_NUM_THREADS=1
DENOISE=(--denoise models/imu_denoiser_stances_quint_mirror --denoise-slow 0.5)
if [ -n "${DENOISER+set}" ]; then  # the raw rows
  [ -z "$DENOISER" ] || { echo "score_turns.sh: DENOISER is empty (the raw rows) or unset, got '$DENOISER'" >&2
                          exit 2; }
  DENOISE=()
fi
mkdir -p "runs/r$R"
turns() {  # turns NAME SET SEED
  .venv/bin/python agents/evaluate.py --policy "$2" --mirror-average "${DENOISE[@]}" \
    --even-legs --part-legs --ground --swing-lift --clips deepmimic:walker/turn_left0 \
    deepmimic:walker/turn_right0 --episodes 20 --per-clip --corrupt imu --strength 1 --seed "$3" \
    --json "bench/results/round${R}_turns_imu1_$1_$3.json" > "runs/r$R/turns_$1_$3.log" 2>&1
}
for S in "${SEEDS[@]}"; do
  turns "$BASE_NAME" "$BASE" "$S" & turns "$CAND_NAME" "$CAND" "$S"; wait
done
.venv/bin/python - "$R" "$BASE_NAME" "$CAND_NAME" "${SEEDS[@]}" <<'PY'
import json, sys
from reference_motion.atomic import write_json
r, base, cand, *seeds = sys.argv[1:]
rows = {s: {n: json.load(open(f"bench/results/round{r}_turns_imu1_{n}_{s}.json"))["ELR_mean"] for n in (base, cand)}
        for s in seeds}
replaces = all(row[cand] > row[base] for row in rows.values())
write_json(f"bench/results/round{r}_select_{cand}.json",  # atomic: later scripts poll for it
           {"baseline": base, "candidate": cand, "ELR": rows, "replaces_baseline": replaces})
print(rows, f"{cand} replaces" if replaces else f"{cand} does not replace", base)
PY
