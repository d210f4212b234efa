"""What the physics rate does to a policy's simulated motion: sinking, sliding, tracking, cost.

Usage: ``python bench/physics_rate.py [--policy models/mimic_general] [--clips library:data/library/val]
[--episodes 10] [--rates 120 240 480] [--json [OUT]]``

One policy, the same clips and start frames, side by side in one run, with the physics stepped at
each of ``--rates`` (:attr:`envs.config.MimicConfig.physics_rate_hz`: the timestep and the contacts'
time constant of two steps, :func:`envs.physics.at_physics_rate`), plus one row at the coarsest
rate whose contacts are as stiff as the finest rate's, MuJoCo's two-step guard (``refsafe``) switched off: the
stiffness alone, without the finer step. Per row: ELR and SR90 (:mod:`agents.evaluation`), the
simulated motion's foot skate, floor penetration (max and mean) and jitter (SPEC "Metrics",
:mod:`reference_motion.quality`, the mean over rollouts), and the physics' own cost: control steps
per second of ``mj_step`` alone on one core, from a reference state with the PD targets held.
"""

from __future__ import annotations

import argparse
import copy
import time

import mujoco

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import artefact_table, reference_clips
from agents.evaluation import evaluate, summarize
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from envs.physics import contact_time_constants
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/

METRICS = ("foot_skate_mps", "penetration_max_m", "penetration_mean_m", "jitter")


def stiff_without_refsafe(env, rate_hz: float) -> None:
    """Give ``env`` (at its own rate) a model whose contacts have the time constant of two steps at
    ``rate_hz``, with MuJoCo's two-step guard off so the constant is used as given."""
    base = env.unwrapped
    model = copy.deepcopy(base.model)
    model.geom_solref[:, 0] = 2.0 / rate_hz
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_REFSAFE)
    base.model, base.data = model, mujoco.MjData(model)


def physics_steps_per_s(env, seconds: float = 2.0) -> float:
    """Control steps per second of ``mj_step`` alone on ``env``'s model (one core), from its reset
    state with the controls held; restarted from there whenever the body falls."""
    base = env.unwrapped
    env.reset(seed=0, options={"clip": 0, "start_frame": 0})
    model, data = base.model, base.data
    start_q, start_v = data.qpos.copy(), data.qvel.copy()
    nstep = base.substeps * base.config.frames_per_control
    steps, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        mujoco.mj_step(model, data, nstep=nstep)
        steps += 1
        if data.qpos[2] < 0.4:
            data.qpos[:], data.qvel[:] = start_q, start_v
    return steps / (time.perf_counter() - t0)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--episodes", type=int, default=10, help="rollouts per clip and row")
    p.add_argument("--rates", type=float, nargs="+", default=[120.0, 240.0, 480.0])
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    policy = load_policy(args.policy)
    clips = reference_clips(args.clips, FOOT_MODELS[policy.foot], MimicConfig(), None, 1.0, 0)
    coarse, fine = min(args.rates), max(args.rates)
    rows = [(f"{r:g} Hz", r, None) for r in args.rates]
    rows.append((f"{coarse:g} Hz, contacts of {fine:g} Hz", coarse, fine))
    table = []
    for label, rate, stiff in rows:
        performer = policy.simulating(rate)
        env = performer.make_env(clips, artefacts=None)
        if stiff:
            stiff_without_refsafe(env, stiff)
        cost = physics_steps_per_s(env)
        env.reset(seed=0)
        t0 = time.perf_counter()
        runs = evaluate(env, performer, episodes=args.episodes)[1]
        summary, artefacts = summarize(runs), artefact_table(runs)
        row = {"setting": label, "physics_rate_hz": rate,
               "contact_timeconst_s": float(contact_time_constants(env.unwrapped.model)[0]),
               "refsafe": stiff is None, "physics_control_steps_per_s": cost, "rollouts": len(runs),
               "ELR": summary["ELR_mean"], "SR90": summary["SR90"], "wall_s": time.perf_counter() - t0,
               **{k: artefacts[k]["output"] for k in METRICS}, "input": {k: artefacts[k]["input"] for k in METRICS}}
        table.append(row)
        print(f"{label:<28} physics {cost:6.0f} steps/s  ELR {row['ELR']:.3f}  SR90 {row['SR90']:.2f}  skate "
              f"{row['foot_skate_mps']:.3f} m/s  penetration max {100 * row['penetration_max_m']:.2f} cm, mean "
              f"{1000 * row['penetration_mean_m']:.2f} mm  jitter {row['jitter']:.0f}", flush=True)
    result = {"policy": args.policy, "clips": args.clips, "episodes": args.episodes, "rows": table}
    if not emit_json(result, args.json):
        inp = table[0]["input"]
        print(f"{'the clips themselves':<28} {'':>22}  {'':>22}skate {inp['foot_skate_mps']:.3f} m/s  penetration "
              f"max {100 * inp['penetration_max_m']:.2f} cm, mean {1000 * inp['penetration_mean_m']:.2f} mm  "
              f"jitter {inp['jitter']:.0f}")


if __name__ == "__main__":
    main()
