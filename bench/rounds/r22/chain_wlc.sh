#!/bin/bash
# usage: bench/rounds/r22/chain_wlc.sh CANDIDATE_POLICY_DIR   (WLC against WCL: raw draws 900000+, clean, then confirmation 910000+)
cd "$(dirname "$0")/../../.." && mkdir -p runs/r22
P=$1
bench/rounds/r22/score_any.sh WCL models/mimic_general_clean_pose 900000 --no-denoise --part-legs &
bench/rounds/r22/score_any.sh WLC $P 900000 --no-denoise --part-legs
wait
bench/rounds/r22/clean_any.sh WLC $P --part-legs &
bench/rounds/r22/score_any.sh WCL models/mimic_general_clean_pose 910000 --no-denoise --part-legs
wait
bench/rounds/r22/score_any.sh WLC $P 910000 --no-denoise --part-legs
