"""How the style-shifted validation rollouts end (round 34's probe; validation's takes only, no held-out take).

A policy tracks the IMU-corrupted style-shifted draws of validation's takes as the shifted rows do (behind a
denoiser's slowed corrections and the IMU rows' preparation), and every rollout that ends early is recorded by
version: how it ended (``fallen`` or ``lagging``, the head 0.91 m from the take's), where (share of the episode), and,
at its last frame, three distances (m): the simulated pelvis's height below the judged take's; its horizontal distance
from the judged take's, and the part of that along the judged take's direction of travel (positive: behind it);
and the IMU's own horizontal drift there (the judged take's pelvis from the clean shifted take's). Every early end is
ADAPT's head-distance termination before the fall rule sees a fall, so each is classed by those distances: *fallen*
(the pelvis more than FALLEN_BELOW_M below the take's), else *behind* or *ahead* (more than ALONG_M of the distance
along the take's way), else *aside*.

usage: python bench/rounds/r34/ending_probe.py POLICY DENOISER FIRST_SEED DRAWS OUT.json [--steer GAIN_HZ CAP_MPS]
[--torque-scale PART FACTOR]
(the preparation of the IMU rows: mirror-averaged, slowed 0.5 s, legs evened and parted, grounded, swing lift).
``--steer`` sets the steering of the observed reference velocities (``MimicConfig.steer_gain_hz`` and
``steer_max_speed_mps``) in place of the policy's own; ``--torque-scale`` multiplies the torque limit of every actuator
whose name contains PART (e.g. ``foot_y``, the ankles' pitch) by FACTOR, the policy acting as trained.
"""
from __future__ import annotations

import argparse
import json
import sys

import numpy as np

sys.path.insert(0, ".")
import envs  # noqa: E402,F401  (registers the ids)
from agents.evaluate import corrupted, reference_clips, tracked_and_judged  # noqa: E402
from agents.evaluation import evaluate, evaluate_tracking  # noqa: E402
from agents.mirror import MirrorAveraged, MirrorMaps  # noqa: E402
from agents.policy import MimicPolicy, load_policy  # noqa: E402
from envs.config import MimicConfig  # noqa: E402
from envs.preparation import preparation_of  # noqa: E402
from perception.imu_denoiser import slowed  # noqa: E402
from perception.weights import load_network  # noqa: E402
from reference_motion.cli import require_frames  # noqa: E402
from reference_motion.grounding import add_grounding_option  # noqa: E402
from reference_motion.leg_gap import add_leg_gap_option  # noqa: E402
from reference_motion.leg_symmetry import add_leg_symmetry_option  # noqa: E402
from reference_motion.library import STYLE_SHIFT_NAMES, style_shifted  # noqa: E402
from reference_motion.motion import Motion  # noqa: E402
from reference_motion.swing_lift import add_swing_lift_options  # noqa: E402


def ending(run, clean_root: np.ndarray) -> dict:
    """The distances at a failed rollout's last frame (see the module's docstring)."""
    sim, ref = run.simulated.qpos[:, :3], run.reference.qpos[:, :3]
    last = len(sim) - 1
    back = max(0, last - 30)
    travel = ref[last, :2] - ref[back, :2]
    direction = travel / max(np.linalg.norm(travel), 1e-6)
    gap = ref[last, :2] - sim[last, :2]
    return {"ended_by": run.ended_by, "share": float(run.elr), "height_below_m": float(ref[last, 2] - sim[last, 2]),
            "horizontal_m": float(np.linalg.norm(gap)), "behind_m": float(gap @ direction),
            "imu_drift_m": float(np.linalg.norm(ref[last, :2] - clean_root[run.start_frame + last, :2]))}


FALLEN_BELOW_M = 0.25
"""A rollout ended early with its pelvis more than this below the take's (m) has fallen."""
ALONG_M = 0.3
"""An upright one more than this behind or ahead of the take's pelvis along its way (m) walked too slowly or too fast."""


def end_class(record: dict) -> str:
    """``"fallen"``, ``"behind"``, ``"ahead"`` or ``"aside"``: how a rollout that ended early ended (its record)."""
    if record["height_below_m"] > FALLEN_BELOW_M:
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


def performed(policy: MimicPolicy, tracked: list[Motion], judged: list[Motion], torque_scale: tuple[str, float] | None):
    """:func:`evaluate_tracking` (2 rollouts per clip, mirror-averaged), the actuators whose names contain
    ``torque_scale[0]`` given ``torque_scale[1]`` times their torque limits."""
    if torque_scale is None:
        return evaluate_tracking(policy, tracked, judged, episodes=2, mirror_average=True)
    env = policy.make_env(tracked, artefacts=None, judged_clips=judged)
    model = env.unwrapped.model
    part, factor = torque_scale
    scaled = [i for i in range(model.nu) if part in model.actuator(i).name]
    if not scaled:
        raise SystemExit(f"--torque-scale: no actuator's name contains {part!r}")
    model.actuator_forcerange[scaled] *= factor
    env.reset(seed=0)
    return evaluate(env, MirrorAveraged(policy, MirrorMaps.of(env)), episodes=2)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("policy")
    p.add_argument("denoiser")
    p.add_argument("first_seed", type=int)
    p.add_argument("draws", type=int)
    p.add_argument("out")
    p.add_argument("--steer", nargs=2, type=float, metavar=("GAIN_HZ", "CAP_MPS"))
    p.add_argument("--torque-scale", nargs=2, metavar=("PART", "FACTOR"))
    args = p.parse_args()
    policy_path, denoiser_path, first_seed, draws, out = args.policy, args.denoiser, args.first_seed, args.draws, args.out
    torque_scale = None if args.torque_scale is None else (args.torque_scale[0], float(args.torque_scale[1]))
    prep = argparse.ArgumentParser()
    add_leg_symmetry_option(prep, "")
    add_leg_gap_option(prep, "")
    add_grounding_option(prep, "")
    add_swing_lift_options(prep, "")
    steps = preparation_of(prep.parse_args(["--even-legs", "--part-legs", "--ground", "--swing-lift"]))
    policy = load_policy(policy_path)
    if args.steer is not None:
        policy = policy.steering(args.steer[0])._reconfigured("steer_max_speed_mps", args.steer[1], "steer_cap_at")
    net = slowed(load_network(denoiser_path, "denoiser"), 0.5)
    config = MimicConfig()
    n = len(STYLE_SHIFT_NAMES)
    records = []
    for j in range(draws):
        seed = first_seed + j * 35
        clips = reference_clips(["library:data/library/val"], "humanoid_1seg", config, None, 1.0, seed)
        shifted = [require_frames(c, config.min_clip_frames + 1, c.name, "a mimic episode")
                   for c in style_shifted(clips, seed)]
        tracked, judged = tracked_and_judged(corrupted(shifted, "imu", 1.0, seed), net, **steps)
        _, runs = performed(policy, tracked, judged, torque_scale)
        index = {clip.name: i for i, clip in enumerate(tracked)}
        for run in runs:
            i = index[run.clip]
            record = {"seed": seed, "version": STYLE_SHIFT_NAMES[i % n], "clip": run.clip, "elr": float(run.elr)}
            if run.elr < 1.0:
                record |= ending(run, shifted[i].qpos[:, :3])
            records.append(record)
        print(f"draw {j}: ELR {np.mean([r['elr'] for r in records]):.3f} so far", flush=True)
    summary = summarize(records)
    for version, row in summary.items():
        print(version, json.dumps(row), flush=True)
    with open(out, "w") as f:
        json.dump({"policy": policy_path, "denoiser": denoiser_path, "first_seed": first_seed,
                   "steering": args.steer, "torque_scale": args.torque_scale,
                   "summary": summary, "records": records}, f, indent=1)


if __name__ == "__main__":
    main()
