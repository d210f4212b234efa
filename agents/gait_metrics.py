"""How well a simulated gait reconstructs its reference (contactvision §6.5): pure functions of arrays.

* :func:`joint_angle_rmse_deg` — joint-angle RMSE of the simulation against the reference
  (ContactVision: 3.27°);
* :func:`contact_f1` — F1 of the simulated contacts against the targets ĉ;
* :func:`toe_push_off` — per push-off (a rise of the ToeRefEstimator's target), the peak toe
  dorsiflexion of the simulation and of the target, and when each peaks;
* :func:`forward_displacement_error` — the simulated root's horizontal displacement against the
  reference's, as a fraction;
* :func:`simulated_contacts` — the contact states a simulated motion has frame by frame (MuJoCo's
  collision detection at each stored state; the environment reports those of the last physics
  substep's start, which can differ by one 1/120-s substep).

Contacts are ``(T, 4)`` bool in (left_toe, right_toe, left_heel, right_heel) order; angles are
rad in, degrees out, as the names say; frames are 60 Hz unless ``fps`` says otherwise.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import mujoco
import numpy as np

from envs.bodies import floor_contact_geoms, region_contacts
from reference_motion.humanoid.model import load_model
from reference_motion.motion import Motion


def joint_angle_rmse_deg(hinges: np.ndarray, ref_hinges: np.ndarray) -> float:
    """RMSE (degrees) over every frame and hinge of ``hinges`` against ``ref_hinges`` (both ``(T, H)`` rad)."""
    hinges, ref_hinges = np.asarray(hinges, float), np.asarray(ref_hinges, float)
    if hinges.shape != ref_hinges.shape or hinges.ndim != 2 or hinges.size == 0:
        raise ValueError(f"hinges and ref_hinges must both be (T, H) with T, H > 0, got {hinges.shape} and "
                         f"{ref_hinges.shape}")
    return float(np.degrees(np.sqrt(np.mean((hinges - ref_hinges) ** 2))))


def contact_f1(contacts: np.ndarray, targets: np.ndarray) -> float:
    """F1 of ``contacts`` against ``targets`` (both ``(T, 4)`` bool), all channels pooled; 1.0 when
    neither has a contact."""
    contacts, targets = np.asarray(contacts, bool), np.asarray(targets, bool)
    if contacts.shape != targets.shape:
        raise ValueError(f"contacts {contacts.shape} and targets {targets.shape} differ in shape")
    tp = int((contacts & targets).sum())
    wrong = int((contacts ^ targets).sum())
    return 1.0 if tp + wrong == 0 else 2 * tp / (2 * tp + wrong)


@dataclass(frozen=True)
class PushOff:
    """One push-off of one foot.

    Attributes:
        foot: 0 left, 1 right.
        start, stop: frames of the target's rise from 0 and of its return to 0 (exclusive).
        target_peak_deg, target_peak_frame: the ToeRef target's largest angle and its frame.
        peak_deg, peak_frame: the simulated toe hinge's largest angle in ``start..stop`` and its frame.
    """

    foot: int
    start: int
    stop: int
    target_peak_deg: float
    target_peak_frame: int
    peak_deg: float
    peak_frame: int


def toe_push_off(toe_angles: np.ndarray, toe_targets: np.ndarray) -> list[PushOff]:
    """The push-offs of ``toe_targets`` ``(T, 2)`` (rad; left, right; > 0 bends the toes up, the
    ToeRefEstimator's output) with the simulated ``toe_angles`` ``(T, 2)`` (rad) in each."""
    toe_angles, toe_targets = np.asarray(toe_angles, float), np.asarray(toe_targets, float)
    if toe_angles.shape != toe_targets.shape or toe_angles.ndim != 2 or toe_angles.shape[1] != 2:
        raise ValueError(f"toe_angles and toe_targets must both be (T, 2), got {toe_angles.shape} and "
                         f"{toe_targets.shape}")
    out = []
    for foot in range(2):
        active = np.concatenate([[False], toe_targets[:, foot] > 1e-9, [False]])
        edges = np.flatnonzero(np.diff(active.astype(int)))
        for start, stop in zip(edges[::2], edges[1::2]):
            target, sim = toe_targets[start:stop, foot], toe_angles[start:stop, foot]
            out.append(PushOff(foot=foot, start=int(start), stop=int(stop),
                               target_peak_deg=float(np.degrees(target.max())),
                               target_peak_frame=int(start + np.argmax(target)),
                               peak_deg=float(np.degrees(sim.max())), peak_frame=int(start + np.argmax(sim))))
    return out


@dataclass(frozen=True)
class PushOffSummary:
    """Means over the push-offs of a clip (NaN when it has none).

    Attributes:
        count: push-offs.
        target_peak_deg, peak_deg: mean peak toe angle of the target and of the simulation (degrees).
        timing_ms: mean of (simulated peak frame − target peak frame), in ms (> 0: the simulation peaks later).
    """

    count: int
    target_peak_deg: float
    peak_deg: float
    timing_ms: float

    def as_dict(self) -> dict:
        return asdict(self)


def summarize_push_offs(push_offs: list[PushOff], fps: float) -> PushOffSummary:
    """:class:`PushOffSummary` of ``push_offs`` at ``fps``."""
    if not push_offs:
        return PushOffSummary(0, float("nan"), float("nan"), float("nan"))
    return PushOffSummary(count=len(push_offs),
                          target_peak_deg=float(np.mean([p.target_peak_deg for p in push_offs])),
                          peak_deg=float(np.mean([p.peak_deg for p in push_offs])),
                          timing_ms=float(np.mean([p.peak_frame - p.target_peak_frame for p in push_offs])
                                          * 1000.0 / fps))


def forward_displacement_error(root: np.ndarray, ref_root: np.ndarray) -> float:
    """``|d / d_ref − 1|``: d the horizontal distance from the first to the last root position
    ``root (T, 3)`` (m, world), ``d_ref`` the reference's; ``inf`` when the reference stays put."""
    root, ref_root = np.asarray(root, float), np.asarray(ref_root, float)
    if root.shape != ref_root.shape or root.ndim != 2 or root.shape[1] < 2 or len(root) < 2:
        raise ValueError(f"root and ref_root must both be (T >= 2, 3), got {root.shape} and {ref_root.shape}")
    d = np.linalg.norm(root[-1, :2] - root[0, :2])
    d_ref = np.linalg.norm(ref_root[-1, :2] - ref_root[0, :2])
    return float(abs(d / d_ref - 1.0)) if d_ref > 1e-9 else float("inf")


def simulated_contacts(motion: Motion) -> np.ndarray:
    """Contacts ``(T, 4)`` bool (LT, RT, LH, RH) of a motion's stored states: a sole sphere of the
    region touching the floor in MuJoCo's collision detection at that ``qpos`` (as
    :class:`envs.mimic.MimicEnv` reports them while simulating, up to one substep)."""
    humanoid = load_model(motion.model)
    model = humanoid.model
    data = mujoco.MjData(model)
    floor = model.geom("floor").id
    out = np.zeros((motion.n_frames, 4), dtype=bool)
    for t, qpos in enumerate(motion.qpos):
        data.qpos[:] = qpos
        mujoco.mj_forward(model, data)
        out[t] = region_contacts(floor_contact_geoms(data, floor), humanoid.geom_contact_channel)
    return out
