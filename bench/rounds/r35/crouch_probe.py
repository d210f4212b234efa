"""Can a policy perform a crouched take at all? (round 35's probe; training and validation takes, no held-out take).

Round 34's probe found validation's crouched dash (the happy style's, carried with a posture whose crouch bends the hips
0.14-0.20 rad) running ahead of the take, clean, and ending early. This probe asks whether the policy does the same
on the takes it trained on: each take of ``--clips`` (default: the training split's dashes and validation's dash),
clean, carried with a crouch alone (:func:`reference_motion.transforms.posture_offsets` with ``crouch`` = each of
``--crouch-deg``; the copies made as training makes them, :func:`reference_motion.library.postured`), grounded and
swing-lifted as the clean rows track them, ``--episodes`` mirror-averaged rollouts each. Per take and crouch it records
the ELR, how many rollouts ended early, and the pace: the simulated pelvis's horizontal path length over the take's,
over the frames performed (over 1: the body went further than the take).

usage: python bench/rounds/r35/crouch_probe.py POLICY OUT.json [--clips SOURCE ...] [--crouch-deg DEG ...]
[--episodes N]
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[3]
sys.path[:0] = [str(ROOT)]
import envs  # noqa: E402,F401  (registers the ids)
from agents.evaluate import reference_clips, tracked_and_judged  # noqa: E402
from agents.evaluation import Rollout, evaluate_tracking  # noqa: E402
from agents.policy import load_policy  # noqa: E402
from envs.config import FOOT_MODELS, MimicConfig  # noqa: E402
from reference_motion.grounding import Grounding  # noqa: E402
from reference_motion.library import postured  # noqa: E402
from reference_motion.motion_library import library_set  # noqa: E402
from reference_motion.swing_lift import SwingLift  # noqa: E402
from reference_motion.transforms import posture_offsets  # noqa: E402

LIBRARY = "data/library"


def pace(run: Rollout) -> float:
    """The simulated pelvis's horizontal path length over the take's (as judged; the tracked take's path is the same),
    over the frames ``run`` performed."""
    def length(q: np.ndarray) -> float:
        return float(np.linalg.norm(np.diff(q[:, :2], axis=0), axis=1).sum())
    return length(run.simulated.qpos) / max(length(run.reference.qpos), 1e-6)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("policy")
    p.add_argument("out")
    p.add_argument("--clips", nargs="+", default=None,
                   help="SOURCE strings (default: the library's training and validation dashes, read from its manifest)")
    p.add_argument("--crouch-deg", nargs="+", type=float, default=[0.0, 6.0, 10.0, 14.0])
    p.add_argument("--episodes", type=int, default=4)
    args = p.parse_args()
    policy = load_policy(args.policy)
    config = MimicConfig()
    if args.clips is None:  # every dash of the library but the held-out ones, in the manifest's order
        held_out = set(library_set(f"library:{LIBRARY}/test", ("dash",)))
        args.clips = [take for take in library_set(f"library:{LIBRARY}", ("dash",)) if take not in held_out]
    takes = reference_clips(args.clips, FOOT_MODELS[policy.foot], config, None, 1.0, 0)
    rows = []
    for deg in args.crouch_deg:
        clips = [postured(t, posture_offsets(t.model, crouch=np.radians(deg)), f"crouch {deg:g}") if deg else t
                 for t in takes]
        tracked, judged = tracked_and_judged(clips, None, grounding=Grounding(), lift=SwingLift())
        _, runs = evaluate_tracking(policy, tracked, judged, episodes=args.episodes, mirror_average=True)
        for clip in tracked:
            mine = [r for r in runs if r.clip == clip.name]
            rows.append({"clip": clip.name, "crouch_deg": deg, "ELR": float(np.mean([r.elr for r in mine])),
                         "ended_early": sum(r.elr < 1.0 for r in mine), "pace": float(np.mean([pace(r) for r in mine]))})
            print(json.dumps(rows[-1]), flush=True)
        print(f"crouch {deg:g} deg: ELR {np.mean([r.elr for r in runs]):.3f}", flush=True)
    with open(args.out, "w") as f:
        json.dump({"policy": args.policy, "clips": args.clips, "episodes": args.episodes, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
