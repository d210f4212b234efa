"""ContactVision's gait reconstruction on held-out walks, and its Fig. 12 ablations, side by side.

Usage: ``python bench/gait_reconstruction.py --policies full=models/mimic_gait
[no_fc=DIR no_toeref=DIR one_segment=DIR] [--ablations none no_fc no_toeref] [--clips SOURCE ...]
[--seconds 10] [--episodes 5] [--adapt-budget-s S [--adapt-target SR90|none] [--adapt-variance V] [--adapt-lr LR]
[--adapt-keep evaluation|performance]]
[--json [OUT]]``

For each policy (a ``MimicGait-v0`` policy; the ablations are trained with
``agents/train_ppo.py --env-id MimicGait-v0 --gait-ablation no_fc|no_toeref`` or ``--foot one``,
or, with ``--ablations``, each policy is scored under each listed ablation of its task (``none``: as it is)
(:meth:`agents.policy.MimicPolicy.ablated`): the same weights adapted per sequence under the
ablated reward or toe targets, as ContactVision trains each ablation per sequence, and judged
against the same gait reference and contact targets as the policy itself)
and each held-out walk (default: the library test split's forward walks, styles never trained on),
the clip is re-performed end to end by ``agents/clean.py``'s algorithm (rewind-and-retry,
re-anchoring only as a last resort), zero-shot or, with ``--adapt-budget-s S``, by the policy
adapted to the clip first (:mod:`agents.adaptation`, at most ``S`` s per clip, a fresh cache;
stopping at SR90 0.9 unless ``--adapt-target none`` trains on to the budget, with the policy's own
exploration noise unless ``--adapt-variance``; ``agents/reconstruct_gait.py`` adapts as
``agents.reconstruct_gait.GAIT_ADAPTATION`` says; the joint RMSE and contact F1
before and after every chunk are kept in the JSON), and scored against its gait reference and contact targets
(:mod:`agents.gait_metrics`): joint-angle RMSE (goal ≤ 3°; ContactVision 3.27°), contact F1
against ĉ (goal ≥ 0.85), push-off peak toe angle and timing against the ToeRef target, forward
displacement error (goal ≤ 5%), the gait parameters of the simulated contacts against those of
ĉ, re-anchors; plus ADAPT's ELR / SR90 over ``--episodes`` 5-s segments per clip. Means over
the clips per policy are printed as one table; ``--json`` writes every per-clip figure too.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.adaptation import KEEP_RULES, AdaptConfig, adapt_policy
from agents.clean import POLICY_ALONE, clean_motion, sr90_target
from agents.evaluation import evaluate
from agents.policy import MimicPolicy, load_policy
from agents.reconstruct_gait import gait_targets, reconstruction_metrics
from envs.config import FOOT_MODELS, GAIT_ABLATIONS
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.cli import or_none, positive_float
from reference_motion.library import expand_clips, load_motion
from reference_motion.motion import Motion

CLIPS = tuple(f"library:data/library#dataset-1_walk_{style}_{take:03d}" for style in ("giant", "old", "tired")
              for take in (1, 2))
"""The library test split's six forward walks (three styles never trained on)."""

PARAMETERS = ("stance", "swing", "single_support", "double_support")


def score(policy_dir: str, clips: list[str], seconds: float, episodes: int, adapt_budget_s: float = 0.0,
          adapt_target: float | None = AdaptConfig.target_sr90, adapt_variance: float | None = None,
          ablation: str | None = None, adapt_lr: float | None = None, adapt_keep: str = AdaptConfig.keep) -> dict:
    """Per-clip metrics of one policy (adapted to each clip first when ``adapt_budget_s`` > 0, up
    to SR90 ``adapt_target``, with exploration noise ``adapt_variance`` and learning rate
    ``adapt_lr``, ``None``: the policy's own, keeping the chunk ``adapt_keep`` ranks best; under a gait ``ablation`` of its task when one is
    named) and their means."""
    judge = load_policy(policy_dir)
    generalist = judge.ablated(ablation) if ablation else judge
    with tempfile.TemporaryDirectory() as cache:  # adapted policies: a fresh cache, nothing reused
        adapt = (AdaptConfig(budget_s=adapt_budget_s, target_sr90=adapt_target, action_variance=adapt_variance,
                             learning_rate=adapt_lr, keep=adapt_keep,
                             cache_dir=Path(cache)) if adapt_budget_s > 0 else None)
        rows = [score_clip(generalist, clip, seconds, episodes, adapt, judge) for clip in clips]
    return {"policy": policy_dir, "ablation": ablation, "adapt_budget_s": adapt_budget_s, "adapt_target": adapt_target,
            "adapt_variance": adapt_variance, "adapt_lr": adapt_lr, "adapt_keep": adapt_keep, "clips": rows,
            "mean": means(rows)}


def score_clip(generalist: MimicPolicy, clip: str, seconds: float, episodes: int, adapt: AdaptConfig | None,
               judge: MimicPolicy | None = None) -> dict:
    """The metrics of one clip re-performed by ``generalist``, adapted to it first with ``adapt``
    (with the joint RMSE and contact F1 after every chunk), against the gait reference and contact
    targets of ``judge``'s task (default: ``generalist``'s own)."""
    reference = load_motion(clip, FOOT_MODELS[generalist.foot], min_frames=int(seconds * 60) + 1)
    reference = reference.with_qpos(reference.qpos[:int(seconds * 60) + 1], loop=False)
    targets, toe_targets, gait_reference = gait_targets(judge or generalist, reference)
    policy, adaptation = generalist, {}
    if adapt is not None:
        def quality(current: MimicPolicy, performed: Motion) -> dict:  # the clip as the policy now performs it
            m = reconstruction_metrics(performed, gait_reference, targets, toe_targets)
            return {"joint_rmse_deg": m["joint_rmse_deg"], "contact_f1": m["contact_f1"]}

        adapted = adapt_policy(generalist, reference, adapt, progress=False, on_chunk=quality)
        policy = adapted.policy
        adaptation = {"adapt_s": adapted.wall_s, "adapt_steps": adapted.steps, "ELR_before": adapted.elr_before,
                      "adapt_stopped_by": adapted.stopped_by, "adapt_before": adapted.before,
                      "adapt_chunks": adapted.chunks}
    start = time.perf_counter()
    simulated = clean_motion(policy, reference, POLICY_ALONE, progress=False)  # as measured: the policy alone
    wall = time.perf_counter() - start
    metrics = reconstruction_metrics(simulated, gait_reference, targets, toe_targets)
    metrics.pop("contacts")
    env = policy.make_env([reference], artefacts=None)
    evaluation, _ = evaluate(env, policy, episodes=episodes, offset_step=30)
    env.close()
    row = {"clip": clip, **metrics, "reanchors": len(simulated.source["reanchors"]),
           "ELR": evaluation["ELR_mean"], "SR90": evaluation["SR90"], "wall_s": wall, **adaptation}
    print(f"  {clip.split('#')[-1]:<32} RMSE {metrics['joint_rmse_deg']:5.2f} deg  F1 {metrics['contact_f1']:.3f}  "
          f"disp err {metrics['forward_displacement_error']:6.1%}  re-anchors {row['reanchors']}  "
          f"ELR {evaluation['ELR_mean']:.2f}", flush=True)
    return row


def means(rows: list[dict]) -> dict:
    """The mean of every scalar figure over the clips (push-off figures over the clips that have any)."""
    def mean(values: list[float]) -> float:
        finite = [v for v in values if v is not None and math.isfinite(v)]
        return float(np.mean(finite)) if finite else float("nan")

    out = {k: mean([r[k] for r in rows]) for k in ("joint_rmse_deg", "contact_f1", "forward_displacement_error",
                                                    "reanchors", "ELR", "SR90", "wall_s")}
    if "adapt_s" in rows[0]:
        out.update({k: mean([r[k] for r in rows]) for k in ("adapt_s", "ELR_before")})
    for k in ("peak_deg", "target_peak_deg", "timing_ms"):
        out[f"push_off_{k}"] = mean([r["push_off"][k] for r in rows])
    for who in ("simulated", "targets"):
        for k in PARAMETERS:
            out[f"{k}_{who}"] = mean([r["gait_parameters"][who][k] for r in rows])
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policies", nargs="+", required=True, metavar="NAME=DIR", help="policies to compare")
    p.add_argument("--ablations", nargs="+", choices=("none", *GAIT_ABLATIONS), default=["none"],
                   help="score each policy under these ablations of its task (none: as it is; rows NAME and "
                        "NAME-ABLATION; the same weights are adapted under the ablation, so it needs --adapt-budget-s)")
    p.add_argument("--clips", nargs="+", default=list(CLIPS), help="held-out walks (SOURCE strings or clip sets)")
    p.add_argument("--seconds", type=float, default=10.0, help="each clip looped or cut to this long")
    p.add_argument("--episodes", type=int, default=5, help="5-s segments per clip for ELR / SR90")
    p.add_argument("--adapt-budget-s", type=float, default=0.0,
                   help="adapt each policy to each clip for at most this long first (0: zero-shot)")
    p.add_argument("--adapt-target", type=sr90_target, default=AdaptConfig.target_sr90,
                   help="stop adapting once SR90 reaches this; 'none': train to the budget")
    p.add_argument("--adapt-variance", type=or_none(positive_float), default=None,
                   help="exploration noise σ² (rad²) while adapting ('none', the default: the policy's own)")
    p.add_argument("--adapt-lr", type=or_none(positive_float), default=None,
                   help="PPO learning rate while adapting ('none', the default: the policy's own)")
    p.add_argument("--adapt-keep", choices=KEEP_RULES, default=AdaptConfig.keep,
                   help="which chunk an adaptation keeps (agents.adaptation.AdaptConfig.keep)")
    p.add_argument("--json", nargs="?", const="-", default=None, help="write the results as JSON (to OUT, or print)")
    args = p.parse_args()
    adapting = args.adapt_variance is not None or args.adapt_lr is not None or args.adapt_keep != AdaptConfig.keep
    if adapting and not args.adapt_budget_s > 0:
        p.error("--adapt-variance, --adapt-lr and --adapt-keep set how a policy is adapted; they need --adapt-budget-s")
    if set(args.ablations) - {"none"} and not args.adapt_budget_s > 0:
        p.error("--ablations needs --adapt-budget-s: an ablation changes what a policy is trained on (no_fc: the "
                "reward alone), so the same weights zero-shot score as the policy itself")
    clips = expand_clips(args.clips)
    results = {}
    for item in args.policies:
        name, _, directory = item.partition("=")
        for ablation in [None if a == "none" else a for a in args.ablations]:
            row = name if ablation is None else f"{name}-{ablation}"
            print(f"{row} ({directory}{'' if ablation is None else f' under {ablation}'})", flush=True)
            results[row] = score(directory, clips, args.seconds, args.episodes, args.adapt_budget_s,
                                 args.adapt_target, args.adapt_variance, ablation, args.adapt_lr, args.adapt_keep)
    print(f"\n{'policy':<22}{'RMSE deg':>9}{'F1':>7}{'disp err':>9}{'toe peak':>9}{'target':>8}{'timing ms':>10}"
          f"{'reanch':>7}{'ELR':>6}{'SR90':>6}")
    for name, r in results.items():
        m = r["mean"]
        print(f"{name:<22}{m['joint_rmse_deg']:>9.2f}{m['contact_f1']:>7.3f}{m['forward_displacement_error']:>9.1%}"
              f"{m['push_off_peak_deg']:>9.1f}{m['push_off_target_peak_deg']:>8.1f}{m['push_off_timing_ms']:>10.0f}"
              f"{m['reanchors']:>7.1f}{m['ELR']:>6.2f}{m['SR90']:>6.2f}")
    print(f"\n{'gait parameter':<16}" + "".join(f"{n:>20}" for n in results) + f"{'targets ĉ':>12}")
    first = next(iter(results.values()))["mean"]
    for k in PARAMETERS:
        print(f"{k:<16}" + "".join(f"{r['mean'][f'{k}_simulated']:>20.3f}" for r in results.values())
              + f"{first[f'{k}_targets']:>12.3f}")
    emit_json({"clips": clips, "seconds": args.seconds, "episodes": args.episodes, "ablations": args.ablations,
               "adapt_budget_s": args.adapt_budget_s, "adapt_target": args.adapt_target,
               "adapt_variance": args.adapt_variance, "adapt_lr": args.adapt_lr, "adapt_keep": args.adapt_keep,
               "results": results}, args.json)


if __name__ == "__main__":
    main()
