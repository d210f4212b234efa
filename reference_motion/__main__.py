"""Command line: ``python -m reference_motion {info,quality,render,list,import} ...``.

Examples::

    python -m reference_motion import ../shared/mocap --out data/library   # build a motion library
    python -m reference_motion list
    python -m reference_motion info deepmimic:walk --json
    python -m reference_motion quality deepmimic:walk --corrupt imu --strength 1 --seed 3 --json
    python -m reference_motion render deepmimic:run --out run.mp4
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.cli import (CliParser, add_mocap_options, mocap_options, non_negative_float, one_line_errors,
                                  output_dir, output_file, positive_float)
from reference_motion.importer import import_library
from reference_motion.library import load_motion, named_set
from reference_motion.motion_library import SPLITS
from reference_motion.motion import MODEL_NQ, Motion
from reference_motion.quality import motion_quality
from reference_motion.render import SUPPORTED as RENDER_SUFFIXES, render


def _add_source(p: argparse.ArgumentParser) -> None:
    p.add_argument("source", help="deepmimic:NAME, library:DIR#TAKE, or a .npz / .bvh / .amc / .txt file")
    p.add_argument("--model", default="humanoid_1seg", choices=sorted(MODEL_NQ), help="target humanoid")
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS,
                   help="add synthetic IMU artefacts: all kinds ('imu') or a single kind")
    p.add_argument("--strength", type=non_negative_float, default=1.0, help="artefact strength (default 1)")
    p.add_argument("--seed", type=int, default=0, help="artefact random seed (default 0)")
    add_mocap_options(p)


def _motions(args: argparse.Namespace) -> tuple[Motion, Motion]:
    """The clip as loaded, and as it should be measured/shown (corrupted when ``--corrupt``)."""
    clean = load_motion(args.source, args.model, mocap=mocap_options(args))
    if not args.corrupt:
        return clean, clean
    return clean, corrupt(clean, ArtefactRecipe.named(args.corrupt, args.strength), args.seed)


def _info(motion: Motion) -> dict:
    return {"name": motion.name, "model": motion.model, "frames": motion.n_frames, "fps": motion.fps,
            "duration_s": round(motion.duration, 4), "loop": motion.loop, "nq": motion.qpos.shape[1],
            "source": motion.source}


@one_line_errors
def main(argv: list[str] | None = None, prog: str = "python -m reference_motion") -> int:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the exit status."""
    parser = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p_list = sub.add_parser("list", help="list the built-in clips")
    p_list.add_argument("--set", default="deepmimic",
                        help="clip set: deepmimic, locomotion, or a motion library library:DIR[/train|val|test]")
    p_info = sub.add_parser("info", help="frames, rate, duration and provenance of a clip")
    _add_source(p_info)
    p_info.add_argument("--json", action="store_true", help="print JSON")
    p_q = sub.add_parser("quality", help="artefact metrics of a clip")
    _add_source(p_q)
    p_q.add_argument("--json", action="store_true", help="print one JSON object")
    p_r = sub.add_parser("render", help="render a clip offscreen to .mp4/.gif/.png")
    _add_source(p_r)
    p_r.add_argument("--out", type=output_file(*RENDER_SUFFIXES), required=True,
                     help="output file (.mp4, .gif or .png)")
    p_r.add_argument("--fps", type=positive_float, default=30.0, help="video frame rate (default 30)")
    p_r.add_argument("--with-clean", action="store_true", help="with --corrupt: clean clip beside the corrupted one")
    p_imp = sub.add_parser("import", help="build a motion library from mocap takes (.bvh, .amc, or folders of them)")
    p_imp.add_argument("paths", nargs="+", type=Path, help="take files or folders (searched recursively)")
    p_imp.add_argument("--out", type=output_dir, required=True, help="library folder (resumes an import there)")
    p_imp.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_mocap_options(p_imp)
    args = parser.parse_args(argv)

    if args.command == "import":
        manifest = import_library(args.paths, args.out, mocap=mocap_options(args), progress=not args.no_progress)
        takes = manifest["takes"]
        splits = {s: sum(t["split"] == s for t in takes) for s in SPLITS}
        print(f"{args.out}: {len(takes)} takes ({', '.join(f'{n} {s}' for s, n in splits.items())}), "
              f"{len(manifest['refused'])} refused, {manifest['wall_s']:.0f} s of import")
        for refused in manifest["refused"]:
            print(f"  refused {refused['file']}: {refused['reason']}")
        return 0
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
        motions = [clean, motion] if (args.with_clean and args.corrupt) else motion
        print(f"wrote {render(motions, args.out, fps=args.fps)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
