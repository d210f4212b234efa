"""The mimic observation of adapt Table 1, as a pure function of simulated and reference arrays.

Layout (``B`` observed bodies, ``A`` action size; all world frame, SI):

============  ====  =====================================================================
name          size  content
============  ====  =====================================================================
v_com         3     CoM velocity of the character
ref_v_com     3     CoM velocity of the reference
dv_com        3     v_com − ref_v_com
ref_v_hor     2     horizontal (x, y) CoM velocity of the reference
dv_hor        2     horizontal CoM velocity of the character − ref_v_hor
p             3B    body origins relative to the character's CoM (world axes)
v             3B    body origin velocities
dp            3B    p − the reference's body origins relative to its CoM
dv            3B    v − the reference's body velocities
prev_action   A     the smoothed action of the previous step
============  ====  =====================================================================

With all 20 bodies and the 20-D key-joint action this is the 273-D state of ADAPT.
"""

from __future__ import annotations

import numpy as np


def observation_slices(n_bodies: int, n_action: int) -> dict[str, slice]:
    """Named slices of the observation vector (the module table, in order)."""
    sizes = {"v_com": 3, "ref_v_com": 3, "dv_com": 3, "ref_v_hor": 2, "dv_hor": 2,
             "p": 3 * n_bodies, "v": 3 * n_bodies, "dp": 3 * n_bodies, "dv": 3 * n_bodies,
             "prev_action": n_action}
    out, start = {}, 0
    for name, size in sizes.items():
        out[name] = slice(start, start + size)
        start += size
    return out


def observation_size(n_bodies: int, n_action: int) -> int:
    """Length of the observation: 13 + 12·B + A."""
    return 13 + 12 * n_bodies + n_action


def mimic_observation(pos: np.ndarray, linvel: np.ndarray, com: np.ndarray, com_vel: np.ndarray,
                      ref_pos_rel: np.ndarray, ref_linvel: np.ndarray, ref_com_vel: np.ndarray,
                      prev_action: np.ndarray) -> np.ndarray:
    """Observation vector ``(13 + 12·B + A,)`` float32.

    Args:
        pos, linvel: ``(B, 3)`` the character's observed body origins and their velocities.
        com, com_vel: ``(3,)`` the character's CoM and its velocity.
        ref_pos_rel: ``(B, 3)`` the reference's body origins relative to the reference CoM.
        ref_linvel: ``(B, 3)`` the reference's body velocities.
        ref_com_vel: ``(3,)`` the reference's CoM velocity.
        prev_action: ``(A,)`` smoothed previous action.
    """
    p = pos - com
    dv_com = com_vel - ref_com_vel
    return np.concatenate([
        com_vel, ref_com_vel, dv_com, ref_com_vel[:2], dv_com[:2],
        p.ravel(), linvel.ravel(), (p - ref_pos_rel).ravel(), (linvel - ref_linvel).ravel(), prev_action,
    ]).astype(np.float32)


# --------------------------------------------------------------------------- MimicGait-v0
def gait_observation_slices(n_bodies: int, n_action: int, preview_frames: int) -> dict[str, slice]:
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
    out = observation_slices(n_bodies, n_action)
    start = out["prev_action"].stop
    for name, size in (("ref_contacts", 4 * preview_frames), ("ref_toe", 2 * preview_frames), ("contacts", 4)):
        out[name] = slice(start, start + size)
        start += size
    return out


def gait_observation(mimic_obs: np.ndarray, ref_contacts: np.ndarray, ref_toe: np.ndarray,
                     contacts: np.ndarray) -> np.ndarray:
    """The ``MimicGait-v0`` observation ``(13 + 12·B + A + 6P + 4,)`` float32
    (:func:`gait_observation_slices`).

    Args:
        mimic_obs: the mimic observation (:func:`mimic_observation`).
        ref_contacts: ``(P, 4)`` contact targets (bool or 0/1) of the next ``P`` frames.
        ref_toe: ``(P, 2)`` toe target angles (rad; left, right) of the same frames.
        contacts: ``(4,)`` the simulated contacts now.
    """
    return np.concatenate([mimic_obs, np.asarray(ref_contacts, dtype=np.float32).ravel(),
                           np.asarray(ref_toe, dtype=np.float32).ravel(),
                           np.asarray(contacts, dtype=np.float32)]).astype(np.float32)
