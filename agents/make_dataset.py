"""Make a physics-labelled dataset: trained policies re-perform the clip library, recording vGRF.

Usage::

    python agents/make_dataset.py --out data/physics            # ~5 min on 2 cores, resumable

See :mod:`agents.physics_dataset` for what is recorded and :mod:`perception.dataset` for the format
the perception networks read (``python -m perception train-vgrf --dataset data/physics ...``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

if __package__ in (None, ""):  # `python agents/make_dataset.py` puts agents/ first on the path: use the repo root
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents.physics_dataset import DatasetConfig, generate
from reference_motion.cli import CliParser, one_line_errors, output_dir, positive_int


def build_parser(prog: str | None = None) -> CliParser:
    d = DatasetConfig()
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0],
                  formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--out", type=output_dir, required=True, help="dataset directory (resumes if it exists)")
    p.add_argument("--policies", nargs="+", default=list(d.policies), help="policy directories")
    p.add_argument("--clips", nargs="+", default=list(d.clips), help="SOURCE strings of the clip library")
    p.add_argument("--variants", type=positive_int, default=d.variants, help="references per clip")
    p.add_argument("--episodes", type=positive_int, default=d.episodes, help="windows performed per reference")
    p.add_argument("--seed", type=int, default=d.seed)
    p.add_argument("--no-progress", action="store_true")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> dict:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the dataset's manifest."""
    args = build_parser(prog).parse_args(argv)
    config = DatasetConfig(policies=tuple(args.policies), clips=tuple(args.clips), variants=args.variants,
                           episodes=args.episodes, seed=args.seed)
    manifest = generate(args.out, config, progress=not args.no_progress)
    for split, s in manifest["summary"].items():
        print(f"{split:>5}: {s['frames']:>7} frames, {s['episodes']:>4} episodes, {len(s['clips'])} clips, "
              f"endings {s['endings']}")
    return manifest


if __name__ == "__main__":
    main()
