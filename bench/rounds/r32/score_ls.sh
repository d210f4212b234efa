#!/bin/bash
# Round 32: scores LS as registered (amended at 08:00 UTC): waits for its candidate (bench/rounds/r28/candidate.sh
# runs/r32/ppo_ls 0850 LS), then LS and LU behind SQ on the style-shifted draws 1590000+ with their validation clean
# files and bench/select_policy.py's rule; if LS leads, the confirmation draws 1600000+ and the rule with them
# (bench/rounds/score_shifted.sh; bench/results/round32_select_LS_1590000.json, round32_select_LS.json).
cd "$(dirname "$0")/../../.."
exec bash bench/rounds/score_shifted.sh runs/r31/ppo_lu/checkpoints/step_4005888.zip LUSQ LU_SQ LS 1590000 1600000 \
  round32_select_LS
