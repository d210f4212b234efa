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
