#!/bin/bash
# usage: bench/rounds/r30/heldout_pv10.sh ROW   (ROW: slow or raw)
# Round 30: the held-out rows of a row PV10 led on validation and on its confirmation draws, once (seeds 1000-4000,
# the test split and the DeepMimic walkers), as round 29 scored PV (bench/rounds/r29/heldout_pv.sh).
cd "$(dirname "$0")/../../.."
W=$(cat runs/r28/PV10_candidate.txt)
case $1 in
  slow) QT=models/imu_denoiser_soles_quint_mirror
        SEEDS="1000 2000" bash bench/rounds/r24/heldout_slow.sh PV10 "$W" $QT --even-legs --part-legs &
        SEEDS="3000 4000" bash bench/rounds/r24/heldout_slow.sh PV10 "$W" $QT --even-legs --part-legs ;;
  raw)  bash bench/rounds/r23/heldout.sh PV10 "$W" --even-legs ;;
  *) echo "heldout_pv10.sh: ROW is slow or raw, got '$1'" >&2; exit 2 ;;
esac
wait
