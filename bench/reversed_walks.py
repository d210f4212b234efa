"""Backward walks, real and made by time reversal: how each policy performs them, side by side.

Usage: ``python bench/reversed_walks.py --policy models/mimic_general [DIR ...] [--split train|val]
[--episodes 4] [--json [OUT]]``

``train_ppo.py --reverse`` adds forward walks played backwards in time
(:func:`reference_motion.transforms.reversed_in_time`), which the same torques and ground forces
perform. Three groups of clips of one split of the library, ADAPT's protocol (``--episodes``
rollouts per clip, start frames ``--offset-step`` control steps apart, clean references):

- ``backward``: the split's real backward walks (``walk-back``);
- ``reversed``: its forward walks (``walk_``) played backwards;
- ``forward``: the same forward walks as recorded.

On ``val`` (the style no policy trains on) this is what a run adding reversed walks is chosen on
for its backward walking; ``train`` shows what it fits.
"""

from __future__ import annotations

import argparse

import envs  # noqa: F401  (registers the ids)
from agents.evaluation import evaluate
from agents.policy import load_policy
from envs.config import FOOT_MODELS
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.library import expand_clips, load_motion
from reference_motion.transforms import reversed_in_time


def groups(split: str, model: str) -> dict[str, list]:
    """The split's ``backward``, ``reversed`` and ``forward`` clips (Motions) for ``model``."""
    clips = expand_clips([f"library:data/library/{split}"])
    walks = [c for c in clips if "_walk_" in c]
    load = lambda c: load_motion(c, model)  # noqa: E731
    forward = [load(c) for c in walks]
    return {"backward": [load(c) for c in clips if "_walk-back_" in c],
            "reversed": [reversed_in_time(m) for m in forward], "forward": forward}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", nargs="+", default=["models/mimic_general"])
    p.add_argument("--split", default="val", choices=["train", "val"],
                   help="library split (the test split only for a final measurement, by hand)")
    p.add_argument("--episodes", type=int, default=4)
    p.add_argument("--offset-step", type=int, default=15)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    result = {"split": args.split, "episodes": args.episodes, "offset_step": args.offset_step, "policies": {}}
    print(f"ELR / SR90 on the {args.split} split's walks, {args.episodes} rollouts per clip")
    print(f"{'policy':<40}" + "".join(f"{g:>18}" for g in ("backward", "reversed", "forward")))
    cache = {}
    for path in args.policy:
        policy = load_policy(path)
        model = FOOT_MODELS[policy.foot]
        if model not in cache:
            cache[model] = groups(args.split, model)
        row = {}
        for name, clips in cache[model].items():
            env = policy.make_env(clips, artefacts=None)
            summary, _ = evaluate(env, policy, episodes=args.episodes, offset_step=args.offset_step)
            env.close()
            row[name] = {"clips": len(clips), **summary}
        result["policies"][path] = row
        print(f"{path:<40}" + "".join(f"{row[g]['ELR_mean']:>11.3f} / {row[g]['SR90']:.2f}" for g in row), flush=True)
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
