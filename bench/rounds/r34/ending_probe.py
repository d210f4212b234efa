"""How the style-shifted validation rollouts end (round 34's probe; validation's takes only, no held-out take).

A policy tracks the IMU-corrupted style-shifted draws of validation's takes as the shifted rows do
(``bench/imu_draws.py --style-shifts``: the same seeds, behind a denoiser's corrections slowed to 0.5 s, mirror-averaged,
legs evened and parted, grounded, swing-lifted), 2 rollouts per take and version in each draw, and every rollout that
ends early is recorded: its ``ended_by``, the share of the episode it performed, and, at its last frame, the simulated
pelvis's height below the judged take's (m), its horizontal distance from the judged take's (m), the part of that
along the judged take's way over its last 0.5 s (m, positive: behind it; 0 where the take moved under
MIN_TRAVEL_M then), and the IMU's own horizontal drift there (the judged take's pelvis from the clean shifted
take's, m). ADAPT's head-distance termination ("lagging") usually ends a fall before the fall rule ("fallen") sees
it, so each early end is classed by those distances (:func:`end_class`): *fallen* (either rule, the pelvis more
than FALLEN_BELOW_M below the take's), else *behind* or *ahead* (more than ALONG_M along the take's way), else
*aside*.

DENOISER ``none`` (stop 93): the takes as the suit gave them, the rest of the preparation as before.

usage: python bench/rounds/r34/ending_probe.py POLICY DENOISER FIRST_SEED DRAWS OUT.json [--steer GAIN_HZ CAP_MPS]
[--torque-scale PART FACTOR]

``--steer`` sets the steering of the observed reference velocities (``MimicConfig.steer_gain_hz`` and
``steer_max_speed_mps``) in place of the policy's own; ``--torque-scale`` multiplies the torque limit of every actuator
whose name contains PART (e.g. ``foot_y``, the ankles' pitch) by FACTOR, the policy acting as trained.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[3]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]
import envs  # noqa: E402,F401  (registers the ids)
from agents.evaluate import corrupted, tracked_and_judged  # noqa: E402
from agents.evaluation import Rollout, evaluate_tracking  # noqa: E402
from agents.policy import MimicPolicy, load_policy  # noqa: E402
from envs.config import MimicConfig  # noqa: E402
from envs.preparation import PreparationSteps  # noqa: E402
from perception.imu_denoiser import slowed  # noqa: E402
from perception.weights import load_network  # noqa: E402
from imu_draws import drawn_clips  # noqa: E402  (bench/imu_draws.py)
from reference_motion.cli import positive_float  # noqa: E402
from reference_motion.grounding import Grounding  # noqa: E402
from reference_motion.leg_gap import LegGap  # noqa: E402
from reference_motion.leg_symmetry import LegSymmetry  # noqa: E402
from reference_motion.library import STYLE_SHIFT_NAMES, expand_clips  # noqa: E402
from reference_motion.motion import Motion  # noqa: E402
from reference_motion.swing_lift import SwingLift  # noqa: E402

EPISODES = 2
"""Rollouts per take and version in each draw (the shifted rows' ``--episodes``)."""
VAL_CLIPS = ["library:data/library/val"]
FALLEN_BELOW_M = 0.25
"""An early end with the pelvis more than this below the take's (m) is a fall."""
ALONG_M = 0.3
"""An upright early end more than this behind or ahead of the take's pelvis along its way (m) walked too slowly or
too fast."""
MIN_TRAVEL_M = 0.05
"""Under this much travel of the take's pelvis in its last 0.5 s (m) the take has no way to be behind or ahead on."""
WAY_FRAMES = 30
"""The frames (0.5 s at 60 Hz) over which the take's way is read at an early end."""


def ending(run: Rollout, clean_root: np.ndarray) -> dict:
    """The record of a rollout ``run`` that ended early (see the module's docstring); ``clean_root`` ``(T, 3)``: the
    clean shifted take's pelvis positions (m), frame-aligned with the judged take."""
    sim, ref = run.simulated.qpos[:, :3], run.reference.qpos[:, :3]
    last = len(sim) - 1
    travel = ref[last, :2] - ref[max(0, last - WAY_FRAMES), :2]
    gap = ref[last, :2] - sim[last, :2]
    distance = np.linalg.norm(travel)
    behind = float(gap @ travel / distance) if distance >= MIN_TRAVEL_M else 0.0
    return {"ended_by": run.ended_by, "share": float(run.elr), "height_below_m": float(ref[last, 2] - sim[last, 2]),
            "horizontal_m": float(np.linalg.norm(gap)), "behind_m": behind,
            "imu_drift_m": float(np.linalg.norm(ref[last, :2] - clean_root[run.start_frame + last, :2]))}


def end_class(record: dict) -> str:
    """``"fallen"``, ``"behind"``, ``"ahead"`` or ``"aside"``: how a rollout that ended early ended (its record)."""
    if record["ended_by"] == "fallen" or record["height_below_m"] > FALLEN_BELOW_M:
        return "fallen"
    return "behind" if record["behind_m"] > ALONG_M else "ahead" if record["behind_m"] < -ALONG_M else "aside"


def summarize(records: list[dict]) -> dict[str, dict]:
    """Per version: rollouts, mean ELR, how many ended early and how (:func:`end_class`), and the medians of the
    early ends' distances."""
    summary = {}
    for version in STYLE_SHIFT_NAMES:
        mine = [r for r in records if r["version"] == version]
        failed = [r for r in mine if r["elr"] < 1.0]
        row = {"rollouts": len(mine), "ELR": float(np.mean([r["elr"] for r in mine])), "ended_early": len(failed),
               "ended": {k: sum(end_class(r) == k for r in failed) for k in ("fallen", "behind", "ahead", "aside")}}
        for key in ("height_below_m", "behind_m", "imu_drift_m", "share"):
            if failed:
                row[f"median_{key}"] = float(np.median([r[key] for r in failed]))
        summary[version] = row
    return summary


def performed(policy: MimicPolicy, tracked: list[Motion], judged: list[Motion],
              torque_scale: tuple[str, float] | None) -> list[Rollout]:
    """The rollouts of :func:`evaluate_tracking` (mirror-averaged), the actuators whose names contain
    ``torque_scale[0]`` given ``torque_scale[1]`` times their torque limits (restored afterwards: the
    MuJoCo model may be shared)."""
    limits = []  # (model, actuators, their limits as they were)

    def scale_torques(env) -> None:
        model = env.unwrapped.model
        part, factor = torque_scale
        scaled = [i for i in range(model.nu) if part in model.actuator(i).name]
        if not scaled:
            raise SystemExit(f"--torque-scale: no actuator's name contains {part!r}")
        limits.append((model, scaled, model.actuator_forcerange[scaled].copy()))
        model.actuator_forcerange[scaled] *= factor

    try:
        return evaluate_tracking(policy, tracked, judged, episodes=EPISODES, mirror_average=True,
                                 prepare_env=None if torque_scale is None else scale_torques)[1]
    finally:
        for model, scaled, original in limits:
            model.actuator_forcerange[scaled] = original


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("policy", help="a policy directory or run checkpoint")
    p.add_argument("denoiser", help="the IMU denoiser the takes pass through (its corrections slowed to 0.5 s); "
                                    "'none': the takes as the suit gave them (the raw rows, stop 93)")
    p.add_argument("first_seed", type=int, help="the first draw's seed (as imu_draws.py --first-seed)")
    p.add_argument("draws", type=int)
    p.add_argument("out", help="the JSON to write")
    p.add_argument("--steer", nargs=2, type=positive_float, metavar=("GAIN_HZ", "CAP_MPS"))
    p.add_argument("--torque-scale", nargs=2, metavar=("PART", "FACTOR"))
    args = p.parse_args()
    torque_scale = None
    if args.torque_scale is not None:
        try:
            torque_scale = (args.torque_scale[0], positive_float(args.torque_scale[1]))
        except argparse.ArgumentTypeError as e:
            p.error(f"--torque-scale FACTOR: {e}")
    steps = PreparationSteps(symmetry=LegSymmetry(), legs=LegGap(), grounding=Grounding(), lift=SwingLift())
    policy = load_policy(args.policy)
    if args.steer is not None:
        policy = policy.steering(*args.steer)
    net = None if args.denoiser == "none" else slowed(load_network(args.denoiser, "denoiser"), 0.5)
    config = MimicConfig()
    versions = len(STYLE_SHIFT_NAMES)
    stride = len(expand_clips(VAL_CLIPS)) * versions  # imu_draws.py --style-shifts: a seed per tracked clip
    records = []
    for j in range(args.draws):
        seed = args.first_seed + j * stride
        shifted = drawn_clips(VAL_CLIPS, "humanoid_1seg", config, seed, style_shifts=True)
        tracked, judged = tracked_and_judged(corrupted(shifted, "imu", 1.0, seed), net, **steps)
        index = {clip.name: i for i, clip in enumerate(tracked)}
        for run in performed(policy, tracked, judged, torque_scale):
            i = index[run.clip]
            record = {"seed": seed, "version": STYLE_SHIFT_NAMES[i % versions], "clip": run.clip, "elr": float(run.elr)}
            if run.elr < 1.0:
                record |= ending(run, shifted[i].qpos[:, :3])
            records.append(record)
        print(f"draw {j}: ELR {np.mean([r['elr'] for r in records]):.3f} so far", flush=True)
    summary = summarize(records)
    for version, row in summary.items():
        print(version, json.dumps(row), flush=True)
    with open(args.out, "w") as f:
        json.dump({"policy": args.policy, "denoiser": args.denoiser, "first_seed": args.first_seed,
                   "draws": args.draws, "episodes": EPISODES, "steering": args.steer,
                   "torque_scale": None if torque_scale is None else list(torque_scale),
                   "summary": summary, "records": records}, f, indent=1)


if __name__ == "__main__":
    main()
