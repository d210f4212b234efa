"""Round 52 probe: bench/imu_draws.py with foot_level.level_feet applied after --part-legs (ROLL=DEG sets its suit roll
spread; a tiny one levels the pitch only).

usage: [ROLL=1e-6] python bench/rounds/r52/draws_level.py IMU_DRAWS_ARGS..."""
import os
import runpy
import sys

sys.path.insert(0, "."); sys.path.insert(0, "bench"); sys.path.insert(0, "bench/rounds/r52")
import envs.preparation as prep
from foot_level import FootLevel, level_feet
_part = prep.part_legs
LEVEL = FootLevel(suit_roll_deg=float(os.environ.get("ROLL", 3.9)))
prep.part_legs = lambda take, legs: level_feet(_part(take, legs), LEVEL)
sys.argv = ["bench/imu_draws.py"] + sys.argv[1:]
runpy.run_path("bench/imu_draws.py", run_name="__main__")
