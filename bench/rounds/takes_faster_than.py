"""Print the library takes of a set and kinds whose median ground speed is above a threshold, space-separated.

Usage: ``python bench/rounds/takes_faster_than.py SET KINDS SPEED``, e.g.
``python bench/rounds/takes_faster_than.py library:data/library/train dash,run 3.0`` (the dash expert's training takes:
bench/rounds/r37/dx_cmd.sh, bench/rounds/r44/dxs_cmd.sh). Speed in m/s, the root's median horizontal speed on
the ``humanoid_1seg`` retarget, as the policy set routes by it (:func:`agents.policy_set.goes_fast`).
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from agents.policy_set import goes_fast  # noqa: E402
from reference_motion.motion import Motion  # noqa: E402
from reference_motion.motion_library import library_set, resolve_take  # noqa: E402

MODEL = "humanoid_1seg"


def takes_faster_than(take_set: str, kinds: tuple[str, ...], speed_mps: float) -> list[str]:
    """The takes of ``take_set`` of the given kinds whose median ground speed (m/s) is above ``speed_mps``: the policy
    set's fast rule (:func:`agents.policy_set.goes_fast`)."""
    return [take for take in library_set(take_set, kinds)
            if goes_fast(Motion.load(resolve_take(take, MODEL), model=MODEL), speed_mps)]


if __name__ == "__main__":
    usage = "usage: takes_faster_than.py SET KINDS SPEED (e.g. library:data/library/train dash,run 3.0)"
    if len(sys.argv) != 4:
        sys.exit(usage)
    try:
        threshold = float(sys.argv[3])
    except ValueError:
        sys.exit(f"takes_faster_than.py: SPEED is a number of m/s, got {sys.argv[3]!r}; {usage}")
    print(" ".join(takes_faster_than(sys.argv[1], tuple(sys.argv[2].split(",")), threshold)))
