"""The ``physmimic`` command: one front for every command line of the project.

``physmimic COMMAND ARGS...`` runs the command line behind COMMAND with ARGS, as if it had been
started directly (``physmimic evaluate ...`` = ``python agents/evaluate.py ...``); ``physmimic
COMMAND --help`` shows its options. Installed by ``pip install`` (``[project.scripts]``).
"""

from __future__ import annotations

import argparse
import importlib
import sys

from reference_motion.cli import CliParser, one_line_errors

COMMANDS = {
    "motion": ("reference_motion.__main__", "clips: list, info, quality, render (python -m reference_motion)"),
    "perception": ("perception.__main__", "contacts, vGRF, cleanup, gait and the networks "
                                          "(python -m perception)"),
    "dataset": ("agents.make_dataset", "a physics-labelled dataset: policies re-perform clips, recording vGRF "
                                       "(agents/make_dataset.py)"),
    "train": ("agents.train_ppo", "train a mimic policy with PPO (agents/train_ppo.py)"),
    "evaluate": ("agents.evaluate", "evaluate a policy with ADAPT's protocol (agents/evaluate.py)"),
    "clean": ("agents.clean", "re-perform a clip with a policy under physics, or track it with the diff-PD "
                              "cycle (agents/clean.py)"),
    "gait": ("agents.reconstruct_gait", "reconstruct a walk with the two-segment foot: contacts, toe targets, "
                                        "MimicGait-v0 policy, gait report (agents/reconstruct_gait.py)"),
    "train-diffpd": ("agents.train_diffpd", "train the differentiable PD cycle's networks (agents/train_diffpd.py)"),
    "distill": ("agents.distill", "distil a policy set into one network by DAgger (agents/distill.py)"),
    "ship": ("agents.ship", "ship a training run's best policy to models/ (agents/ship.py)"),
    "mirror": ("agents.mirror_policy", "write a policy's mirror image, a teacher for a clip's other side "
                                       "(agents/mirror_policy.py)"),
}
"""Command → (module whose ``main(argv, prog)`` runs it, what it does)."""


@one_line_errors
def main(argv: list[str] | None = None) -> int:
    """Run ``physmimic`` with ``argv`` (default: ``sys.argv[1:]``); returns the exit status."""
    parser = CliParser(prog="physmimic", description=__doc__.split("\n\n")[0],
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="commands:\n" + "\n".join(f"  {name:<12}{what}" for name, (_, what) in COMMANDS.items())
                       + "\n\n'physmimic COMMAND --help' shows a command's options.")
    parser.add_argument("command", choices=COMMANDS, metavar="COMMAND", help="one of: " + ", ".join(COMMANDS))
    parser.add_argument("args", nargs=argparse.REMAINDER, help="the command's arguments")
    args = parser.parse_args(argv)
    module = importlib.import_module(COMMANDS[args.command][0])
    module.main(args.args, prog=f"physmimic {args.command}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
