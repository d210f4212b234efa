"""Does a policy keep its feet when shoved, or in another body? ADAPT's protocol with random
pushes of the pelvis, then with the humanoid's physics randomised.

Usage: ``python bench/push_recovery.py --policy models/mimic_general [DIR ...]
[--clips library:data/library/val] [--forces 0 80,160 150,300] [--bodies 0.15,0.3,0.15]
[--episodes 10] [--json [OUT]]``

``train_ppo.py --push-force`` trains with random horizontal pushes of the pelvis
(:class:`envs.config.Pushes`, DeepMimic's perturbations) so that the policy learns recoveries from
states no clip shows. Here each policy performs the clean clips (``--episodes`` rollouts per clip,
start frames ``--offset-step`` control steps apart) under pushes of each ``--forces`` range (N,
``LOW,HIGH``; ``0``: none) at ``--rate`` pushes per second, each ``--duration`` s long; the pushes
are drawn from the env's generator, seeded alike for every policy. ``train_ppo.py --dynamics``
trains in bodies drawn anew every episode (:class:`envs.config.Dynamics`); each ``--bodies`` entry
(``MASS,FRICTION,STRENGTH[,OFFSET_DEG]`` half-ranges) is a further column, the clean clips performed, unpushed,
in bodies drawn the same way (the draws seeded alike for every policy too). Printed: ELR / SR90 per
policy and column, side by side.
"""

from __future__ import annotations

import argparse

import envs  # noqa: F401  (registers the ids)
from agents.evaluation import evaluate
from agents.policy import load_policy
from envs.config import Dynamics, Pushes
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.library import expand_clips

SEED = 123
"""Seed of each evaluation env: the same pushes for every policy, as long as their episodes do."""


def force_range(text: str) -> tuple[float, float] | None:
    """``"LOW,HIGH"`` (N) as a tuple; ``"0"``: no pushes (``None``)."""
    if text == "0":
        return None
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"a force range is LOW,HIGH in N (or 0 for none), got {text!r}") from None
    return lo, hi


def body_ranges(text: str) -> Dynamics:
    """``"MASS,FRICTION,STRENGTH[,OFFSET_DEG]"`` half-ranges as :class:`envs.config.Dynamics`."""
    try:
        values = [float(v) for v in text.split(",")]
        if len(values) not in (3, 4):
            raise ValueError(f"{len(values)} values")
        return Dynamics(*values)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"a body range is MASS,FRICTION,STRENGTH half-ranges in [0, 1) and an "
                                         f"optional OFFSET_DEG, got {text!r} ({e})") from None


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", nargs="+", default=["models/mimic_general"])
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"])
    p.add_argument("--forces", nargs="+", type=force_range, default=[None, (80.0, 160.0), (150.0, 300.0)])
    p.add_argument("--bodies", nargs="*", type=body_ranges, default=[],
                   help="also perform the clips unpushed in bodies randomised by these MASS,FRICTION,STRENGTH "
                        "half-ranges and optional PD-target OFFSET_DEG (e.g. 0.15,0.3,0.15 or 0,0,0,3.5)")
    p.add_argument("--rate", type=float, default=0.5, help="pushes per second")
    p.add_argument("--duration", type=float, default=Pushes.duration_s, help="s")
    p.add_argument("--episodes", type=int, default=10)
    p.add_argument("--offset-step", type=int, default=6)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    clips = expand_clips(args.clips)
    columns = {("none" if f is None else f"{f[0]:g}-{f[1]:g} N"):
               (None if f is None else Pushes(force_n=f, duration_s=args.duration, rate_hz=args.rate), None)
               for f in args.forces}  # label: (pushes, bodies)
    columns.update({f"body ±{b.mass:g},{b.friction:g},{b.strength:g},{b.offset_deg:g}°": (None, b) for b in args.bodies})
    result = {"clips": args.clips, "rate_hz": args.rate, "duration_s": args.duration, "episodes": args.episodes,
              "bodies": [vars(b) for b in args.bodies], "policies": {}}
    print(f"ELR / SR90 under random pelvis pushes ({args.rate:g}/s, {args.duration:g} s each) and in random bodies, "
          f"{args.episodes} rollouts per clip of {len(clips)}")
    print(f"{'policy':<44}" + "".join(f"{label:>24}" for label in columns))
    for path in args.policy:
        policy = load_policy(path)
        row = {}
        for label, (pushes, bodies) in columns.items():
            env = policy.make_env(clips, artefacts=None, pushes=pushes, dynamics=bodies)
            env.reset(seed=SEED)
            summary, _ = evaluate(env, policy, episodes=args.episodes, offset_step=args.offset_step)
            env.close()
            row[label] = summary
        result["policies"][path] = row
        print(f"{path:<44}" + "".join(f"{row[l]['ELR_mean']:>17.3f} / {row[l]['SR90']:.2f}" for l in columns), flush=True)
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
