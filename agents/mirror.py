"""A mirror-symmetric actor: a policy's action averaged with its action on the mirrored observation.

PPO trains on every clip and its mirror image (``train_ppo.py --mirror``), but nothing makes the
network itself symmetric: given an observation and the same observation mirrored, its two actions,
mapped onto each other, can differ by more than the action range, and a policy that favours one
side veers off a take it should walk straight. :class:`MirrorAveraged` acts with

    a(o) = ½ (π(o) + M_a π(M_o o)),

where ``M_o`` mirrors an observation (left and right bodies swapped, lateral components negated)
and ``M_a`` an action (left and right hinges swapped, hinges about x and z negated): an exactly
mirror-symmetric policy from the same weights, at twice the network's cost per step. The maps
(:class:`MirrorMaps`) are those of the left/right mirror about the x–z plane
(:func:`reference_motion.transforms.mirror`), which the environment reproduces exactly: the
observation of a mirrored clip's state is the mirrored observation (``tests/test_mirror.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import gymnasium as gym
import numpy as np

from envs.mimic import actuator_qpos
from envs.observations import WINDOW_PARTS, window_step_size
from reference_motion.transforms import mirror_map, mirror_twin

if TYPE_CHECKING:
    from agents.rollout import Policy

LATERAL_VECTORS = ("v_com", "ref_v_com", "dv_com", "ref_v_hor", "dv_hor", "dp_com")
"""Observation slices that are one vector (x, y[, z]) each: under the mirror only y changes sign."""
BODY_VECTORS = ("p", "v", "dp", "dv")
"""Observation slices holding one 3-vector per observed body."""


@dataclass(frozen=True)
class MirrorMaps:
    """Index permutation and sign of the observation ``(D,)`` and the action ``(A,)`` under the
    left/right mirror: ``mirrored = x[perm] * sign``. Each map is its own inverse."""

    obs_perm: np.ndarray
    obs_sign: np.ndarray
    action_perm: np.ndarray
    action_sign: np.ndarray

    def __post_init__(self) -> None:
        """Take the fields as arrays (integer permutations, float32 signs) and raise a clear
        ``ValueError`` unless each map is a signed permutation (signs ±1) that undoes itself
        (``perm[perm]`` the identity, ``sign[perm] == sign``), as a left/right mirror does: the
        symmetric actor and a policy's mirror image rely on it."""
        for what, perm_field, sign_field in (("observation", "obs_perm", "obs_sign"),
                                             ("action", "action_perm", "action_sign")):
            perm, sign = np.asarray(getattr(self, perm_field)), np.asarray(getattr(self, sign_field), dtype=np.float32)
            if perm.ndim != 1 or perm.shape != sign.shape:
                raise ValueError(f"the {what} map's perm {perm.shape} and sign {sign.shape} must be one "
                                 f"vector each, of the same length")
            if not np.issubdtype(perm.dtype, np.integer) or sorted(perm.tolist()) != list(range(len(perm))):
                raise ValueError(f"the {what} map's perm is not a permutation of the integers 0..{len(perm) - 1}")
            if not np.all(np.abs(sign) == 1.0):
                raise ValueError(f"the {what} map's signs must be +1 or -1")
            if not (np.array_equal(perm[perm], np.arange(len(perm))) and np.array_equal(sign[perm], sign)):
                raise ValueError(f"the {what} map is not its own inverse (perm[perm] must be the identity "
                                 f"and sign[perm] equal sign); a left/right mirror is")
            object.__setattr__(self, perm_field, perm)  # frozen: set once, here
            object.__setattr__(self, sign_field, sign)

    @classmethod
    def of(cls, env: gym.Env) -> MirrorMaps:
        """The maps of a mimic environment's observation and action (``MimicIMU-v0`` and its
        ablations: the 8 key joints or every hinge, ADAPT's or DReCon's bodies, any observation
        frame, with or without the reference around now). A clear ``ValueError`` for a layout it
        does not know (``MimicGait-v0``'s contact and toe inputs)."""
        base = env.unwrapped
        slices = getattr(base, "obs_slices", None)
        known = set(LATERAL_VECTORS) | set(BODY_VECTORS) | set(WINDOW_PARTS) | {"prev_action"}
        if slices is None or not set(slices) <= known:
            extra = sorted(set(slices or {}) - known) or ["no obs_slices"]
            raise ValueError(f"{base.spec.id if base.spec else type(base).__name__}: the mirror-symmetric actor "
                             f"knows the mimic observation ({', '.join(sorted(known))}), not {', '.join(extra)}")
        names = list(base.humanoid.body_names)
        observed = names if isinstance(base.observed, slice) else [names[i] for i in base.observed]
        if sorted(mirror_twin(n) for n in observed) != sorted(observed):
            raise ValueError(f"the observed bodies {observed} are not closed under the mirror")
        size = base.observation_space.shape[0]
        obs_perm, obs_sign = np.arange(size), np.ones(size, dtype=np.float32)
        for name in LATERAL_VECTORS:
            if name in slices:
                obs_sign[slices[name].start + 1] = -1.0
        twins = [observed.index(mirror_twin(body)) for body in observed]

        def mirror_bodies(start: int) -> None:  # one 3-vector per observed body from ``start``
            for b, twin in enumerate(twins):
                obs_perm[start + 3 * b:start + 3 * b + 3] = np.arange(start + 3 * twin, start + 3 * twin + 3)
                obs_sign[start + 3 * b + 1] = -1.0

        for name in BODY_VECTORS:
            mirror_bodies(slices[name].start)
        per_step = window_step_size(len(observed))
        for name in WINDOW_PARTS:
            if name in slices:
                for start in range(slices[name].start, slices[name].stop, per_step):
                    obs_sign[[start + 1, start + 4]] = -1.0  # the CoM's shift and velocity
                    mirror_bodies(start + 6)
        hinge_qpos = actuator_qpos(base.humanoid.model)[base.driven]
        qpos_perm, qpos_sign = mirror_map(base.humanoid.name)
        component = {int(q): k for k, q in enumerate(hinge_qpos)}
        unmatched = [base.humanoid.hinge_names[q - 7] for q in hinge_qpos if int(qpos_perm[q]) not in component]
        if unmatched:
            raise ValueError(f"the driven hinges are not closed under the mirror: the twins of {unmatched} are not driven")
        action_perm = np.array([component[int(qpos_perm[q])] for q in hinge_qpos])
        action_sign = qpos_sign[hinge_qpos].astype(np.float32)
        start = slices["prev_action"].start
        obs_perm[start:start + len(action_perm)] = start + action_perm
        obs_sign[start:start + len(action_perm)] = action_sign
        return cls(obs_perm, obs_sign, action_perm, action_sign)

    def leading(self, size: int) -> MirrorMaps:
        """The maps of the observation's first ``size`` values (the same action map): those of a
        policy observing the layout without what follows, as a teacher reads a student's
        observation without its reference window (``agents/distill.py --lookahead``); ``size`` equal
        to the whole observation gives these maps (a teacher whose window is the student's). A clear
        ``ValueError`` where the mirror moves a value across ``size``."""
        perm = self.obs_perm[:size]
        if len(perm) != size or (size and perm.max() >= size):
            raise ValueError(f"the observation's first {size} values are not closed under the mirror "
                             f"(it has {len(self.obs_perm)})")
        return MirrorMaps(perm, self.obs_sign[:size], self.action_perm, self.action_sign)

    def observation(self, obs: np.ndarray) -> np.ndarray:
        """The mirrored observation ``(..., D)`` of ``obs (..., D)`` (one, or a batch)."""
        return obs[..., self.obs_perm] * self.obs_sign

    def action(self, action: np.ndarray) -> np.ndarray:
        """The mirrored action ``(..., A)`` of ``action (..., A)`` (one, or a batch)."""
        return action[..., self.action_perm] * self.action_sign

    def averaged(self, action: np.ndarray, action_on_mirrored: np.ndarray) -> np.ndarray:
        """The symmetric actor's action ``(..., A)``: the mean of a policy's ``action`` on an
        observation and, mapped back, its ``action_on_mirrored`` on that observation's mirror image."""
        return 0.5 * (np.asarray(action) + self.action(np.asarray(action_on_mirrored)))


class MirrorAveraged:
    """``policy``'s action averaged with its action on the mirrored observation, mapped back
    (the module's equation): one raw observation ``(D,)`` → an action ``(A,)`` (rad), exactly
    mirror symmetric. ``maps``: :meth:`MirrorMaps.of` the environment the policy acts in. Any
    actor (an ensemble, ...); a :class:`~agents.policy.MimicPolicy` also acts so by itself after
    :meth:`~agents.policy.MimicPolicy.mirror_averaged`."""

    def __init__(self, policy: Policy, maps: MirrorMaps):
        self.policy, self.maps = policy, maps

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return self.maps.averaged(self.policy(obs), self.policy(self.maps.observation(obs)))


def actor_label(policy: object, mirror_average: bool) -> str:
    """How results name a policy's actor: its path, marked when the symmetric actor acted (so
    ``bench/select_policy.py`` tells the two apart)."""
    return f"{policy} (mirror-averaged)" if mirror_average else str(policy)
