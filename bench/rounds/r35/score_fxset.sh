#!/bin/bash
# Round 35, as registered: FX's newest checkpoint at 17:45 UTC (bench/rounds/r28/candidate.sh stops its run with a
# checkpoint), the policy set FXSET made of it (runs/r35/FXSET: takes faster than 2.0 m/s to FX, every other take to
# LSS at 0.5 M steps), scored against LSS behind SQ on validation clean and the style-shifted draws 1730000+,
# confirmed on 1740000+ if it leads (bench/rounds/score_shifted.sh), and if it leads both, its held-out rows once.
set -eo pipefail
cd "$(dirname "$0")/../../.."
LSS=runs/r34/ppo_lss/checkpoints/step_500000.zip
bash bench/rounds/r28/candidate.sh runs/r35/ppo_fx 1745 FX
.venv/bin/python -c "
import sys; from pathlib import Path; from agents.policy_set import PolicySet
PolicySet(Path('runs/r35/FXSET'), Path(sys.argv[1]), Path(sys.argv[1]), fast=Path(sys.argv[2]), fast_speed_mps=2.0).save()
" "$LSS" "$(cat runs/r28/FX_candidate.txt)"
echo runs/r35/FXSET > runs/r28/FXSET_candidate.txt
bash bench/rounds/score_shifted.sh "$LSS" LSS LSS_SQ FXSET 1730000 1740000 round35_select_FXSET
if bash bench/rounds/replaced.sh round35_select_FXSET; then
  DENOISER=models/imu_denoiser_stances_quint_mirror bash bench/rounds/r30/heldout.sh FXSET slow
fi
