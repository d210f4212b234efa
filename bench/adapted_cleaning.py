"""The main job on takes never seen: adapt the generalist to each take, clean it, and score it.

Usage: ``python bench/adapted_cleaning.py --policy models/mimic_general [--takes 10]
[--seconds 10] [--strength 1] [--seed 5000] [--adapt-budget-s 300] [--adapt-steps N]
[--adapt-target-kl KL] [--adapt-target SR90|none] [--adapt-keep evaluation|performance]
[--physics-threads N] [--settings 0.5x4 1:searchall:16x64] [--denoise [DIR]] [--obs-frame F] [--physics-rate-hz HZ]
[--out-dir DIR] [--only I ...] [--no-adapt] [--mirror-average]
[--json [OUT]]``; ``--merge RUN.json ...`` summarises runs of single takes (``--only``) together.

For each of ``--takes`` takes of the library's test split (styles never trained on, spread over
the split's motions), cut to ``--seconds`` (cyclic clips looped to it; a shorter take is used
whole: the library's takes are not cyclic) and IMU-corrupted at ``--strength`` with
seed ``--seed + i`` (seeds no training run uses: training variants come from the run's seed), the
policy is adapted to the corrupted take (:mod:`agents.adaptation`, per-take budget
``--adapt-budget-s``, stopping at SR90 ``--adapt-target`` and keeping the chunk ``--adapt-keep``
ranks best; a fresh cache so nothing is reused) and cleans it (:func:`agents.clean.clean_motion`)
with each of ``--settings`` (:class:`agents.clean.CleanConfig` as ``bench/clean_settings.py`` names
them: by default the policy alone with stochastic retries, and clean.py's default, every stretch
searched), side by side. Reported per take and setting and summarised: whether the whole take was simulated without a re-anchor
(goal: ≥ 9 of 10), ELR of the adapted policy on the take (ADAPT's protocol; goal ≥ 0.97), foot
skate, floating and penetration of the cleaned take against the corrupted input (goal: each
≥ 80% lower; jitter too), the same after the contact touch-up (``clean.py --touch-up``,
:mod:`reference_motion.touch_up`), and the adaptation wall time (median and max; goal ≤ 5 min for 10 s).
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.adaptation import KEEP_RULES, AdaptConfig, adapt_policy, evaluate_on_clip
from agents.clean import CleanConfig, clean_motion, sr90_target, touched_up
from clean_settings import label, setting  # bench/clean_settings.py: the scripts run from bench/
from agents.policy_set import member_denoiser, route_clips
from envs.config import FOOT_MODELS
from envs.observations import SAME_LAYOUT_FRAMES
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import add_denoise_option, denoise
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.library import expand_clips, load_motion
from reference_motion.motion import Motion
from reference_motion.quality import motion_quality

ARTEFACTS = ("foot_skate_mps", "floating_m", "penetration_max_m", "penetration_mean_m", "jitter")
"""The artefacts compared with the input (the issue's goal names the first four; the touch-up's
leg IK adds jitter)."""


def spread(items: list[str], n: int) -> list[str]:
    """``n`` items spread evenly over ``items`` (all of them when there are no more than ``n``)."""
    if len(items) <= n:
        return list(items)
    return [items[i] for i in np.linspace(0, len(items) - 1, n).round().astype(int)]


def cut_take(clip: str, foot: str, seconds: float) -> Motion:
    """``clip`` on the ``foot`` model (cyclic clips looped), cut to ``seconds`` at 60 Hz (a shorter
    take whole)."""
    frames = int(round(seconds * 60)) + 1
    take = load_motion(clip, FOOT_MODELS[foot], min_frames=frames)
    return take.with_qpos(take.qpos[:frames], loop=False) if take.n_frames > frames else take


def corrupted_take(clip: str, foot: str, seconds: float, strength: float, seed: int) -> Motion:
    """:func:`cut_take` IMU-corrupted at ``strength`` with ``seed``."""
    return corrupt(cut_take(clip, foot, seconds), ArtefactRecipe.imu().scaled(strength), seed)


def reduction_of(before: float, after: float) -> float:
    """How far ``after`` is below ``before`` as a fraction of it (NaN where ``before`` is 0)."""
    return 1 - after / before if before > 0 else float("nan")


def reduction(fraction: float) -> str:
    """A reduction below the input as printed: ``-52%``, ``+109%`` for an increase, ``n/a`` where
    the input had none of the artefact (NaN)."""
    return "n/a" if np.isnan(fraction) else f"{-fraction:+.0%}"


def cleaning(policy, reference: Motion, before: dict, config: CleanConfig, out_stem: Path | None) -> dict:
    """``reference`` cleaned by ``policy`` with ``config``, touched up, and scored against the
    artefact metrics ``before`` of the take as given (``reference`` itself, or the take it was
    denoised from): a report row (written as ``OUT_STEM_{simulated,touched}.npz``
    too with ``out_stem``)."""
    start = time.perf_counter()
    cleaned = clean_motion(policy, reference, config, progress=False)
    clean_s = time.perf_counter() - start
    touched, touch = touched_up(cleaned)
    after = motion_quality(cleaned).as_dict()
    touched_after = motion_quality(touched).as_dict()
    if out_stem:
        for kind, motion in (("simulated", cleaned), ("touched", touched)):
            motion.save(out_stem.with_name(f"{out_stem.name}_{kind}.npz"))
    return {"setting": label(config), "reanchors": len(cleaned.source["reanchors"]),
            "recoveries": len(cleaned.source["recoveries"]), "clean_s": clean_s,
            **{f"{k}_input": before[k] for k in ARTEFACTS}, **{f"{k}_output": after[k] for k in ARTEFACTS},
            **{f"{k}_reduction": reduction_of(before[k], after[k]) for k in ARTEFACTS},
            **{f"{k}_touched_output": touched_after[k] for k in ARTEFACTS},
            **{f"{k}_touched_reduction": reduction_of(before[k], touched_after[k]) for k in ARTEFACTS},
            "touch_up": touch.as_dict()}


def summary_of(rows: list[dict], setting_label: str) -> dict:
    """The takes' figures with the cleaning ``setting_label`` summarised."""
    cleanings = [next(c for c in r["cleanings"] if c["setting"] == setting_label) for r in rows]
    return {"setting": setting_label, "takes": len(rows), "no_reanchor": sum(c["reanchors"] == 0 for c in cleanings),
            "reanchors": sum(c["reanchors"] for c in cleanings),
            "clean_s_median": float(np.median([c["clean_s"] for c in cleanings])),
            **{f"{k}_{kind}_median": float(np.nanmedian([c[f"{k}_{kind}"] for c in cleanings]))
               for k in ARTEFACTS for kind in ("reduction", "touched_reduction")}}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", default="models/mimic_general")
    p.add_argument("--clips", nargs="+", default=["library:data/library/test"], help="takes to draw from")
    p.add_argument("--takes", type=int, default=10)
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--seed", type=int, default=5000, help="artefact seed of the first take (take i: seed + i)")
    p.add_argument("--adapt-budget-s", type=float, default=300.0)
    p.add_argument("--adapt-steps", type=int, default=None, help="also stop each adaptation after this many steps")
    p.add_argument("--adapt-target-kl", type=float, default=None,
                   help="adapt with the KL-following learning rate (AdaptConfig.target_kl)")
    p.add_argument("--adapt-target", type=sr90_target, default=AdaptConfig.target_sr90,
                   help="stop adapting once SR90 reaches this; 'none': train to the budget")
    p.add_argument("--adapt-keep", choices=KEEP_RULES, default=AdaptConfig.keep,
                   help="which chunk an adaptation keeps (agents.adaptation.AdaptConfig.keep)")
    p.add_argument("--physics-threads", type=int, default=1,
                   help="threads stepping each adaptation's physics (AdaptConfig.physics_threads; 1: the "
                        "protocol runs two of these processes at once, one per core)")
    p.add_argument("--settings", nargs="+", type=setting, default=[setting(s) for s in ("0.5x4", "1:searchall:16x64")],
                   help="how each adapted take is cleaned (bench/clean_settings.py), side by side")
    add_denoise_option(p, "each corrupted take is adapted to and cleaned after it, as clean.py --denoise does; the "
                          "artefacts are compared with the take as given, the ELR is the adapted policy's on the take "
                          "it performs (the denoised one)")
    p.add_argument("--out-dir", type=Path, default=None,
                   help="also write each take's input and, per setting K, its simulated and touched-up clips here (.npz)")
    p.add_argument("--obs-frame", choices=SAME_LAYOUT_FRAMES, default=None,
                   help="adapt and clean with the policy observing in this frame (MimicPolicy.observing; default: "
                        "the frame its sidecar records)")
    p.add_argument("--physics-rate-hz", type=float, default=None, metavar="HZ",
                   help="adapt and clean with the physics at this rate (MimicPolicy.simulating; default: the rate "
                        "its sidecar records)")
    p.add_argument("--no-adapt", action="store_true",
                   help="clean zero-shot with the policy as given; its ELR is scored on each take as adaptation "
                        "scores a chunk (agents.adaptation.evaluate_on_clip) and stands for the adapted one")
    p.add_argument("--mirror-average", action="store_true",
                   help="clean with the policy's mirror-symmetric actor (agents/mirror.py), after any adaptation, "
                        "as clean.py --mirror-average; with --no-adapt the ELR is that actor's too, else the "
                        "adapted network's own")
    p.add_argument("--only", nargs="+", type=int, default=None, metavar="I",
                   help="run only these of the takes (0-based, keeping their seeds seed + I): one process per take "
                        "on a machine with many cores, summarised together by --merge")
    p.add_argument("--merge", nargs="+", type=Path, default=None, metavar="JSON",
                   help="run nothing: summarise the takes of these --json outputs together (one run's settings)")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    if args.merge:
        runs = [json.loads(path.read_text()) for path in args.merge]
        differ = [k for k in ("policy", "no_adapt", "mirror_average", "obs_frame", "physics_rate_hz", "denoiser", "settings", "adapt_budget_s", "seconds", "strength")
                  if any(run.get(k) != runs[0].get(k) for run in runs)]
        if differ:
            p.error(f"--merge: the runs differ in {', '.join(differ)}; merge runs of one protocol only")
        rows = [{**row, "cleanings": [{k: math.nan if v is None else v for k, v in c.items()}  # JSON null: NaN
                                      for c in row["cleanings"]]} for run in runs for row in run["takes"]]
        report(rows, [c["setting"] for c in rows[0]["cleanings"]], {**runs[0], "merged": list(map(str, args.merge))},
               args.json)
        return
    frames = int(round(args.seconds * 60)) + 1
    denoiser = load_network(Path(args.denoise), "denoiser") if args.denoise else None
    takes = spread(expand_clips(args.clips), args.takes)
    outside = sorted(set(args.only or []) - set(range(len(takes))))
    if outside:
        p.error(f"--only {' '.join(map(str, outside))}: there are {len(takes)} takes, 0..{len(takes) - 1}")
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        for i, clip in enumerate(takes):
            if args.only is not None and i not in args.only:
                continue
            [(policy, [reference])] = route_clips(args.policy, lambda foot: [corrupted_take(
                clip, foot, args.seconds, args.strength, args.seed + i)])
            if args.obs_frame:
                policy = policy.observing(args.obs_frame)
            if args.physics_rate_hz:
                policy = policy.simulating(args.physics_rate_hz)
            looped = reference.n_frames >= frames
            config = AdaptConfig(budget_s=args.adapt_budget_s, max_steps=args.adapt_steps,
                                 target_kl=args.adapt_target_kl, target_sr90=args.adapt_target,
                                 keep=args.adapt_keep, physics_threads=args.physics_threads, cache_dir=Path(cache))
            behind = member_denoiser(args.policy, policy, denoiser)  # a set may slow its member's corrections
            performed = denoise(behind, reference) if behind else reference
            if args.no_adapt:  # zero-shot: the actor that cleans, scored on the take as adaptation scores it
                env = policy.make_env([performed], artefacts=None)
                performer = policy.mirror_averaged(env) if args.mirror_average else policy
                zero_shot = evaluate_on_clip(env, performer, config.eval_episodes)
                env.close()
                adapt = {"ELR_before": zero_shot["ELR_mean"], "ELR": zero_shot["ELR_mean"], "SR90": zero_shot["SR90"],
                         "adapt_s": 0.0, "adapt_steps": 0}
            else:  # ELR: the adapted network's own, as adaptation scored it (before any --mirror-average)
                adapted = adapt_policy(policy, performed, config, progress=False)
                performer, adapt = adapted.policy, {"ELR_before": adapted.elr_before, "ELR": adapted.elr_after,
                                                    "SR90": adapted.sr90_after, "adapt_s": adapted.wall_s,
                                                    "adapt_steps": adapted.steps}
                if args.mirror_average:
                    performer = performer.mirror_averaged_on(performed)
            stem = args.out_dir / f"{i:02d}_{clip.split('#')[-1]}" if args.out_dir else None
            if stem:
                reference.save(stem.with_name(f"{stem.name}_input.npz"))
            before = motion_quality(reference).as_dict()
            row = {"clip": clip, "frames": reference.n_frames, "full_length": looped, "seed": args.seed + i,
                   **adapt, "cleanings": [cleaning(performer, performed, before, c,
                                          stem and stem.with_name(f"{stem.name}_{k}"))
                                 for k, c in enumerate(args.settings)]}
            rows.append(row)
            print(f"{clip.split('#')[-1]:<34} ELR {row['ELR_before']:.2f} -> {row['ELR']:.2f}  adapt "
                  f"{row['adapt_s']:.0f} s", flush=True)
            for c in row["cleanings"]:
                print(f"    {c['setting']:<26} re-anchors {c['reanchors']:2d}  skate "
                      f"{reduction(c['foot_skate_mps_reduction'])}  float {reduction(c['floating_m_reduction'])}  "
                      f"pen {reduction(c['penetration_max_m_reduction'])}  clean {c['clean_s']:.0f} s; touched up: "
                      f"skate {reduction(c['foot_skate_mps_touched_reduction'])}  "
                      f"float {reduction(c['floating_m_touched_reduction'])}  "
                      f"pen {reduction(c['penetration_max_m_touched_reduction'])}", flush=True)
    report(rows, [label(c) for c in args.settings],
           {"policy": args.policy, "no_adapt": args.no_adapt, "mirror_average": args.mirror_average,
            "obs_frame": args.obs_frame, "physics_rate_hz": args.physics_rate_hz,
            "denoiser": args.denoise, "seconds": args.seconds,
            "strength": args.strength,
            "adapt_budget_s": args.adapt_budget_s, "adapt_steps": args.adapt_steps,
            "adapt_target_kl": args.adapt_target_kl, "adapt_target": args.adapt_target,
            "adapt_keep": args.adapt_keep, "physics_threads": args.physics_threads,
            "settings": [asdict(c) for c in args.settings]}, args.json)


def report(rows: list[dict], settings: list[str], run: dict, target: str | None) -> None:
    """Print the summary of the takes ``rows`` cleaned with each of ``settings`` (labels) and emit
    it with ``run`` (what the run was: policy, budgets, settings) as JSON to ``target``."""
    adapt_s = [r["adapt_s"] for r in rows]
    summary = {"takes": len(rows), "ELR_mean": float(np.mean([r["ELR"] for r in rows])),
               "adapt_s_median": float(np.median(adapt_s)), "adapt_s_max": float(np.max(adapt_s)),
               "cleanings": [summary_of(rows, setting) for setting in settings]}
    print(f"\nELR {summary['ELR_mean']:.3f} (goal >= 0.97); adaptation median {summary['adapt_s_median']:.0f} s, "
          f"max {summary['adapt_s_max']:.0f} s (goal <= 300 s)")
    for c in summary["cleanings"]:
        print(f"{c['setting']}: no re-anchor on {c['no_reanchor']} of {c['takes']} takes (goal >= 9 of 10), "
              f"{c['reanchors']} re-anchors; median reductions: "
              + ", ".join(f"{k} {c[f'{k}_reduction_median']:.0%}" for k in ARTEFACTS)
              + " (goal: the first four >= 80% each); touched up: "
              + ", ".join(f"{k} {c[f'{k}_touched_reduction_median']:.0%}" for k in ARTEFACTS))
    emit_json({**{k: v for k, v in run.items() if k not in ("summary", "takes")}, "summary": summary, "takes": rows},
              target)


if __name__ == "__main__":
    main()
