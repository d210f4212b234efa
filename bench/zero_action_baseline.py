"""Zero-action baseline: the reference fed open loop to the PD controllers of MimicIMU-v0.

Usage: ``python bench/zero_action_baseline.py [--clip deepmimic:walk] [--episodes 20] [--json [OUT]]``

ADAPT's protocol (:mod:`agents.evaluation`): one 300-frame segment, ``episodes`` rollouts starting
at offsets 0, 3, 6, ... frames, clean reference, the action always zero. The ELR, SR90, RDE and MRR
it reaches are what a trained policy has to beat.
"""

from __future__ import annotations

import argparse
import collections

import gymnasium as gym

import envs  # noqa: F401  (registers the ids)
from agents.evaluation import evaluate, zero_policy
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clip", default="deepmimic:walk")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = parser.parse_args()
    env = gym.make("MimicIMU-v0", clips=[args.clip], artefacts=None)
    env.reset(seed=0)
    summary, runs = evaluate(env, zero_policy(env.action_space.shape[0]), episodes=args.episodes)
    result = {"clip": args.clip, **summary, "ended_by": dict(collections.Counter(r.ended_by for r in runs))}
    if not emit_json(result, args.json):
        print(f"{args.clip}, zero action, {len(runs)} rollouts: ELR {result['ELR_mean']:.3f} ± "
              f"{result['ELR_std']:.3f}, SR90 {result['SR90']:.2f}, RDE {result['RDE_mean']:.4f} m², "
              f"MRR {result['MRR_mean']:.3f}; ended by {result['ended_by']}")


if __name__ == "__main__":
    main()
