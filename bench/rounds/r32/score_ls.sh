#!/bin/bash
# Round 32: scores LS as registered (amended at 08:00 UTC): waits for its candidate (bench/rounds/r28/candidate.sh
# runs/r32/ppo_ls 0850 LS), then LS and LU behind SQ on the style-shifted draws 1590000+ with their validation clean
# files and bench/select_policy.py's rule; if LS leads, the confirmation draws 1600000+ and the rule with them.
set -eo pipefail
cd "$(dirname "$0")/../../.."
LU=runs/r31/ppo_lu/checkpoints/step_4005888.zip
SQ=models/imu_denoiser_stances_quint_mirror
while [ ! -f runs/r28/LS_candidate.txt ]; do sleep 20; done
LS=$(cat runs/r28/LS_candidate.txt)
LABEL=" (mirror-averaged) + denoiser's hinge corrections slowed to 0.5 s + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm"
[ -f bench/results/round24_val_clean_LUSQ.json ] || bash bench/rounds/r24/clean_slow.sh LUSQ $LU $SQ --even-legs --part-legs
[ -f bench/results/round32_shifted_1590000_LU_SQ.json ] || bash bench/rounds/r32/shifted.sh LU_SQ $LU 1590000 $SQ
bash bench/rounds/r24/clean_slow.sh LS "$LS" $SQ --even-legs --part-legs &
CLEAN=$!
bash bench/rounds/r32/shifted.sh LS_SQ "$LS" 1590000 $SQ
wait $CLEAN
rule() {  # rule OUT [--confirm FILES...]
  local out=$1; shift
  (cd bench && ../.venv/bin/python select_policy.py --baseline "$LU$LABEL" --clean results/round24_val_clean_{LUSQ,LS}.json \
    --draws results/round32_shifted_1590000_{LU_SQ,LS_SQ}.json --draws-per-policy 20 "$@" --json "results/$out")
}
rule round32_select_LS_1590000.json
if grep -q "\"winner\": \"$LS" bench/results/round32_select_LS_1590000.json; then
  bash bench/rounds/r32/shifted.sh LU_SQ $LU 1600000 $SQ &
  BASE=$!
  bash bench/rounds/r32/shifted.sh LS_SQ "$LS" 1600000 $SQ
  wait $BASE
  rule round32_select_LS.json --confirm results/round32_shifted_1600000_{LU_SQ,LS_SQ}.json
fi
