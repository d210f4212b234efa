"""Time spent in MuJoCo's ``mj_step`` alone, inside any code that steps the physics (an
environment's episodes, a PPO run): the raw-physics floor the throughput benchmarks report beside
the end-to-end rate. Shared by ``env_throughput.py`` and ``ppo_throughput.py``; the scripts run
from ``bench/``.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

import mujoco


class PhysicsTime:
    """Seconds spent in ``mj_step`` while :func:`timing_mj_step` was active (``busy_s``)."""

    def __init__(self) -> None:
        self.busy_s = 0.0


@contextmanager
def timing_mj_step() -> Iterator[PhysicsTime]:
    """Within the block every call of ``mujoco.mj_step``, whoever makes it, is timed; the block
    yields the running total. ``mujoco.mj_step`` is restored afterwards."""
    raw_step, spent = mujoco.mj_step, PhysicsTime()

    def timed_step(model, data, nstep=1):
        start = time.perf_counter()
        raw_step(model, data, nstep=nstep)
        spent.busy_s += time.perf_counter() - start

    mujoco.mj_step = timed_step
    try:
        yield spent
    finally:
        mujoco.mj_step = raw_step
