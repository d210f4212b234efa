"""The mimic observation of adapt Table 1, as a pure function of simulated and reference arrays.

Layout (``B`` observed bodies, ``A`` action size; SI; world axes, or the heading frame below):

============  ====  =====================================================================
name          size  content
============  ====  =====================================================================
v_com         3     CoM velocity of the character
ref_v_com     3     CoM velocity of the reference
dv_com        3     v_com − ref_v_com
ref_v_hor     2     horizontal (x, y) CoM velocity of the reference
dv_hor        2     horizontal CoM velocity of the character − ref_v_hor
dp_com        3     (heading frame, or ``com_offset``) the character's CoM − the reference's CoM
p             3B    body origins relative to the character's CoM
v             3B    body origin velocities
dp            3B    p − the reference's body origins relative to its CoM
dv            3B    v − the reference's body velocities
prev_action   A     the smoothed action of the previous step
lookahead     K·L   (``MimicConfig.lookahead``, K future control steps; L = 6 + 3B) per step:
                    the reference CoM's displacement from its current position (3), its
                    CoM velocity (3) and its body origins relative to its CoM (3B)
lookbehind    K'·L  (``MimicConfig.lookbehind``, K' past control steps) per step: the same
============  ====  =====================================================================

With all 20 bodies and the 20-D key-joint action this is the 273-D state of ADAPT.

Frames (:data:`OBS_FRAMES`): ADAPT expresses every vector in world axes (``"world"``, adapt
§3.2.1), so the same step walked towards +x and towards +y are different inputs and a policy must
learn each heading apart; nor does it see how far the character has drifted from the reference,
although the lag termination is on exactly that distance. ``"heading"`` rotates every vector
into the character's heading frame (z up, x = the pelvis x axis on the ground, as DeepMimic and
DReCon observe) and adds ``dp_com``, so the observation is the same whatever way the clip walks
and shows the drift the policy must correct. ``"reference"`` keeps ADAPT's layout but turns its
axes about z with the reference: x is the reference pelvis's x axis on the ground at the current
frame. Every clip starts facing +x (the library's convention), so a policy trained in world axes
has seen most of its states facing about +x and performs a clip walked another way, or a turn
that comes round, far worse (``bench/heading_frames.py``: the shipped generalist on DeepMimic's
walk turned 90° survives half as long); in the reference's axes every clip walks towards +x. It
observes nothing the world frame does not, so a world-frame policy runs in it as it is.
``MimicConfig.steer_gain_hz`` leaves the layout as it is but adds a pull back towards the
reference's position to every reference velocity it shows (``ref_v_com``, and so ``dv_com``,
``ref_v_hor``, ``dv_hor`` and ``dv``; :func:`steered_velocities`), so the drift shows up as a
velocity error. ``MimicConfig.com_offset`` adds ``dp_com`` to the world-frame observation alone
(a policy trained on ADAPT's layout can be widened to it, see :func:`agents.warm_start.widen_inputs`).
"""

from __future__ import annotations

import numpy as np

OBS_FRAMES = ("world", "heading", "reference")
"""Axes the observation's vectors are expressed in (module docstring)."""

SAME_LAYOUT_FRAMES = ("world", "reference")
"""Frames whose observations have the same layout and meaning up to a turn about z: a policy
trained in one runs, or is warm-started, in the other as it is."""


def same_layout(frame: str, other: str) -> bool:
    """Whether a policy observing in ``frame`` can observe in ``other`` as it is: the same frame,
    or two of :data:`SAME_LAYOUT_FRAMES`."""
    return frame == other or {frame, other} <= set(SAME_LAYOUT_FRAMES)


WINDOW_PARTS = ("lookahead", "lookbehind")
"""Observation slices holding other reference frames than the current one (the reference window),
in the order they end the observation; each step :func:`window_step_size` values."""


def window_step_size(n_bodies: int) -> int:
    """Values per step of the reference window: the CoM's shift (3) and velocity (3), then one
    3-vector per observed body (:func:`lookahead_observation`)."""
    return 6 + 3 * n_bodies


def observation_slices(n_bodies: int, n_action: int, com_offset: bool = False,
                       lookahead_steps: int = 0, lookbehind_steps: int = 0) -> dict[str, slice]:
    """Named slices of the observation vector (the module table, in order); ``com_offset``: with
    ``dp_com`` (the ``heading`` frame's layout); ``lookahead_steps`` / ``lookbehind_steps``: how
    many future / past reference steps it shows (``lookahead`` / ``lookbehind``, absent for 0)."""
    per_step = window_step_size(n_bodies)
    sizes = {"v_com": 3, "ref_v_com": 3, "dv_com": 3, "ref_v_hor": 2, "dv_hor": 2,
             **({"dp_com": 3} if com_offset else {}), "p": 3 * n_bodies, "v": 3 * n_bodies, "dp": 3 * n_bodies, "dv": 3 * n_bodies,
             "prev_action": n_action, **({"lookahead": lookahead_steps * per_step} if lookahead_steps else {}),
             **({"lookbehind": lookbehind_steps * per_step} if lookbehind_steps else {})}
    out, start = {}, 0
    for name, size in sizes.items():
        out[name] = slice(start, start + size)
        start += size
    return out


def observation_size(n_bodies: int, n_action: int, com_offset: bool = False, lookahead_steps: int = 0,
                     lookbehind_steps: int = 0) -> int:
    """Length of the observation: 13 + 12·B + A (+ 3 with ``dp_com``, + K·(6 + 3B) for K lookahead
    and lookbehind steps together)."""
    return (13 + 12 * n_bodies + n_action + (3 if com_offset else 0)
            + (lookahead_steps + lookbehind_steps) * window_step_size(n_bodies))


def heading_rotation(root_x_axis: np.ndarray) -> np.ndarray:
    """``(..., 3, 3)`` rotation taking world vectors into the heading frame of a root whose x axis is
    ``root_x_axis (..., 3)`` (world): a yaw about world z that turns that axis's ground projection
    onto +x. A root x axis pointing straight up or down (no heading) gives the identity."""
    x, y = root_x_axis[..., 0], root_x_axis[..., 1]
    norm = np.hypot(x, y)
    level = norm >= 1e-9
    safe = np.where(level, norm, 1.0)
    c, s = np.where(level, x / safe, 1.0), np.where(level, y / safe, 0.0)
    zero, one = np.zeros_like(c), np.ones_like(c)
    return np.stack([np.stack([c, s, zero], -1), np.stack([-s, c, zero], -1), np.stack([zero, zero, one], -1)], -2)


def _in_frame(vectors: np.ndarray, rotation: np.ndarray | None, leading: int) -> np.ndarray:
    """``vectors (..., [K,] 3)`` rotated by ``rotation (..., 3, 3)`` (``None``: unchanged); ``leading``
    is the number of batch axes, so a ``(..., K, 3)`` array rotates each of its ``K`` rows."""
    if rotation is None:
        return vectors
    if vectors.ndim == leading + 1:
        return np.einsum("...ij,...j->...i", rotation, vectors)
    return np.einsum("...ij,...kj->...ki", rotation, vectors)


def mimic_observation(pos: np.ndarray, linvel: np.ndarray, com: np.ndarray, com_vel: np.ndarray,
                      ref_pos_rel: np.ndarray, ref_linvel: np.ndarray, ref_com_vel: np.ndarray,
                      prev_action: np.ndarray, heading: np.ndarray | None = None,
                      ref_com: np.ndarray | None = None) -> np.ndarray:
    """Observation vector ``(13 + 12·B + A,)`` float32 (world frame), ``(16 + 12·B + A,)`` with
    ``dp_com`` when ``ref_com`` is given (in the heading frame when ``heading`` is given). Every
    argument may have leading batch axes (the same on all), which the result then has too.

    Args:
        pos, linvel: ``(B, 3)`` the character's observed body origins and their velocities (world, m, m/s).
        com, com_vel: ``(3,)`` the character's CoM and its velocity (world).
        ref_pos_rel: ``(B, 3)`` the reference's body origins relative to the reference CoM (world axes).
        ref_linvel: ``(B, 3)`` the reference's body velocities (world).
        ref_com_vel: ``(3,)`` the reference's CoM velocity (world).
        prev_action: ``(A,)`` smoothed previous action.
        heading: ``(3, 3)`` world → observation-frame rotation, a turn about z
            (:func:`heading_rotation` of the character's root, or of the reference's);
            ``None``: world axes, ADAPT's layout.
        ref_com: ``(3,)`` the reference's CoM (world): given, ``dp_com`` is observed.
    """
    lead = np.ndim(com) - 1
    p = pos - com[..., None, :]
    dv_com = com_vel - ref_com_vel
    com_vel, ref_com_vel, dv_com = (_in_frame(v, heading, lead) for v in (com_vel, ref_com_vel, dv_com))
    p, linvel, ref_pos_rel, ref_linvel = (_in_frame(v, heading, lead) for v in (p, linvel, ref_pos_rel, ref_linvel))
    offset = [] if ref_com is None else [_in_frame(com - ref_com, heading, lead)]
    flat = np.shape(com)[:-1] + (-1,)
    return np.concatenate([
        com_vel, ref_com_vel, dv_com, ref_com_vel[..., :2], dv_com[..., :2], *offset,
        p.reshape(flat), linvel.reshape(flat), (p - ref_pos_rel).reshape(flat), (linvel - ref_linvel).reshape(flat),
        prev_action,
    ], axis=-1).astype(np.float32)


def steering_pull(com: np.ndarray, ref_com: np.ndarray, gain_hz: float, max_speed_mps: float) -> np.ndarray:
    """The horizontal pull ``(..., 2)`` (m/s) back onto the reference: ``s = gain_hz · (ref_com −
    com)`` on the ground (x, y), capped at ``max_speed_mps`` in length; zeros at gain 0.

    Args:
        com, ref_com: ``(..., 3)`` the character's and the reference's CoM (world, m).
        gain_hz: ``≥ 0``, 1/s.
        max_speed_mps: ``> 0``, the cap on ``|s|`` (m/s).
    """
    offset = np.asarray(ref_com, dtype=float)[..., :2] - np.asarray(com, dtype=float)[..., :2]
    if gain_hz == 0:
        return np.zeros_like(offset)
    steer = gain_hz * offset
    length = np.linalg.norm(steer, axis=-1, keepdims=True)
    return steer * np.minimum(1.0, max_speed_mps / np.maximum(length, 1e-12))


def steered_velocities(com: np.ndarray, ref_com: np.ndarray, ref_com_vel: np.ndarray, ref_linvel: np.ndarray,
                       gain_hz: float, max_speed_mps: float) -> tuple[np.ndarray, np.ndarray]:
    """The reference velocities the observation shows when it steers the character back onto the
    reference (``MimicConfig.steer_gain_hz``): the reference's CoM velocity and every body's
    velocity plus the :func:`steering_pull` ``s`` (x, y; z unchanged). A policy that matches the
    reference's velocities then closes a drift from the reference's position at ``gain_hz`` per
    second, like a position loop around its velocity loop; the reward and terminations still judge
    the reference as it is (unless ``MimicConfig.com_velocity_weight`` rewards the same target).
    Every argument may have leading batch axes (the same on all).

    Args:
        com, ref_com: ``(3,)`` the character's and the reference's CoM (world, m).
        ref_com_vel: ``(3,)`` the reference's CoM velocity (world, m/s).
        ref_linvel: ``(B, 3)`` the reference's body velocities (world, m/s).
        gain_hz: ``≥ 0``, 1/s; 0 returns the velocities unchanged.
        max_speed_mps: ``> 0``, the cap on ``|s|`` (m/s).

    Returns:
        ``(ref_com_vel + s, ref_linvel + s)``, the shapes and dtypes of the inputs.
    """
    if gain_hz == 0:
        return ref_com_vel, ref_linvel
    steer = steering_pull(com, ref_com, gain_hz, max_speed_mps)
    com_vel, linvel = np.array(ref_com_vel), np.array(ref_linvel)  # copies, in the inputs' dtypes
    com_vel[..., :2] += steer
    linvel[..., :2] += steer[..., None, :]
    return com_vel, linvel


def lookahead_observation(ref_com: np.ndarray, ahead_com: np.ndarray, ahead_com_vel: np.ndarray,
                          ahead_pos_rel: np.ndarray, heading: np.ndarray | None = None) -> np.ndarray:
    """The ``lookahead`` and ``lookbehind`` parts of the observation ``(K·(6 + 3B),)`` float32: for
    each of ``K`` other reference frames (future or past; the names say "ahead"), in order, the
    reference CoM's displacement from ``ref_com``, its CoM velocity and its body origins relative
    to its CoM, each in the observation's axes. Every argument may have leading batch axes (the
    same on all), which the result then has too.

    Args:
        ref_com: ``(3,)`` the reference's CoM now (world, m).
        ahead_com: ``(K, 3)`` the reference's CoM at each future frame (world, m).
        ahead_com_vel: ``(K, 3)`` its CoM velocity there (world, m/s).
        ahead_pos_rel: ``(K, B, 3)`` its observed body origins relative to its CoM there (world axes, m).
        heading: ``(3, 3)`` world → observation-frame rotation (as in :func:`mimic_observation`);
            ``None``: world axes.
    """
    lead = np.ndim(ref_com) - 1
    rotate = (lambda v: v) if heading is None else (lambda v: np.einsum("...ij,...kj->...ki", heading, v))
    shift, velocity = rotate(ahead_com - ref_com[..., None, :]), rotate(ahead_com_vel)
    bodies = np.shape(ahead_pos_rel)
    pos_rel = rotate(np.reshape(ahead_pos_rel, bodies[:-3] + (-1, 3))).reshape(bodies[:-2] + (-1,))
    per_step = np.concatenate([shift, velocity, pos_rel], axis=-1)
    return per_step.reshape(np.shape(ref_com)[:lead] + (-1,)).astype(np.float32)


# --------------------------------------------------------------------------- MimicGait-v0
def gait_observation_slices(n_bodies: int, n_action: int, preview_frames: int,
                            com_offset: bool = False) -> dict[str, slice]:
    """Named slices of the ``MimicGait-v0`` observation: the mimic observation
    (:func:`observation_slices`), then, with ``P = preview_frames``:

    ============  ====  =====================================================================
    name          size  content
    ============  ====  =====================================================================
    ref_contacts  4P    the contact targets ĉ of the next P reference frames, frame by frame,
                        each (LT, RT, LH, RH) as 0/1
    ref_toe       2P    the toe target angles of the same frames, each (left, right), rad
    contacts      4     the simulated contacts c of the current frame (LT, RT, LH, RH), 0/1
    ============  ====  =====================================================================
    """
    out = observation_slices(n_bodies, n_action, com_offset)
    start = out["prev_action"].stop
    for name, size in (("ref_contacts", 4 * preview_frames), ("ref_toe", 2 * preview_frames), ("contacts", 4)):
        out[name] = slice(start, start + size)
        start += size
    return out


def gait_observation(mimic_obs: np.ndarray, ref_contacts: np.ndarray, ref_toe: np.ndarray,
                     contacts: np.ndarray) -> np.ndarray:
    """The ``MimicGait-v0`` observation ``(13 + 12·B + A + 6P + 4,)`` float32, 3 more in the heading
    frame (:func:`gait_observation_slices`).

    Args:
        mimic_obs: the mimic observation (:func:`mimic_observation`).
        ref_contacts: ``(P, 4)`` contact targets (bool or 0/1) of the next ``P`` frames.
        ref_toe: ``(P, 2)`` toe target angles (rad; left, right) of the same frames.
        contacts: ``(4,)`` the simulated contacts now.
    """
    return np.concatenate([mimic_obs, np.asarray(ref_contacts, dtype=np.float32).ravel(),
                           np.asarray(ref_toe, dtype=np.float32).ravel(),
                           np.asarray(contacts, dtype=np.float32)]).astype(np.float32)
