#!/bin/bash
# Round 33: scores QSF as registered (docs/results.md, "Round 33"): waits for F (bench/rounds/r33/den_fast_cmd.sh),
# makes QSF (SQ with its first member replaced by F), and scores LS (0.5 M) behind QSF against LS behind SQ on the
# style-shifted draws 1640000+ by bench/select_denoiser.py's rule.
set -eo pipefail
cd "$(dirname "$0")/../../.."
LS=runs/r32/ppo_ls/checkpoints/step_500000.zip
SQ=models/imu_denoiser_stances_quint_mirror
while [ ! -f runs/r33/denoiser_fast/shipped/model.pt ] || pgrep -f "run-dir runs/r33/denoiser_fast( |$)" > /dev/null; do
  sleep 20
done
[ -d runs/r33/sq_members/m4 ] || .venv/bin/python bench/rounds/r24/split_quint.py $SQ runs/r33/sq_members
.venv/bin/python -m perception ensemble-denoisers runs/r33/denoiser_fast/shipped runs/r33/sq_members/m{1,2,3,4} \
  --mirror-average --out runs/r33/QSF
[ -f bench/results/round32_shifted_1640000_LS_SQ.json ] || bash bench/rounds/r32/shifted.sh LS_SQ $LS 1640000 $SQ
bash bench/rounds/r32/shifted.sh LS_QSF $LS 1640000 runs/r33/QSF
(cd bench && ../.venv/bin/python select_denoiser.py --baseline results/round32_shifted_1640000_LS_SQ.json \
  --candidates results/round32_shifted_1640000_LS_QSF.json --json results/round33_select_denoiser_QSF_1640000.json)
