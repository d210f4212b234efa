"""Command line: ``python -m reference_motion {info,quality,render,list} ...``.

Examples::

    python -m reference_motion list
    python -m reference_motion info deepmimic:walk --json
    python -m reference_motion quality deepmimic:walk --corrupt imu --strength 1 --seed 3 --json
    python -m reference_motion render deepmimic:run --out run.mp4
"""

from __future__ import annotations

import argparse
import json
import sys

from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.library import load_motion, named_set
from reference_motion.motion import MODEL_NQ, Motion
from reference_motion.quality import motion_quality


def _add_source(p: argparse.ArgumentParser) -> None:
    p.add_argument("source", help="deepmimic:NAME, or a .npz / .bvh / .txt file")
    p.add_argument("--model", default="humanoid_1seg", choices=sorted(MODEL_NQ), help="target humanoid")
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS,
                   help="add synthetic IMU artefacts: all kinds ('imu') or a single kind")
    p.add_argument("--strength", type=float, default=1.0, help="artefact strength (default 1)")
    p.add_argument("--seed", type=int, default=0, help="artefact random seed (default 0)")


def _motions(args: argparse.Namespace) -> tuple[Motion, Motion]:
    """The clip as loaded, and as it should be measured/shown (corrupted when ``--corrupt``)."""
    clean = load_motion(args.source, args.model)
    if not args.corrupt:
        return clean, clean
    return clean, corrupt(clean, ArtefactRecipe.named(args.corrupt, args.strength), args.seed)


def _info(motion: Motion) -> dict:
    return {"name": motion.name, "model": motion.model, "frames": motion.n_frames, "fps": motion.fps,
            "duration_s": round(motion.duration, 4), "loop": motion.loop, "nq": motion.qpos.shape[1],
            "source": motion.source}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m reference_motion", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p_list = sub.add_parser("list", help="list the built-in clips")
    p_list.add_argument("--set", default="deepmimic", help="named set (deepmimic, locomotion)")
    p_info = sub.add_parser("info", help="frames, rate, duration and provenance of a clip")
    _add_source(p_info)
    p_info.add_argument("--json", action="store_true", help="print JSON")
    p_q = sub.add_parser("quality", help="artefact metrics of a clip")
    _add_source(p_q)
    p_q.add_argument("--json", action="store_true", help="print one JSON object")
    p_r = sub.add_parser("render", help="render a clip offscreen to .mp4/.gif/.png")
    _add_source(p_r)
    p_r.add_argument("--out", required=True, help="output file (.mp4, .gif or .png)")
    p_r.add_argument("--fps", type=float, default=30.0, help="video frame rate (default 30)")
    p_r.add_argument("--with-clean", action="store_true", help="with --corrupt: clean clip beside the corrupted one")
    args = parser.parse_args(argv)

    try:
        if args.command == "list":
            print("\n".join(named_set(args.set)))
            return 0
        clean, motion = _motions(args)
        if args.command == "info":
            info = _info(motion)
            print(json.dumps(info, indent=2) if args.json else
                  "\n".join(f"{k}: {v}" for k, v in info.items() if k != "source"))
        elif args.command == "quality":
            report = motion_quality(motion).as_dict()
            report.update(name=motion.name, model=motion.model)
            if args.corrupt:
                report.update(corrupt=args.corrupt, strength=args.strength, seed=args.seed)
            if args.json:
                print(json.dumps(report))
            else:
                print("\n".join(f"{k:24s} {v}" for k, v in report.items()))
        elif args.command == "render":
            from reference_motion.render import render

            motions = [clean, motion] if (args.with_clean and args.corrupt) else motion
            print(f"wrote {render(motions, args.out, fps=args.fps)}")
    except (ValueError, KeyError, FileNotFoundError) as err:
        message = err.args[0] if isinstance(err, KeyError) and err.args else str(err)
        print(f"error: {message}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
