#!/bin/bash
# Round 33: scores LS2 as registered (docs/results.md, "Round 33"): LS carried on, its newest checkpoint at 11:35 UTC
# (bench/rounds/r28/candidate.sh runs/r32/ppo_ls 1135 LS2), against LS at 0.5 M steps (the shipped
# mimic_general_style_shifts), both behind SQ, on the style-shifted draws 1610000+ with their validation clean files
# and bench/select_policy.py's rule; if LS2 leads, the confirmation draws 1620000+ and the rule with them.
# The baseline's rows do not depend on the candidate: `score_ls2.sh base` makes them while the run trains.
set -eo pipefail
cd "$(dirname "$0")/../../.."
LS=runs/r32/ppo_ls/checkpoints/step_500000.zip
SQ=models/imu_denoiser_stances_quint_mirror
base() {
  [ -f bench/results/round24_val_clean_LS.json ] || bash bench/rounds/r24/clean_slow.sh LS $LS $SQ --even-legs --part-legs
  for S in 1610000 1620000; do
    [ -f bench/results/round32_shifted_${S}_LS_SQ.json ] || bash bench/rounds/r32/shifted.sh LS_SQ $LS $S $SQ
  done
}
if [ "$1" = base ]; then base; exit; fi
base
while [ ! -f runs/r28/LS2_candidate.txt ]; do sleep 20; done
LS2=$(cat runs/r28/LS2_candidate.txt)
LABEL=" (mirror-averaged) + denoiser's hinge corrections slowed to 0.5 s + legs evened + legs parted to 15 cm + grounded + swing lift 15 deg above 3 cm"
bash bench/rounds/r24/clean_slow.sh LS2 "$LS2" $SQ --even-legs --part-legs &
CLEAN=$!
bash bench/rounds/r32/shifted.sh LS2_SQ "$LS2" 1610000 $SQ
wait $CLEAN
rule() {  # rule OUT [--confirm FILES...]
  local out=$1; shift
  (cd bench && ../.venv/bin/python select_policy.py --baseline "$LS$LABEL" --clean results/round24_val_clean_{LS,LS2}.json \
    --draws results/round32_shifted_1610000_{LS_SQ,LS2_SQ}.json --draws-per-policy 20 "$@" --json "results/$out")
}
rule round33_select_LS2_1610000.json
if grep -q "\"winner\": \"$LS2" bench/results/round33_select_LS2_1610000.json; then
  bash bench/rounds/r32/shifted.sh LS2_SQ "$LS2" 1620000 $SQ
  rule round33_select_LS2.json --confirm results/round32_shifted_1620000_{LS_SQ,LS2_SQ}.json
fi
