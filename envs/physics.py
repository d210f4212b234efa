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
from dataclasses import dataclass

import mujoco
import numpy as np

from envs.config import Dynamics


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


@dataclass(frozen=True)
class PhysicsDraw:
    """One draw of :class:`envs.config.Dynamics`: the factors one episode's humanoid gets.

    Attributes:
        mass: ``(nbody,)`` factor on each body's mass and inertia (the world body's included; it has none).
        friction: factor on every geom's sliding friction.
        strength: ``(nu,)`` factor on each actuator's ``kp`` and ``kv``.
        offset: ``(nu,)`` rad added to each actuator's PD target (``None``: none).
    """

    mass: np.ndarray
    friction: float
    strength: np.ndarray
    offset: np.ndarray | None = None

    @staticmethod
    def nominal(model: mujoco.MjModel) -> PhysicsDraw:
        """Every factor 1, no offset: ``model`` as it is."""
        return PhysicsDraw(np.ones(model.nbody), 1.0, np.ones(model.nu))


def draw_physics(dynamics: Dynamics, model: mujoco.MjModel, rng: np.random.Generator) -> PhysicsDraw:
    """Factors for one episode of ``model``, each uniform in ``1 ± `` its half-range in ``dynamics``."""
    def factors(half_range: float, n: int) -> np.ndarray:
        return rng.uniform(1.0 - half_range, 1.0 + half_range, n)

    offset = (np.radians(rng.uniform(-dynamics.offset_deg, dynamics.offset_deg, model.nu))
              if dynamics.offset_deg > 0 else None)
    return PhysicsDraw(mass=factors(dynamics.mass, model.nbody), friction=float(factors(dynamics.friction, 1)[0]),
                       strength=factors(dynamics.strength, model.nu), offset=offset)


def apply_physics(model: mujoco.MjModel, data: mujoco.MjData, nominal: mujoco.MjModel, draw: PhysicsDraw) -> None:
    """Write into ``model`` the fields of ``nominal`` (a model of the same humanoid, never changed)
    scaled by ``draw``: body masses and inertias, geom sliding friction, and the position
    actuators' ``kp`` (``gainprm[0]``, ``-biasprm[1]``) and ``kv`` (``-biasprm[2]``); a draw's
    target offset ``b`` becomes the constant force term ``biasprm[0] = kp·b``, so each actuator
    applies ``kp·(ctrl + b − q) − kv·q̇``. Then ``mujoco.mj_setConst`` (with ``data``, ``model``'s,
    as scratch: reset it before simulating) derives what MuJoCo keeps of the masses, the subtree
    masses it divides by for the centre of mass among them. Every other field of ``model`` is left
    as it is; the factors of a draw do not add up over calls.

    Raises:
        ValueError: the models' sizes differ from each other or from the draw's, or an actuator of
            ``nominal`` is not a position servo (fixed gain ``kp``, affine bias ``-kp·q - kv·q̇``).
    """
    sizes = (model.nbody, model.ngeom, model.nu)
    offset = np.zeros(model.nu) if draw.offset is None else draw.offset
    if (nominal.nbody, nominal.ngeom, nominal.nu) != sizes or (len(draw.mass), len(draw.strength), len(offset)) != (
            model.nbody, model.nu, model.nu):
        raise ValueError(f"apply_physics: model (nbody, ngeom, nu) = {sizes}, nominal "
                         f"{(nominal.nbody, nominal.ngeom, nominal.nu)}, draw for {len(draw.mass)} bodies and "
                         f"{len(draw.strength)} actuators ({len(offset)} offsets); they must match")
    servo = ((nominal.actuator_gaintype == mujoco.mjtGain.mjGAIN_FIXED)
             & (nominal.actuator_biastype == mujoco.mjtBias.mjBIAS_AFFINE)
             & np.isclose(nominal.actuator_biasprm[:, 1], -nominal.actuator_gainprm[:, 0]))
    if not servo.all():
        raise ValueError(f"apply_physics scales position servos' kp and kv; actuator(s) "
                         f"{np.flatnonzero(~servo).tolist()} of the nominal model are not (gaintype fixed, "
                         "biastype affine, biasprm[1] = -kp)")
    model.body_mass[:] = nominal.body_mass * draw.mass
    model.body_inertia[:] = nominal.body_inertia * draw.mass[:, None]
    model.geom_friction[:, 0] = nominal.geom_friction[:, 0] * draw.friction
    model.actuator_gainprm[:, 0] = nominal.actuator_gainprm[:, 0] * draw.strength
    model.actuator_biasprm[:, 1:3] = nominal.actuator_biasprm[:, 1:3] * draw.strength[:, None]
    model.actuator_biasprm[:, 0] = nominal.actuator_biasprm[:, 0] + model.actuator_gainprm[:, 0] * offset
    mujoco.mj_setConst(model, data)
