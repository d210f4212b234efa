"""The differentiable PD branch on held-out takes: learned vs fixed gains, GRFNet vs none, vs the PPO cleaner.

Usage: ``python bench/diffpd.py [--model models/diffpd] [--ppo models/mimic_general] [--library-takes 6]
[--strength 1] [--no-ppo] [--json [OUT]]`` (``--json bench/results/diffpd.json`` for the record).

Held-out takes (never trained on; training uses the motion library's train split only): DeepMimic
walker/turn_left1, walker/turn_right1, run, spinkick, jump, kick, and the first ``--library-takes``
of ``library:data/library/test`` when ``data/library`` exists. Each is tracked from its first
frame by three cycles sharing the trained networks, all clips in one batch, on one thread:

* ``learned``: DyNet + GRFNet; ``fixed``: GRFNet with the fixed gains (``s_g = ½, s_f = 0``,
  the baseline); ``no_grf``: DyNet without GRF (λ = 0).

Targets: the clean clip, and an IMU-corrupted copy (``corrupt(clip, ArtefactRecipe.imu().scaled(
strength), 1000 + i)``) judged against the clean clip. Per cycle and target kind, means over takes:

* ``lag_frames``: the shift (60 Hz frames, sub-frame by parabolic interpolation) maximising the
  cross-correlation of the simulated hinge angles with the reference's (:func:`tracking_lag`;
  positive: the simulation is late). Goal: learned cuts the fixed gains' lag by ≥ 30%.
* ``mpjpe_cm``: mean distance of the body origins from the reference's (world frame; for corrupted
  targets pelvis-aligned against the clean clip, since the artefacts drift the root).
* artefacts of :func:`~reference_motion.quality.motion_quality` (foot skate m/s, penetration m,
  jitter) and ``non_penetration_share``: frames whose lowest body point is at most
  :data:`PENETRATION_TOLERANCE_M` below z = 0 (goal ≥ 95%; ``..._strict``: not below at all).
* root forces: ``root_virtual_linear_bw`` (‖τ*_root‖ linear, body weights) and angular N·m — what
  GRF leave unexplained, which the root must apply (``no_grf``: the whole root force).

Root residual and no-slip: the learned cycle re-run on the IMU takes with the residual bound at
0.2 / 0.5 / 1 body weight and 100 / 200 N·m, and unbounded (``residual_bound.sweep_imu``: tracking,
re-anchors, mean |residual| and the share of iterations where it saturates), and with the no-slip
constraint off (``no_slip``: the paper's frictionless projection; foot skate before/after).

Also: predicted vGRF vs MuJoCo's — the PPO policy (``--ppo``) re-performs walker/turn_left1 in
MuJoCo, its contact forces recorded (:class:`agents.physics_dataset.FrameRecorder`), and the cycle
tracks that simulated motion: RMSE (% body weight) and correlation of the total vertical force per
frame, for GRFNet and for the even weight split GRFNet starts from, each as λ alone and as λ plus
the floor projection's impulses (``*_plus_floor``: all the support the cycle's floor gives). Speed on one thread: frames/s
of one clip alone and of the batch; and side by side on the IMU-corrupted DeepMimic takes, the PPO
cleaner (``agents.clean.clean_motion``, zero-shot: no adaptation) vs diff-PD: quality and wall time.
The machine's load average is recorded with the timings (other jobs share its 2 cores), and every
timing is also given in this process's CPU time (one thread: the time on a core of its own).
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import math
import os
import time
from pathlib import Path

import numpy as np
import torch

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from agents.diffpd import DynamicCycle, GRFNet
from agents.diffpd_clean import DiffPDCleanConfig, clean_motions, load_cycle
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion
from reference_motion.motion import Motion
from reference_motion.quality import motion_quality

HELD_OUT = ("deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1", "deepmimic:run", "deepmimic:spinkick",
            "deepmimic:jump", "deepmimic:kick")
"""DeepMimic clips in pybullet_data, none in the training set (which is the library's train split)."""
FAST = ("deepmimic:run", "deepmimic:spinkick", "deepmimic:kick")
PPO_CLIPS = ("deepmimic:walker/turn_left1", "deepmimic:run", "deepmimic:spinkick")
"""Takes the PPO cleaner also cleans (IMU-corrupted), side by side."""
VGRF_CLIP = "deepmimic:walker/turn_left1"
PENETRATION_TOLERANCE_M = 0.005
MAX_LAG = 15


def tracking_lag(simulated: np.ndarray, reference: np.ndarray, max_lag: int = MAX_LAG) -> float:
    """Frames by which ``simulated (T, J)`` trails ``reference (T, J)``: the shift ``s`` maximising
    ``Σ_t Σ_j a_j(t + s) b_j(t)`` (mean-removed, per overlap length), refined by a parabola."""
    a, b = simulated - simulated.mean(0), reference - reference.mean(0)
    T = len(a)
    shifts = range(-max_lag, max_lag + 1)
    corr = np.array([(a[s:] * b[:T - s]).sum() / (T - s) if s >= 0 else (a[:T + s] * b[-s:]).sum() / (T + s)
                     for s in shifts])
    i = int(np.argmax(corr))
    offset = 0.0
    if 0 < i < len(corr) - 1:
        y0, y1, y2 = corr[i - 1:i + 2]
        denom = y0 - 2 * y1 + y2
        offset = 0.5 * (y0 - y2) / denom if denom != 0 else 0.0
    return float(shifts[i] + offset)


def mpjpe_cm(qpos: np.ndarray, reference: np.ndarray, model: str, aligned: bool) -> float:
    """Mean body-origin distance (cm) of ``qpos`` from ``reference`` (both ``(T, nq)``); ``aligned``
    subtracts each frame's pelvis position first."""
    hm = load_model(model)
    a, b = hm.forward_kinematics(qpos).body_pos, hm.forward_kinematics(reference).body_pos
    if aligned:
        a, b = a - a[:, :1], b - b[:, :1]
    return 100.0 * float(np.linalg.norm(a - b, axis=-1).mean())


def quality_row(cleaned: Motion, target: Motion, truth: Motion, corrupted: bool) -> dict:
    """Tracking and artefact measures of ``cleaned`` (see the module docstring)."""
    report = motion_quality(cleaned)
    kin = load_model(cleaned.model).forward_kinematics(cleaned.qpos)
    lowest = kin.lowest
    return {"lag_frames": tracking_lag(cleaned.hinges, truth.hinges),
            "mpjpe_cm": mpjpe_cm(cleaned.qpos, truth.qpos, cleaned.model, aligned=corrupted),
            "foot_skate_mps": report.foot_skate_mps, "penetration_max_m": report.penetration_max_m,
            "penetration_mean_m": report.penetration_mean_m, "jitter": report.jitter,
            "non_penetration_share": float((lowest >= -PENETRATION_TOLERANCE_M).mean()),
            "non_penetration_share_strict": float((lowest >= 0).mean()),
            "foot_points_non_penetration_share": float((kin.foot_points[..., 2].min(-1)
                                                        >= -PENETRATION_TOLERANCE_M).mean()),
            "reanchors": len(cleaned.source.get("reanchors", []))}


def mean_rows(rows: list[dict]) -> dict:
    return {k: float(np.mean([r[k] for r in rows])) for k in rows[0] if k != "clip"}


def held_out_takes(library_takes: int) -> list[str]:
    takes = list(HELD_OUT)
    if library_takes and Path("data/library/manifest.json").exists():
        takes += expand_clips(["library:data/library/test"])[:library_takes]
    return takes


def run_cycle(cycle: DynamicCycle, targets: list[Motion]) -> tuple[list[Motion], list[dict], float, float]:
    """All ``targets`` in one batch: the motions, root-force reports, the wall time and this
    process's CPU time (s; one thread, so the time on a core of its own when others share them)."""
    start, cpu = time.perf_counter(), time.process_time()
    performance = clean_motions(cycle, targets, DiffPDCleanConfig(progress=False))
    return performance.motions, performance.reports, time.perf_counter() - start, time.process_time() - cpu


def variant(cycle: DynamicCycle, **changes) -> DynamicCycle:
    """``cycle``'s networks in a cycle whose configuration has ``changes`` (e.g. another residual bound)."""
    other = DynamicCycle(dataclasses.replace(cycle.config, **changes))
    other.dynet, other.grfnet = cycle.dynet, cycle.grfnet
    return other


SWEEP_KEYS = ("lag_frames", "mpjpe_cm", "foot_skate_mps", "non_penetration_share", "jitter", "reanchors",
              "residual_linear_bw_mean", "residual_angular_nm_mean", "residual_linear_saturated_share",
              "residual_angular_saturated_share", "root_virtual_linear_bw_mean", "grf_vertical_bw_mean")


def sweep_row(cycle: DynamicCycle, names: list[str], targets: list[Motion], truths: list[Motion],
              corrupted: bool) -> dict:
    motions, reports, _, cpu = run_cycle(cycle, targets)
    rows = [{"clip": n, **quality_row(m, t, g, corrupted), **r}
            for n, m, t, g, r in zip(names, motions, targets, truths, reports)]
    mean, fast = mean_rows(rows), mean_rows([r for r in rows if r["clip"] in FAST])
    return {**{k: mean[k] for k in SWEEP_KEYS}, "fast_lag_frames": fast["lag_frames"], "cpu_s": cpu}


def torch_cycle_speed(cycle: DynamicCycle, clip: Motion) -> float:
    """Frames per CPU-second of the torch cycle (``DynamicCycle.frame`` under ``torch.inference_mode``)
    on one clip: the path cleaning used before :mod:`agents.diffpd_fast`."""
    q, qd = torch.tensor(clip.qpos[:1]), torch.tensor(clip.qvel[:1])
    targets = torch.tensor(clip.qpos)
    cpu = time.process_time()
    with torch.inference_mode():
        for t in range(1, clip.n_frames):
            out = cycle.frame(q, qd, targets[t:t + 1])
            q, qd = out.q, out.qd
    return (clip.n_frames - 1) / (time.process_time() - cpu)


def vgrf_vs_mujoco(cycle: DynamicCycle, ppo: str) -> dict:
    """GRFNet's total vertical force vs MuJoCo's contact forces on the PPO policy's re-performance."""
    import envs  # noqa: F401  (registers the ids)
    from agents.physics_dataset import DatasetConfig, FrameRecorder, insole
    from agents.policy import load_policy
    from agents.rollout import run_episode

    policy = load_policy(ppo)
    reference = load_motion(VGRF_CLIP, cycle.config.model)
    env = policy.make_env([reference], artefacts=None, episode_frames=reference.n_frames - 1)
    recorder = FrameRecorder(cycle.config.model)
    base = env.unwrapped
    base.frame_hook, base.substep_hook = recorder, recorder.substep
    episode = run_episode(env, policy, {"clip": 0, "start_frame": 0})
    env.close()
    frames = recorder.take(len(recorder.frames["qpos"]))
    mujoco_bw = frames["forces"].sum((1, 2))  # (N,) body weights, frames 1..N of the episode
    smoothing_s = DatasetConfig().insole_smoothing_s
    mujoco_smooth = insole(frames["forces"], reference.fps, smoothing_s).sum((1, 2))
    simulated = reference.with_qpos(episode.qpos, name=f"{VGRF_CLIP} (PPO, MuJoCo)", loop=False)
    out = {"clip": VGRF_CLIP, "policy": ppo, "frames": int(len(mujoco_bw)), "ended_by": episode.ended_by}
    prior = copy.deepcopy(cycle)
    prior.grfnet = GRFNet(cycle.n_points, cycle.weight, cycle.config.mu, cycle.config.grfnet_hidden).to(
        cycle.config.dtype)  # untrained: the body weight shared evenly by the points in contact
    for label, c in (("grfnet", cycle), ("even_split", prior)):
        perf = clean_motions(c, [simulated], DiffPDCleanConfig(progress=False))
        lam = perf.vgrf[0][1:].sum(-1) / cycle.weight  # frames 1..N
        total = lam + perf.floor_vgrf[0][1:].sum(-1) / cycle.weight
        # GRFNet's λ alone, and λ plus the floor projection's impulses (the cycle's whole support)
        for name, predicted in ((label, lam), (f"{label}_plus_floor", total)):
            n = min(len(predicted), len(mujoco_bw))
            out[name] = {"mean_predicted_bw": float(predicted.mean())}
            for kind, series in (("raw", mujoco_bw), ("insole", mujoco_smooth)):
                p, m = predicted[:n], series[:n]
                out[name][f"rmse_bw_pct_{kind}"] = 100 * float(np.sqrt(np.mean((p - m) ** 2)))
                out[name][f"correlation_{kind}"] = (float(np.corrcoef(p, m)[0, 1])
                                                    if p.std() > 0 and m.std() > 0 else None)
    out["mean_mujoco_bw"] = float(mujoco_bw.mean())
    out["insole_smoothing_s"] = smoothing_s
    return out


def ppo_side_by_side(ppo: str, diffpd: DynamicCycle, clips: list[str], strength: float) -> dict:
    """The PPO cleaner (zero-shot) and diff-PD (batch of one) on the same IMU-corrupted clips."""
    import envs  # noqa: F401
    from agents.clean import POLICY_ALONE, clean_motion  # as measured: the policy alone
    from agents.policy import load_policy
    from envs.config import FOOT_MODELS

    start = time.perf_counter()
    policy = load_policy(ppo)
    load_s = time.perf_counter() - start
    rows = []
    for i, clip in enumerate(clips):
        truth = load_motion(clip, FOOT_MODELS[policy.foot])
        target = corrupt(truth, ArtefactRecipe.imu().scaled(strength), 1000 + HELD_OUT.index(clip))
        start, cpu = time.perf_counter(), time.process_time()
        cleaned = clean_motion(policy, target, POLICY_ALONE, progress=False)
        ppo_s, ppo_cpu = time.perf_counter() - start, time.process_time() - cpu
        [ours], _, ours_s, ours_cpu = run_cycle(diffpd, [target])
        rows.append({"clip": clip, "frames": target.n_frames,
                     "ppo": {**quality_row(cleaned, target, truth, True), "wall_s": ppo_s, "cpu_s": ppo_cpu,
                             "simulated_fraction": cleaned.source["simulated_fraction"]},
                     "diffpd": {**quality_row(ours, target, truth, True), "wall_s": ours_s, "cpu_s": ours_cpu}})
    mean = {who: mean_rows([r[who] for r in rows]) for who in ("ppo", "diffpd")}
    return {"policy": ppo, "policy_load_s": load_s, "adaptation": False, "takes": rows, "mean": mean,
            "time_ratio_ppo_over_diffpd": mean["ppo"]["wall_s"] / mean["diffpd"]["wall_s"],
            "cpu_time_ratio_ppo_over_diffpd": mean["ppo"]["cpu_s"] / mean["diffpd"]["cpu_s"]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--model", type=Path, default=Path("models/diffpd"))
    p.add_argument("--ppo", default="models/mimic_general", help="PPO policy for the vGRF and cleaner comparisons")
    p.add_argument("--no-ppo", action="store_true", help="skip everything that needs the PPO policy")
    p.add_argument("--library-takes", type=int, default=6, help="library test takes added (0: none)")
    p.add_argument("--strength", type=float, default=1.0, help="IMU artefact strength")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    torch.set_num_threads(1)
    t0 = time.perf_counter()
    learned = load_cycle(args.model)
    if learned.dynet is None:
        raise SystemExit(f"error: {args.model} has fixed gains; the bench compares a trained DyNet with them")
    fixed = copy.deepcopy(learned)
    fixed.dynet = None
    no_grf = copy.deepcopy(learned)
    no_grf.grfnet = None
    cycles = {"learned": learned, "fixed": fixed, "no_grf": no_grf}
    model = learned.config.model
    names = held_out_takes(args.library_takes)
    truths = [load_motion(n, model) for n in names]
    recipe = ArtefactRecipe.imu().scaled(args.strength)
    corrupted = [corrupt(m, recipe, 1000 + i) for i, m in enumerate(truths)]
    results: dict = {"model": str(args.model), "takes": names, "fast_takes": [n for n in names if n in FAST],
                     "strength": args.strength, "torch_threads": torch.get_num_threads()}
    frames = sum(m.n_frames - 1 for m in truths)
    results["reference"] = {kind: mean_rows([{"clip": n, **quality_row(t, t, g, kind == "imu")}
                                             for n, t, g in zip(names, targets, truths)])
                            for kind, targets in (("clean", truths), ("imu", corrupted))}
    for kind, m in results["reference"].items():
        print(f"{kind:<5} {'input':<8} lag {m['lag_frames']:5.2f} fr, MPJPE {m['mpjpe_cm']:5.1f} cm, skate "
              f"{m['foot_skate_mps']:.3f} m/s, non-penetration {m['non_penetration_share']:.1%}, "
              f"jitter {m['jitter']:.0f}")
    for kind, targets in (("clean", truths), ("imu", corrupted)):
        per = {}
        for label, cycle in cycles.items():
            motions, reports, wall, cpu = run_cycle(cycle, targets)
            rows = [{"clip": n, **quality_row(m, t, g, kind == "imu"), **r}
                    for n, m, t, g, r in zip(names, motions, targets, truths, reports)]
            per[label] = {"takes": rows, "mean": mean_rows(rows),
                          "fast_mean": mean_rows([r for r in rows if r["clip"] in FAST]),
                          "batch_frames_per_s": frames / wall, "batch_frames_per_cpu_s": frames / cpu}
            m = per[label]["mean"]
            print(f"{kind:<5} {label:<8} lag {m['lag_frames']:5.2f} fr, MPJPE {m['mpjpe_cm']:5.1f} cm, skate "
                  f"{m['foot_skate_mps']:.3f} m/s, non-penetration {m['non_penetration_share']:.1%}, jitter "
                  f"{m['jitter']:.0f}, root force {m['root_virtual_linear_bw_mean']:.3f} BW, "
                  f"{per[label]['batch_frames_per_s']:.0f} frames/s, {per[label]['batch_frames_per_cpu_s']:.0f} per "
                  f"CPU-s (batch of {len(targets)})")
        lag_f, lag_l = per["fixed"]["mean"]["lag_frames"], per["learned"]["mean"]["lag_frames"]
        per["lag_cut"] = 1.0 - lag_l / lag_f if lag_f else None
        per["lag_cut_fast"] = 1.0 - per["learned"]["fast_mean"]["lag_frames"] / per["fixed"]["fast_mean"]["lag_frames"]
        per["root_force_ratio_no_grf_over_grf"] = (per["no_grf"]["mean"]["root_virtual_linear_bw_mean"]
                                                   / per["learned"]["mean"]["root_virtual_linear_bw_mean"])
        print(f"{kind}: learned gains cut the lag by {per['lag_cut']:.1%} (fast takes {per['lag_cut_fast']:.1%}); "
              f"without GRF the root needs {per['root_force_ratio_no_grf_over_grf']:.1f}x the force")
        results[kind] = per
    # the root residual's bound (cleaning-time; the networks were trained at the model's bound) and the
    # no-slip constraint, on the IMU-corrupted takes
    rho, weight = learned.config.residual_bound, learned.weight
    bounds = [(0.2, 200.0), (0.5, 100.0), (0.5, 200.0), (1.0, 200.0), (math.inf, math.inf)]
    results["residual_bound"] = {"trained_linear_bw": rho[0] / weight, "trained_angular_nm": rho[1],
                                 "saturated_means": "share of iterations with a component of tau*_root at or "
                                                    "beyond its bound (the residual at >= 76% of it)",
                                 "sweep_imu": []}
    for lin, ang in bounds:
        row = sweep_row(variant(learned, residual_bound=(lin * weight, ang)), names, corrupted, truths, True)
        results["residual_bound"]["sweep_imu"].append({"linear_bw": None if math.isinf(lin) else lin,
                                                       "angular_nm": None if math.isinf(ang) else ang, **row})
        print(f"imu   bound {lin:g} BW / {ang:g} N·m: lag {row['lag_frames']:.2f} fr, MPJPE {row['mpjpe_cm']:.1f} cm, "
              f"skate {row['foot_skate_mps']:.3f}, non-penetration {row['non_penetration_share']:.1%}, re-anchors "
              f"{row['reanchors']:.2f}/take, residual {row['residual_linear_bw_mean']:.2f} BW (saturated "
              f"{row['residual_linear_saturated_share']:.0%}) / {row['residual_angular_nm_mean']:.0f} N·m "
              f"({row['residual_angular_saturated_share']:.0%})")
    slip = variant(learned, no_slip_height=0.0)
    results["no_slip"] = {"height_m": learned.config.no_slip_height,
                          **{f"{kind}_{label}": sweep_row(c, names, targets, truths, kind == "imu")
                             for kind, targets in (("clean", truths), ("imu", corrupted))
                             for label, c in (("with", learned), ("without", slip))}}
    for kind in ("clean", "imu"):
        a, b = results["no_slip"][f"{kind}_without"], results["no_slip"][f"{kind}_with"]
        print(f"{kind:<5} foot skate without no-slip {a['foot_skate_mps']:.3f} m/s, with {b['foot_skate_mps']:.3f} "
              f"(input {results['reference'][kind]['foot_skate_mps']:.3f}); non-penetration "
              f"{a['non_penetration_share']:.1%} / {b['non_penetration_share']:.1%}")
    # speed of one clip alone (batch of one), one thread
    single = truths[names.index("deepmimic:run")]
    _, _, wall, cpu = run_cycle(learned, [single])
    results["speed"] = {"single_clip": "deepmimic:run", "single_frames_per_s": (single.n_frames - 1) / wall,
                        "single_frames_per_cpu_s": (single.n_frames - 1) / cpu,
                        "batch_frames_per_s": results["clean"]["learned"]["batch_frames_per_s"],
                        "batch_frames_per_cpu_s": results["clean"]["learned"]["batch_frames_per_cpu_s"],
                        "batch_size": len(truths), "load_average": list(os.getloadavg()), "cpu_count": os.cpu_count()}
    results["speed"]["single_frames_per_cpu_s_torch_cycle"] = torch_cycle_speed(learned, single)
    sp = results["speed"]
    print(f"speed (1 thread): one clip {sp['single_frames_per_s']:.0f} frames/s wall, "
          f"{sp['single_frames_per_cpu_s']:.0f} per CPU-s (torch cycle "
          f"{sp['single_frames_per_cpu_s_torch_cycle']:.0f}); batch of {len(truths)} {sp['batch_frames_per_s']:.0f} wall, "
          f"{sp['batch_frames_per_cpu_s']:.0f} per "
          f"CPU-s (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    if not args.no_ppo:
        results["vgrf_vs_mujoco"] = v = vgrf_vs_mujoco(learned, args.ppo)
        for label in ("grfnet", "grfnet_plus_floor", "even_split", "even_split_plus_floor"):
            g = v[label]
            print(f"vGRF vs MuJoCo ({v['clip']}, {v['frames']} frames), {label}: RMSE {g['rmse_bw_pct_raw']:.1f}% BW "
                  f"raw / {g['rmse_bw_pct_insole']:.1f}% insole-smoothed (r = {g['correlation_raw']:.2f} / "
                  f"{g['correlation_insole']:.2f}); mean {g['mean_predicted_bw']:.2f} BW vs {v['mean_mujoco_bw']:.2f}")
        results["ppo_vs_diffpd"] = s = ppo_side_by_side(args.ppo, learned, list(PPO_CLIPS), args.strength)
        for who in ("ppo", "diffpd"):
            m = s["mean"][who]
            print(f"IMU takes, {who:<6}: MPJPE {m['mpjpe_cm']:.1f} cm, lag {m['lag_frames']:.2f} fr, skate "
                  f"{m['foot_skate_mps']:.3f} m/s, non-penetration {m['non_penetration_share']:.1%}, jitter "
                  f"{m['jitter']:.0f}, {m['wall_s']:.2f} s ({m['cpu_s']:.2f} CPU-s) a take")
    skate_in = results["reference"]["imu"]["foot_skate_mps"]
    results["imu_foot_skate_cut"] = 1.0 - results["imu"]["learned"]["mean"]["foot_skate_mps"] / skate_in
    results["goals"] = {"lag_cut_ge_30pct": results["clean"]["lag_cut"] >= 0.30,
                        "imu_foot_skate_cut_ge_80pct": results["imu_foot_skate_cut"] >= 0.80,
                        "residual_bounded": bool(np.isfinite(rho).all()),
                        "non_penetration_ge_95pct":
                            results["clean"]["learned"]["mean"]["non_penetration_share"] >= 0.95,
                        "speed_ge_200_fps_single_cpu": results["speed"]["single_frames_per_cpu_s"] >= 200,
                        "speed_ge_200_fps_batch_cpu": results["speed"]["batch_frames_per_cpu_s"] >= 200}
    results["wall_s"] = time.perf_counter() - t0
    print(f"goals: {results['goals']}; {results['wall_s']:.0f} s")
    emit_json(results, args.json)


if __name__ == "__main__":
    main()
