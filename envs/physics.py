"""The simulation model of a mimic task at its physics rate (:attr:`envs.config.MimicConfig.physics_rate_hz`).

MuJoCo's contacts are soft: a contact's constraint relaxes with a time constant ``solref[0]`` that
MuJoCo never lets fall below two physics steps (its ``refsafe`` guard). Our humanoids ask for
0.01 s, so at their own 1/120 s step every floor contact runs at the 0.0167 s floor: a sole under
a stride's load sinks up to ~3 cm into the floor, and a rocking foot slides. A finer step is the
only way to stiffer contacts that stay stable (a time constant under two steps bounces:
``bench/physics_rate.py``), so :func:`at_physics_rate` sets both together.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np


def model_rate_hz(model: mujoco.MjModel) -> float:
    """The physics rate (Hz) of ``model``'s own timestep."""
    return 1.0 / model.opt.timestep


def contact_time_constants(model: mujoco.MjModel) -> np.ndarray:
    """``(ngeom,)`` the contact time constant (s) MuJoCo uses for each geom of ``model``: its
    ``solref[0]``, raised to two physics steps unless the ``refsafe`` guard is switched off."""
    asked = model.geom_solref[:, 0]
    if model.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_REFSAFE):
        return asked.copy()
    return np.maximum(asked, 2.0 * model.opt.timestep)


def at_physics_rate(model: mujoco.MjModel, rate_hz: float) -> mujoco.MjModel:
    """``model`` stepped at ``rate_hz``: itself when that is its own rate (within 1e-6), else a copy
    whose timestep is ``1 / rate_hz`` s and whose geoms' contact time constants are two of those
    steps (the stiffest MuJoCo keeps stable), none softer than the one MuJoCo gave it at its own rate.
    The damping ratio and impedance are kept. The model given is never changed (models are
    shared: :func:`reference_motion.humanoid.model.load_model` caches them)."""
    if not rate_hz > 0:
        raise ValueError(f"physics rate must be positive, got {rate_hz!r} Hz")
    if abs(rate_hz - model_rate_hz(model)) <= 1e-6 * rate_hz:
        return model
    fine = copy.deepcopy(model)
    fine.opt.timestep = 1.0 / rate_hz
    fine.geom_solref[:, 0] = np.minimum(contact_time_constants(model), 2.0 * fine.opt.timestep)
    return fine
