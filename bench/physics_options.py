"""What MuJoCo's solver options cost and change on our humanoids: the Jacobian's layout (dense, which
MuJoCo picks by itself below 60 dofs, or sparse, which the MJCF files set) and the solver's iteration
limits, timed on the states a trained policy really visits.

Usage: ``python bench/physics_options.py [--rounds R] [--json [OUT]]``

A shipped policy performs DeepMimic clips (``mimic_general`` on walk and run for ``humanoid_1seg``,
``mimic_gait_ff`` on walk for ``humanoid_2seg``; seeded episodes from two start frames each, at most
300 frames); the integration state after every 60 Hz frame is recorded, and each frame but an
episode's first (whose start state is the reset's) becomes a (state, controls) pair within its
episode. Replaying the pairs with the MJCF's own options must give the recorded next states (checked
to 1e-9). Each option set then replays every pair (``mj_step`` × the substeps of a frame), timed,
and its next ``qpos`` is compared with the baseline's (dense Jacobian, MuJoCo's defaults otherwise).
``R`` interleaved rounds; the median is reported.
"""

from __future__ import annotations

import argparse
import copy
import statistics
import time
from collections.abc import Callable

import mujoco
import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.policy import load_policy
from agents.rollout import run_episode
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.cli import positive_int

STATE = mujoco.mjtState.mjSTATE_INTEGRATION
"""Everything ``mj_step`` reads (the physics state, controls and the solver's warm start)."""
REPLAY_TOLERANCE = 1e-9
"""Largest |Δqpos| allowed between a replayed frame (the MJCF's own options) and the recording."""
CASES = {"humanoid_1seg": ("models/mimic_general", ["deepmimic:walk", "deepmimic:run"]),
         "humanoid_2seg": ("models/mimic_gait_ff", ["deepmimic:walk"])}
OPTIONS: dict[str, Callable[[mujoco.MjOption], None]] = {
    "dense Jacobian (baseline)": lambda o: setattr(o, "jacobian", mujoco.mjtJacobian.mjJAC_DENSE),
    "sparse Jacobian (the MJCF files)": lambda o: setattr(o, "jacobian", mujoco.mjtJacobian.mjJAC_SPARSE),
    "sparse, iterations 20, ls_iterations 10": lambda o: (setattr(o, "jacobian", mujoco.mjtJacobian.mjJAC_SPARSE),
                                                         setattr(o, "iterations", 20),
                                                         setattr(o, "ls_iterations", 10)),
}


def record_frames(policy_dir: str, clips: list[str]) -> tuple[mujoco.MjModel, int, list[np.ndarray],
                                                               list[np.ndarray], list[np.ndarray]]:
    """The env's model, its substeps per frame, and for every frame of the policy's seeded episodes on
    ``clips`` (two starts each, at most 300 frames) but each episode's first: the integration state
    before it, its controls, and the ``qpos`` it was recorded to reach."""
    policy = load_policy(policy_dir)
    env = policy.make_env(clips)
    base = env.unwrapped
    states, controls, reached = [], [], []
    episode: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []

    def record(data: mujoco.MjData) -> None:  # called after each frame, its controls still in data.ctrl
        state = np.empty(mujoco.mj_stateSize(base.model, STATE))
        mujoco.mj_getState(base.model, data, state, STATE)
        episode.append((state, data.ctrl.copy(), data.qpos.copy()))

    base.frame_hook = record
    for seed, (clip, start) in enumerate((c, s) for c in clips for s in (0, 20)):
        episode.clear()
        run_episode(env, policy, {"clip": clip, "start_frame": start}, max_frames=300, seed=seed)
        for (before, _, _), (_, ctrl, after) in zip(episode[:-1], episode[1:]):  # frame k+1 from the state after k
            states.append(before)
            controls.append(ctrl)
            reached.append(after)
    base.frame_hook = None
    env.close()
    return base.model, base.substeps, states, controls, reached


def replay(model: mujoco.MjModel, substeps: int, states: list[np.ndarray],
           controls: list[np.ndarray]) -> tuple[float, np.ndarray]:
    """µs per frame of ``mj_step`` from each recorded state, and the ``(N, nq)`` qpos after each."""
    data = mujoco.MjData(model)
    busy, after = 0.0, []
    for state, ctrl in zip(states, controls):
        mujoco.mj_setState(model, data, state, STATE)
        data.ctrl[:] = ctrl  # the state holds the previous frame's controls
        start = time.perf_counter()
        mujoco.mj_step(model, data, nstep=substeps)
        busy += time.perf_counter() - start
        after.append(data.qpos.copy())
    return 1e6 * busy / len(states), np.array(after)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=positive_int, default=7, help="interleaved rounds (the median is reported)")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    result: dict = {"rounds": args.rounds, "bodies": {}}
    for body, (policy_dir, clips) in CASES.items():
        recorded, substeps, states, controls, reached = record_frames(policy_dir, clips)
        _, replayed = replay(recorded, substeps, states, controls)
        mismatch = float(np.abs(replayed - np.array(reached)).max())
        if mismatch > REPLAY_TOLERANCE:
            raise RuntimeError(f"{body}: replaying the recorded frames misses the recording by {mismatch:.1e} "
                               f"(> {REPLAY_TOLERANCE:.0e}): the replay is not the simulation that was recorded")
        models = {}
        for label, apply in OPTIONS.items():
            models[label] = copy.deepcopy(recorded)
            apply(models[label].opt)
        times: dict[str, list[float]] = {label: [] for label in OPTIONS}
        qpos: dict[str, np.ndarray] = {}
        for _ in range(args.rounds):
            for label, model in models.items():
                us, qpos[label] = replay(model, substeps, states, controls)
                times[label].append(us)
        baseline = next(iter(OPTIONS))
        rows = []
        for label in OPTIONS:
            deviation = np.abs(qpos[label] - qpos[baseline])
            rows.append({"options": label, "us_per_frame": round(statistics.median(times[label]), 1),
                         "rounds_us_per_frame": [round(t, 1) for t in times[label]],
                         "speedup_vs_baseline": round(statistics.median(times[baseline]) / statistics.median(times[label]), 3),
                         "max_qpos_deviation": float(deviation.max()), "mean_qpos_deviation": float(deviation.mean())})
        result["bodies"][body] = {"policy": policy_dir, "clips": clips, "frames": len(states), "nv": recorded.nv,
                                  "replay_vs_recording_max_qpos": mismatch,
                                  "substeps_per_frame": substeps, "rows": rows}
    if not emit_json(result, args.json):
        for body, r in result["bodies"].items():
            print(f"{body} (nv {r['nv']}, {r['frames']} frames of {r['policy']} on {', '.join(r['clips'])})")
            for row in r["rows"]:
                print(f"  {row['options']:42s} {row['us_per_frame']:7.1f} µs/frame  ×{row['speedup_vs_baseline']:.3f}  "
                      f"max |Δqpos| {row['max_qpos_deviation']:.1e}")


if __name__ == "__main__":
    main()
