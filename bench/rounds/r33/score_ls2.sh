#!/bin/bash
# Round 33: scores LS2 as registered (docs/results.md, "Round 33"): LS carried on, its newest checkpoint at 11:35 UTC
# (bench/rounds/r28/candidate.sh runs/r32/ppo_ls 1135 LS2), against LS at 0.5 M steps (the shipped
# mimic_general_style_shifts), both behind SQ, on the style-shifted draws 1610000+ with their validation clean files
# and bench/select_policy.py's rule; if LS2 leads, the confirmation draws 1620000+ and the rule with them
# (bench/rounds/score_shifted.sh). The baseline's rows do not depend on the candidate: `score_ls2.sh base` makes them
# while the run trains.
cd "$(dirname "$0")/../../.."
case "$1" in
  "") MODE=() ;;
  base) MODE=(--base-only) ;;
  *) echo "score_ls2.sh: expected no argument or 'base', got '$1'" >&2; exit 2 ;;
esac
exec bash bench/rounds/score_shifted.sh "${MODE[@]}" runs/r32/ppo_ls/checkpoints/step_500000.zip LS LS_SQ LS2 1610000 \
  1620000 round33_select_LS2
