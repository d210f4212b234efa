#!/bin/bash
# Round 34: scores QF5 as registered (docs/results.md, "Round 34"): waits for members 1-4
# (bench/rounds/r34/den_fast_seed.sh), makes QF5 (round 33's F and them, mirror-averaged), and scores LS (0.5 M) behind
# QF5 against LS behind SQ on the style-shifted draws 1660000+ by bench/select_denoiser.py's rule, each row on its own
# core; if QF5 leads, the same on the confirmation draws 1670000+. The held-out rows are run by hand, once, if it
# leads both.
set -eo pipefail
cd "$(dirname "$0")/../../.."
LS=runs/r32/ppo_ls/checkpoints/step_500000.zip
SQ=models/imu_denoiser_stances_quint_mirror
for N in 1 2 3 4; do
  while [ ! -f runs/r34/denoiser_fast_s$N/shipped/model.pt ] || pgrep -f "run-dir runs/r34/denoiser_fast_s$N( |$)" > /dev/null; do
    sleep 20
  done
done
[ -f runs/r34/QF5/model.pt ] || .venv/bin/python -m perception ensemble-denoisers runs/r33/denoiser_fast/shipped \
  runs/r34/denoiser_fast_s{1,2,3,4}/shipped --mirror-average --out runs/r34/QF5
rows() {  # rows SEED: the baseline's and the candidate's draws, side by side
  [ -f "bench/results/round32_shifted_$1_LS_SQ.json" ] || bash bench/rounds/r32/shifted.sh LS_SQ $LS "$1" $SQ &
  local BASE_JOB=$!
  bash bench/rounds/r32/shifted.sh LS_QF5 $LS "$1" runs/r34/QF5
  wait $BASE_JOB
}
rows 1660000
(cd bench && ../.venv/bin/python select_denoiser.py --baseline results/round32_shifted_1660000_LS_SQ.json \
  --candidates results/round32_shifted_1660000_LS_QF5.json --json results/round34_select_denoiser_QF5_1660000.json)
if bash bench/rounds/rule_says.sh round34_select_denoiser_QF5_1660000 leads_by_rule; then
  rows 1670000
  (cd bench && ../.venv/bin/python select_denoiser.py --baseline results/round32_shifted_1660000_LS_SQ.json \
    --candidates results/round32_shifted_1660000_LS_QF5.json --confirm-baseline results/round32_shifted_1670000_LS_SQ.json \
    --confirm results/round32_shifted_1670000_LS_QF5.json --json results/round34_select_denoiser_QF5.json)
fi
