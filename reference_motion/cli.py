"""One error path for every command line: bad input ends in one line naming the file, exit status 1.

Every CLI (``python -m reference_motion``, ``python -m perception``, ``agents/*.py`` and the
``physmimic`` command that fronts them) builds its parser with :class:`CliParser`, types its
numbers and outputs with the argument types below, and wraps its ``main`` in
:func:`one_line_errors`. What a user can get wrong then ends as one line on stderr,
``error: <file or argument>: <what is wrong>``, exit status 1, no traceback and nothing
half-written:

* a bad argument (a number out of range, an output the writer cannot produce or whose folder
  cannot be created, a missing option) is refused by the parser before any work is done;
* a missing, damaged or unsuitable input is reported by its loader, which raises ``ValueError``
  (:class:`~reference_motion.motion.MotionError`, ``PolicyError``), ``KeyError`` (unknown names),
  ``OSError`` or ``ImportError`` (an optional extra not installed) with the file in the message.

Any other exception is a bug and keeps its traceback; ``PHYSMIMIC_TRACEBACK=1`` keeps it for the
errors above too.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import NoReturn, ParamSpec, TypeVar

from reference_motion.motion import Motion, MotionError
from reference_motion.rigs import UNITS, UP_AXES, MocapOptions, load_joint_map
from reference_motion.source import CANONICAL_JOINTS

USER_ERRORS = (ValueError, KeyError, OSError, ImportError)
"""Exceptions that mean bad input, not a bug: reported in one line."""

TRACEBACK_VARIABLE = "PHYSMIMIC_TRACEBACK"
"""Set this environment variable to a non-empty value to see the traceback of a user error too."""

P = ParamSpec("P")
R = TypeVar("R")
N = TypeVar("N", int, float)


class UsageError(ValueError):
    """A command line the parser refuses (raised by :meth:`CliParser.error` instead of exiting)."""


class CliParser(argparse.ArgumentParser):
    """``argparse.ArgumentParser`` whose errors go through :func:`one_line_errors` (one line, exit
    status 1) instead of printing the usage and exiting with status 2; its subparsers are of this
    class too."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{message} (see {self.prog} --help)")


def error_line(err: BaseException) -> str:
    """``err``'s message on one line (a ``KeyError``'s without the quotes its ``str`` adds)."""
    message = str(err.args[0]) if isinstance(err, KeyError) and err.args else str(err)
    return " ".join(line.strip() for line in message.splitlines() if line.strip()) or type(err).__name__


def one_line_errors(main: Callable[P, R]) -> Callable[P, R]:
    """Wrap a CLI ``main`` so that a :data:`USER_ERRORS` exception ends it with
    ``SystemExit("error: <message>")``: Python prints that one line to stderr and exits with
    status 1, and in-process callers can read it from the exception."""

    @functools.wraps(main)
    def run(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return main(*args, **kwargs)
        except USER_ERRORS as err:
            if os.environ.get(TRACEBACK_VARIABLE):
                raise
            raise SystemExit(f"error: {error_line(err)}") from None

    return run


# ------------------------------------------------------------------ argument types
def _bounded(convert: Callable[[str], N], what: str, low: float, strict: bool = False,
             high: float = math.inf) -> Callable[[str], N]:
    """Argument type: ``convert(text)``, finite, ``>= low`` (``> low`` if ``strict``) and ``<= high``;
    ``what`` words it for the error."""

    def parse(text: str) -> N:
        try:
            value = convert(text)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and (value > low if strict else value >= low) and value <= high):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return value

    return parse


positive_int = _bounded(int, "a positive integer", 0, strict=True)
non_negative_int = _bounded(int, "a non-negative integer", 0)
positive_float = _bounded(float, "a positive number", 0.0, strict=True)
non_negative_float = _bounded(float, "a non-negative number", 0.0)
fraction = _bounded(float, "a number from 0 to 1", 0.0, high=1.0)


def _check_folder(folder: Path, shown: str) -> None:
    """Refuse ``shown`` unless ``folder`` is a writable folder or can be created (its nearest
    existing ancestor is a writable folder)."""
    existing = folder
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise argparse.ArgumentTypeError(f"{shown}: cannot create the folder {folder}: {existing} is a file")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise argparse.ArgumentTypeError(f"{shown}: cannot write in the folder {existing} (permission denied)")


def output_file(*suffixes: str) -> Callable[[str], Path]:
    """Argument type of an output file that a writer produces as one of ``suffixes`` (``".npz"``,
    ``".mp4"``, ...): refused before any work is done when its type is another or its folder
    cannot be created."""

    def parse(text: str) -> Path:
        path = Path(text)
        if path.suffix.lower() not in suffixes:
            choices = ", ".join(suffixes[:-1]) + " or " + suffixes[-1] if len(suffixes) > 1 else suffixes[0]
            raise argparse.ArgumentTypeError(f"{text}: cannot write a {path.suffix or 'suffix-less'} file; "
                                             f"use {choices}")
        if path.is_dir():
            raise argparse.ArgumentTypeError(f"{text}: is a folder, expected a file name")
        _check_folder(path.parent, text)
        return path

    return parse


def output_dir(text: str) -> Path:
    """Argument type of an output folder: an existing writable folder or one that can be created."""
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: is a file, expected a folder")
    _check_folder(path, text)
    return path


# ------------------------------------------------------------------ inputs
def require_frames(motion: Motion, needed: int, source: str, purpose: str) -> Motion:
    """``motion`` (loaded from ``source``) if it has at least ``needed`` frames; otherwise a
    :class:`MotionError` naming ``source`` and what the frames are needed for."""
    if motion.n_frames < needed:
        raise MotionError(f"{source}: the clip has {motion.n_frames} frames at {motion.fps:g} Hz; {purpose} needs "
                          f"at least {needed}")
    return motion


def add_mocap_options(parser: argparse.ArgumentParser) -> None:
    """The options of a SOURCE that is a mocap file: ``--joint-map``, ``--units``, ``--up``, ``--asf``
    (read back by :func:`mocap_options`)."""
    g = parser.add_argument_group("mocap files (BVH, ASF/AMC): override what is detected")
    g.add_argument("--joint-map", type=Path, default=None, metavar="FILE.json",
                   help="JSON object {canonical joint: joint in the file} for a rig not recognised "
                        f"(canonical joints: {', '.join(CANONICAL_JOINTS)})")
    g.add_argument("--units", choices=sorted(UNITS), default=None, help="length unit of the file (default: detected)")
    g.add_argument("--up", choices=UP_AXES, default=None, help="up axis of the file (default: detected)")
    g.add_argument("--asf", type=Path, default=None, help="skeleton of an .amc take (default: the .asf beside it)")


def mocap_options(args: argparse.Namespace) -> MocapOptions:
    """The :class:`MocapOptions` given by :func:`add_mocap_options`' arguments."""
    return MocapOptions(joint_map=load_joint_map(args.joint_map) if args.joint_map else None,
                        units=args.units, up=args.up, asf=args.asf)


def or_none(parse: Callable[[str], float]) -> Callable[[str], float | None]:
    """An argparse type: ``none`` (any case) gives ``None``, anything else goes to ``parse``."""
    def parse_or_none(text: str) -> float | None:
        return None if text.strip().lower() == "none" else parse(text)

    return parse_or_none


def resumable_run(parser: argparse.ArgumentParser, argv: list[str], what: str,
                  changeable: tuple[str, ...] = ("rounds",)) -> tuple[argparse.Namespace, list[str]]:
    """Parse ``argv`` for a run kept in ``--out`` (its settings in ``OUT/args.json``) that
    ``--resume`` continues: returns ``(args, history)``, the settings (on ``--resume`` the stored
    ones, defaults for options newer than the run, with the ``changeable`` options (destination
    names) the command line sets, and its ``--no-progress``) and the commands that ran it so far.
    Raises ``FileNotFoundError`` on ``--resume`` with no run there, ``ValueError`` on ``--resume``
    with an option that cannot change, or for a new run where one is (``what`` names the kind of
    run in the messages). Options must be spelt out (``parser.allow_abbrev`` is switched off)."""
    parser.allow_abbrev = False
    args = parser.parse_args(argv)
    settings = args.out / "args.json"
    if args.resume:
        if not settings.is_file():
            raise FileNotFoundError(f"{settings}: not found: no {what} to resume in {args.out} (--resume)")
        given = {a.dest for a in parser._actions
                 if any(arg.split("=", 1)[0] in a.option_strings for arg in argv if arg.startswith("--"))}
        fixed = sorted(given - set(changeable) - {"out", "resume", "no_progress"})
        if fixed:
            names = lambda dests: ", ".join("--" + k.replace("_", "-") for k in dests)  # noqa: E731
            raise ValueError(f"{names(fixed)} cannot change on --resume: the {what} in {args.out} keeps the settings "
                             f"it started with (only {names(changeable)} may change)")
        stored = {**vars(parser.parse_args(["--out", str(args.out)])), **json.loads(settings.read_text())}
        changed = {k: getattr(args, k) for k in changeable if k in given}
        resumed = argparse.Namespace(**{**stored, **changed, "out": args.out, "resume": True,
                                        "no_progress": args.no_progress})
        return resumed, stored.get("commands", [])
    if settings.exists():
        raise ValueError(f"{args.out}: already holds a {what}; pass --resume to continue it or pick a new --out")
    return args, []
