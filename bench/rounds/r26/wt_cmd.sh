#!/bin/bash
# Round 26, WT: WW's own student by DAgger (agents/distill.py --from-default, [512, 512]), taught the training
# dashes and runs it loses by the older specialists that perform them (bench/rounds/r26/wt_set: dash_active and
# dash_masculinity by models/mimic_dash_set's specialists, dash_musical, run_active and run_musical by
# models/mimic_general_taught; every other take by WW itself, as its symmetric actor), their states weighted 20x;
# references prepared as WW's training prepared them.
cd "$(dirname "$0")/../../.." && mkdir -p runs/r26
MUJOCO_GL=egl OMP_NUM_THREADS=1 .venv/bin/python agents/distill.py --teacher bench/rounds/r26/wt_set \
  --clips library:data/library/train deepmimic:walk deepmimic:run deepmimic:walker/turn_left0 deepmimic:walker/turn_right0 \
  --exclude 'library:data/library#02_04' 'library:data/library#02_05' 'library:data/library#02_06' \
    'library:data/library#02_07' 'library:data/library#02_08' 'library:data/library#02_09' 'library:data/library#02_10' \
  --mirror --warp '*walk-back*=1.25,1.5' --corrupted-fraction 0.75 --strength 0.75 1.5 --variants-per-clip 2 \
  --denoise models/imu_denoiser_soles_quint_mirror --denoise-slow 0.5 --even-legs --part-legs --ground --swing-lift \
  --mirror-average --plain-teachers active masculinity mimic_general_taught \
  --net 512,512 --from-default --rounds 4 \
  --teacher-weight active=20 masculinity=20 mimic_general_taught=20 --no-progress --out runs/r26/distill_wt \
  > runs/r26/distill_wt.log 2>&1
