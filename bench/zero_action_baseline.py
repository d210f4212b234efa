"""Zero-action baseline: the reference fed open loop to the PD controllers of MimicIMU-v0, and
optionally a trained policy beside it on the same clips.

Usage: ``python bench/zero_action_baseline.py [--clips deepmimic:walk ...] [--policy DIR]
[--episodes 20] [--offset-step 3] [--json [OUT]]``

ADAPT's protocol (:mod:`agents.evaluation`): per clip one 300-frame segment, ``episodes`` rollouts
starting at offsets 0, ``offset-step``, ... frames, clean reference, the action always zero. The
ELR, SR90, RDE and MRR it reaches are what a trained policy has to beat; with ``--policy`` the
policy runs the same rollouts in its own environment configuration (its sidecar) and each clip's
ELR is printed for both, so a clip on which the policy does no better than zero action shows.
"""

from __future__ import annotations

import argparse
import collections

import gymnasium as gym

import envs  # noqa: F401  (registers the ids)
from agents.evaluate import reference_clips
from agents.evaluation import evaluate, per_clip, zero_policy
from agents.policy import load_policy
from envs.config import FOOT_MODELS, MimicConfig
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/


def scored(env: gym.Env, policy, episodes: int, offset_step: int) -> dict:
    """ADAPT's summary, the endings and each clip's ELR / SR90 of ``policy`` on ``env``'s clips."""
    env.reset(seed=0)
    summary, runs = evaluate(env, policy, episodes=episodes, offset_step=offset_step)
    return {**summary, "ended_by": dict(collections.Counter(r.ended_by for r in runs)), "per_clip": per_clip(runs)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", nargs="+", default=["deepmimic:walk"], help="SOURCE strings or clip sets")
    parser.add_argument("--policy", help="also run this policy directory on the same rollouts")
    parser.add_argument("--episodes", type=int, default=20, help="rollouts per clip")
    parser.add_argument("--offset-step", type=int, default=3, help="frames between the rollouts' start frames")
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    policy = load_policy(args.policy) if args.policy else None
    foot = policy.foot if policy else "one"
    motions = reference_clips(args.clips, FOOT_MODELS[foot], MimicConfig(), None, 0.0, 0)
    env = policy.make_env(motions, artefacts=None) if policy else gym.make("MimicIMU-v0", clips=motions, artefacts=None)
    scores = {"zero_action": scored(env, zero_policy(env.action_space.shape[0]), args.episodes, args.offset_step)}
    if policy:
        scores["policy"] = {"path": args.policy, **scored(env, policy, args.episodes, args.offset_step)}
    result = {"clips": args.clips, **scores}
    if emit_json(result, args.json):
        return
    for name, r in scores.items():
        print(f"{name}, {args.episodes} rollouts per clip: ELR {r['ELR_mean']:.3f} ± {r['ELR_std']:.3f}, SR90 "
              f"{r['SR90']:.2f}, RDE {r['RDE_mean']:.4f} m², MRR {r['MRR_mean']:.3f}; ended by {r['ended_by']}")
    if policy:
        zero = {row["clip"]: row["ELR"] for row in scores["zero_action"]["per_clip"]}
        print(f"  {'clip (worst policy first)':<56}{'policy':>8}{'zero':>8}")
        for row in scores["policy"]["per_clip"]:
            print(f"  {row['clip']:<56}{row['ELR']:>8.2f}{zero[row['clip']]:>8.2f}")


if __name__ == "__main__":
    main()
