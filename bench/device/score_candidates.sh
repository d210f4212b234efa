#!/bin/bash
# Lent-machine run of validation's registered choice (README "Wider stances": the rule, the
# confirmation, then the held-out sets once), every evaluation a process of its own on 16 cores.
# usage: [FIRST=100000] [CONFIRM=110000] [DRAWS=10] [DEN=DIR] bash bench/device/score_candidates.sh BASELINE CANDIDATE...
#  Each of BASELINE and CANDIDATE is an actor: a policy directory or checkpoint, then any of the actor
#  options evaluate.py and imu_draws.py share, in one quoted argument, e.g.
#  'models/mimic_general_privileged --mirror-average --ground --swing-lift' (validation's choice for IMU takes since
#  stop 60; 'models/mimic_general_stance_avg ...' alike before it).
#  1. each actor: validation clean (agents/evaluate.py, 20 rollouts per take) and DRAWS IMU draws behind
#     the denoiser DEN (default: validation's choice, models/imu_denoiser_soles_quint_mirror;
#     bench/imu_draws.py, one draw per process, seeds FIRST+); the rule (bench/select_policy.py) names
#     a winner.
#  2. if the winner is not the baseline: both on DRAWS more draws (seeds CONFIRM+). Meanwhile the winner's
#     held-out evaluations (test split and DeepMimic walkers; clean, IMU strength 1, IMU behind the
#     denoiser) run, and are deleted unread unless the winner leads the confirmation too.
# Carried as in heading_eval.sh: .whl/ (py3.12 wheels of mujoco, mujoco-core, mujoco-studio, glfw,
# pyopengl, websockets, gymnasium, stable-baselines3, farama-notifications) and .devpkgs/ (the stand-in
# pybullet_data; lib/ = data/library's manifest and the humanoid_1seg files of the takes scored here).
# Writes $OUT/choice.tar (the JSON and logs of steps 1 and 2) and, if the winner replaces the
# baseline, $OUT/heldout.tar.
set -u -o pipefail
[ $# -ge 2 ] || { echo "usage: [FIRST=S] [CONFIRM=S] [DRAWS=N] [DEN=DIR] bash $0 BASELINE CANDIDATE..." >&2; exit 2; }
BASE=$1; shift; CANDIDATES=("$@")
FIRST=${FIRST:-100000}; CONFIRM=${CONFIRM:-110000}; DRAWS=${DRAWS:-10}
HELDOUT=${HELDOUT:-1}  # 0: stop after the confirmation, the held-out sets untouched (smoke tests)
# rollouts (lower them only for a smoke test): per validation take, per take and draw, per test take, per walker
VAL_EPISODES=${VAL_EPISODES:-20}; DRAW_EPISODES=${DRAW_EPISODES:-2}; TEST_EPISODES=${TEST_EPISODES:-5}; WALKER_EPISODES=${WALKER_EPISODES:-20}
OUT=${OUT:-/tmp/score_candidates}; W=$(mktemp -d); mkdir -p $OUT $W/choice $W/heldout
PY=${PY:-python3}; JOBS=${JOBS:-$(nproc)}
source bench/device/setup.sh
VAL=library:data/library/val
DEN=${DEN:-models/imu_denoiser_soles_quint_mirror}
STRIDE=$($PY -c "from reference_motion.library import expand_clips; print(len(expand_clips(['$VAL'])))") || exit 1
name() { echo "$1" | tr '/. ' '___'; }
draw_jobs() {  # $1: first seed; the actors after it; one command per (actor, draw)
  local first=$1; shift
  for P in "$@"; do for j in $(seq 0 $((DRAWS - 1))); do
    echo "$PY bench/imu_draws.py --policies $P --clips $VAL --denoise $DEN --draws 1 --episodes $DRAW_EPISODES" \
         "--stride $STRIDE --first-seed $((first + j * STRIDE)) --json $W/choice/draws_${first}_$(name "$P")_$j.json"
  done; done
}
run_all() {  # $1: the log for the jobs' stderr; the commands on stdin, JOBS at a time; stops the script if one fails
  xargs -P $JOBS -I{} sh -c "{} > /dev/null 2>> $1" || { echo "a job failed; the end of $1:" >&2; tail -n 20 $1 >&2; exit 1; }
}
{
  for P in "$BASE" "${CANDIDATES[@]}"; do
    echo "$PY agents/evaluate.py --policy $P --clips $VAL --episodes $VAL_EPISODES --per-clip --json $W/choice/clean_$(name "$P").json"
  done
  draw_jobs $FIRST "$BASE" "${CANDIDATES[@]}"
} | run_all $W/choice/errors.log || exit 1
field() { $PY -c "import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$@"; }
BASE_LABEL=$(field $W/choice/clean_$(name "$BASE").json policy) || exit 1
select_rule() {  # the rule on the first draws; more arguments (--confirm FILES) go to select_policy.py
  $PY bench/select_policy.py --baseline "$BASE_LABEL" --draws-per-policy $DRAWS --clean $W/choice/clean_*.json \
    --draws $W/choice/draws_${FIRST}_*.json "$@"
}
select_rule --json $W/choice/rule.json | tee $W/choice/rule.txt || exit 1
tar -C $W -cf $OUT/choice.tar choice
WINNER_LABEL=$(field $W/choice/rule.json winner) || exit 1
WINNER=""
for P in "$BASE" "${CANDIDATES[@]}"; do  # the actor whose clean evaluation carries the winner's label
  [ "$(field $W/choice/clean_$(name "$P").json policy)" = "$WINNER_LABEL" ] && WINNER=$P
done
[ -n "$WINNER" ] || { echo "no actor is labelled '$WINNER_LABEL'" >&2; exit 1; }
[ "$(field $W/choice/rule.json leads_by_rule)" = True ] || { echo "the baseline stays; nothing held out is scored"; exit 0; }
WALKERS="deepmimic:walker/0walk_forward deepmimic:walker/turn_left1 deepmimic:walker/turn_right1"
EVAL="$PY agents/evaluate.py --policy $WINNER --per-clip"
IMU="--corrupt imu --strength 1 --seed 1000"
{
  draw_jobs $CONFIRM "$BASE" "$WINNER"
  if [ "$HELDOUT" = 1 ]; then
    echo "$EVAL --clips library:data/library/test --episodes $TEST_EPISODES --json $W/heldout/test_clean.json"
    echo "$EVAL --clips library:data/library/test --episodes $TEST_EPISODES $IMU --json $W/heldout/test_imu1.json"
    echo "$EVAL --clips library:data/library/test --episodes $TEST_EPISODES $IMU --denoise $DEN --json $W/heldout/test_imu1_den.json"
    echo "$EVAL --clips $WALKERS --episodes $WALKER_EPISODES --json $W/heldout/walkers_clean.json"
    echo "$EVAL --clips $WALKERS --episodes $WALKER_EPISODES $IMU --json $W/heldout/walkers_imu1.json"
    echo "$EVAL --clips $WALKERS --episodes $WALKER_EPISODES $IMU --denoise $DEN --json $W/heldout/walkers_imu1_den.json"
  fi
} | run_all $W/heldout/errors.log || { rm -rf $W/heldout; exit 1; }
select_rule --confirm $W/choice/draws_${CONFIRM}_*.json --json $W/choice/confirmed.json | tee $W/choice/confirmed.txt \
  || { rm -rf $W/heldout; exit 1; }
tar -C $W -cf $OUT/choice.tar choice
if [ "$HELDOUT" != 1 ]; then
  echo "HELDOUT=$HELDOUT: the held-out sets were not scored"
elif [ "$(field $W/choice/confirmed.json replaces_baseline)" = True ]; then
  tar -C $W -cf $OUT/heldout.tar heldout
  for f in $W/heldout/*.json; do
    $PY -c "import json, sys; d = json.load(open(sys.argv[1])); print(f\"{sys.argv[2]:<20} ELR {d['ELR_mean']:.3f}  SR90 {d['SR90']:.3f}\")" \
      $f $(basename $f .json)
  done
else
  rm -rf $W/heldout
  echo "the winner did not lead the confirmation: its held-out evaluations were deleted unread"
fi
