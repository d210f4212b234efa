#!/bin/bash
# usage: bench/rounds/r29/heldout_pv.sh ROW   (ROW: slow or raw)
# Round 29: the held-out rows of a row PV led on validation and on its confirmation draws, once (seeds 1000-4000, the
# test split and the DeepMimic walkers), two seeds at a time on the two cores, as round 26 scored WW.
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/PV_candidate.txt)
case $1 in
  slow) QT=models/imu_denoiser_soles_quint_mirror
        SEEDS="1000 2000" bash bench/rounds/r24/heldout_slow.sh PV "$W" $QT --even-legs --part-legs &
        SEEDS="3000 4000" bash bench/rounds/r24/heldout_slow.sh PV "$W" $QT --even-legs --part-legs ;;
  raw)  bash bench/rounds/r23/heldout.sh PV "$W" --even-legs ;;
  *) echo "heldout_pv.sh: ROW is slow or raw, got '$1'" >&2; exit 2 ;;
esac
wait
