#!/bin/bash
# usage: bench/rounds/r47/score_raw.sh
# Round 47, RAWSET: the shipped policy set (models/mimic_general_expert_set) tracking IMU takes with no denoiser in
# front, the rows "no denoiser", against the raw rows' choice since round 29, PV (models/mimic_general_asymmetric),
# both with the raw rows' preparation (--mirror-average --even-legs --part-legs --ground --swing-lift). Scored by
# bench/rounds/score_shifted.sh with DENOISER empty: validation clean with that preparation (round23_val_clean_{PVSHIP,
# RAWSET}.json) and validation's style-shifted IMU draws 2190000+ with none in front (round32_shifted_2190000_{PV_RAW,
# RAWSET_RAW}.json), confirmed on 2200000+ if it leads (the rules bench/results/round47_select_RAWSET_2190000.json and
# round47_select_RAWSET.json). Nothing else is chosen on these draws. If it replaces PV, its held-out rows are scored
# once, by hand: bench/rounds/r30/heldout.sh RAWSET raw.
set -eo pipefail
cd "$(dirname "$0")/../../.." && mkdir -p runs/r28
echo models/mimic_general_expert_set > runs/r28/RAWSET_candidate.txt
DENOISER= exec bash bench/rounds/score_shifted.sh models/mimic_general_asymmetric PVSHIP PV_RAW RAWSET 2190000 2200000 \
  round47_select_RAWSET
