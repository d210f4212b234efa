#!/bin/bash
# usage: bench/rounds/r30/heldout.sh NAME ROW   (ROW: slow or raw)
# The held-out rows of a row a registered candidate NAME (its checkpoint in runs/r28/NAME_candidate.txt) led on
# validation and on its confirmation draws, once (seeds 1000-4000, the test split and the DeepMimic walkers), as
# round 29 scored PV (bench/rounds/r29/heldout_pv.sh); later rounds call this one rather than a copy. DENOISER=DIR puts
# another denoiser in front of the slow row (default: imu_denoiser_soles_quint_mirror); DENOISE_SLOW= (empty) tracks
# behind its full corrections (bench/rounds/r24/heldout_slow.sh; the files keep the name "slow").
cd "$(dirname "$0")/../../.."
N=$1
W=$(cat "runs/r28/${N}_candidate.txt") || exit 1
case $2 in
  slow) D=${DENOISER:-models/imu_denoiser_soles_quint_mirror}
        SEEDS="1000 2000" bash bench/rounds/r24/heldout_slow.sh "$N" "$W" "$D" --even-legs --part-legs &
        FIRST=$!
        SEEDS="3000 4000" bash bench/rounds/r24/heldout_slow.sh "$N" "$W" "$D" --even-legs --part-legs || exit 1
        wait $FIRST || exit 1 ;;
  raw)  bash bench/rounds/r23/heldout.sh "$N" "$W" --even-legs || exit 1 ;;
  *) echo "heldout.sh: ROW is slow or raw, got '$2'" >&2; exit 2 ;;
esac
