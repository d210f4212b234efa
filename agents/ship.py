"""Ship a training run's best policy (or its newest, or a given, checkpoint) to ``models/NAME``, evaluated.

Usage::

    python agents/ship.py --run-dir runs/mimic_walk --name mimic_walk --clips deepmimic:walk
    python agents/ship.py --run-dir runs/data_mix/mixed --name mimic_imu --clips HELD_OUT... --corrupt imu --seed 1000
    python agents/ship.py --run-dir runs/r32/ppo_ls --name NAME --checkpoint runs/r32/ppo_ls/checkpoints/step_500000.zip ...

Copies ``RUN/best`` (model, observation statistics, sidecar; with ``--newest`` the run's newest
checkpoint instead, with ``--checkpoint STEP_ZIP`` that one, for a choice registered on it), evaluates it with
``agents/evaluate.py`` (the extra arguments are passed on) and records the evaluation, its command
and the run's training steps and wall time in all (at its newest checkpoint) in
``models/NAME/sidecar.json``. The model ships deflated (SB3 loads it the same) and is refused over 20 MB. The policy
is assembled beside ``models/NAME`` and replaces it only once evaluated, so a failed run leaves
``models/NAME`` as it was. A checkpoint of a run trained with a privileged critic
(``train_ppo.py --privileged-critic``) ships as its actor, a plain policy (its ``run/`` keeps the
whole network for resuming).

``--resumable`` also copies the run's newest checkpoint and its records (``args.json``,
``evaluations.jsonl``, ``wall.json``) to ``models/NAME/run/``, from which a later session resumes
training (``cp -r models/NAME/run runs/X && python agents/train_ppo.py --run-dir runs/X --resume``).
Every other folder already in ``models/NAME`` (a ``run/`` when not ``--resumable``, other runs
and students kept beside the policy) is kept.
"""

from __future__ import annotations

import json
import pickle
import shlex
import shutil
import sys
import zipfile
from pathlib import Path

from stable_baselines3 import PPO

if __package__ in (None, ""):  # `python agents/ship.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents import evaluate
from agents.policy import CHECKPOINTS_DIR, MODEL_FILE, SIDECAR_FILE, STATS_FILE
from agents.privileged_critic import PrivilegedCriticPolicy, actor_only
from agents.train_ppo import CHECKPOINT, newest_checkpoint, recorded_progress
from reference_motion.atomic import write_json
from reference_motion.cli import CliParser, one_line_errors, output_dir

MAX_MODEL_BYTES = 20_000_000
"""The most bytes a file in ``models/`` may take: 20 MB."""
RUN_RECORDS = ("args.json", "evaluations.jsonl", "wall.json")


def _checked_size(path: Path, shown: str | None = None) -> int:
    """``path``'s size in bytes; raises ValueError, naming ``shown`` (default: ``path``), if it is over
    the limit for ``models/``."""
    size = path.stat().st_size
    if size > MAX_MODEL_BYTES:
        raise ValueError(f"{shown or path}: {size / 1e6:.1f} MB, over the {MAX_MODEL_BYTES / 1e6:g} MB limit "
                         f"for models/")
    return size


def copy_resumable_run(run_dir: Path, dest: Path) -> None:
    """Copy ``run_dir``'s newest checkpoint (model, observation statistics, sidecar) and its records
    to ``dest`` so that ``train_ppo.py --resume`` continues from it. SB3 stores a checkpoint's
    weights and optimizer state uncompressed; the copy is deflated (:func:`_deflated_copy`), which
    SB3 loads the same (20.0 → 18.3 MB for ``mimic_general_dash_symmetric``'s [512, 512] network and
    its Adam moments). Raises ValueError, naming the checkpoint, if the copy is over the limit."""
    checkpoint = newest_checkpoint(run_dir)
    if checkpoint is None:
        raise FileNotFoundError(f"{run_dir / CHECKPOINTS_DIR}: no step_*.zip checkpoint to make the run resumable")
    (dest / CHECKPOINTS_DIR).mkdir(parents=True)
    for path in run_dir.joinpath(CHECKPOINTS_DIR).glob(checkpoint.stem + "_*"):
        shutil.copy2(path, dest / CHECKPOINTS_DIR / path.name)
    _deflated_copy(checkpoint, dest / CHECKPOINTS_DIR / checkpoint.name)
    _checked_size(dest / CHECKPOINTS_DIR / checkpoint.name, shown=f"{checkpoint} (deflated)")
    for name in RUN_RECORDS:
        if (run_dir / name).exists():
            shutil.copy2(run_dir / name, dest / name)


def _deflated_copy(source: Path, dest: Path) -> None:
    """Write the zip archive ``source`` to ``dest`` with every member deflated (same names, same bytes)."""
    with zipfile.ZipFile(source) as zin, zipfile.ZipFile(dest, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as zout:
        for member in zin.infolist():
            zout.writestr(member.filename, zin.read(member))


def _deflate_in_place(path: Path) -> None:
    """Rewrite the zip archive ``path`` with every member deflated (:func:`_deflated_copy`)."""
    deflated = path.with_name(path.name + ".deflated")
    _deflated_copy(path, deflated)
    deflated.replace(path)


def _as_actor(directory: Path) -> None:
    """Rewrite the model and statistics of the policy ``directory`` as their actor
    (:func:`agents.privileged_critic.actor_only`) if the network was trained with a privileged critic."""
    model = PPO.load(directory / MODEL_FILE, device="cpu")
    if isinstance(model.policy, PrivilegedCriticPolicy):
        with open(directory / STATS_FILE, "rb") as f:
            model, statistics = actor_only(model, pickle.load(f))
        statistics.save(str(directory / STATS_FILE))
        model.save(directory / MODEL_FILE)


def _best_files(run_dir: Path) -> dict[str, Path]:
    """The policy files of ``run_dir``'s best checkpoint, by the name each takes in ``models/NAME``."""
    best = run_dir / "best"
    if not (best / MODEL_FILE).exists():
        raise FileNotFoundError(f"{best / MODEL_FILE}: not found: the run has not been evaluated yet")
    return {name: best / name for name in (MODEL_FILE, STATS_FILE, SIDECAR_FILE)}


def _newest_files(run_dir: Path) -> dict[str, Path]:
    """The policy files of ``run_dir``'s newest checkpoint (:func:`_checkpoint_files`)."""
    checkpoint = newest_checkpoint(run_dir)
    if checkpoint is None:
        raise FileNotFoundError(f"{run_dir / CHECKPOINTS_DIR}: no step_*.zip checkpoint to ship (--newest)")
    return _checkpoint_files(checkpoint)


def _checkpoint_files(checkpoint: Path, run_dir: Path | None = None) -> dict[str, Path]:
    """The policy files of ``checkpoint`` (``step_N.zip``, ``step_N_vecnormalize.pkl``,
    ``step_N_sidecar.json``), by the name each takes in ``models/NAME``; with ``run_dir``, refused
    unless the checkpoint is that run's (its records go into the sidecar)."""
    if not checkpoint.is_file():
        raise FileNotFoundError(f"{checkpoint}: no such checkpoint")
    if not CHECKPOINT.fullmatch(checkpoint.name):
        raise ValueError(f"{checkpoint}: not a checkpoint: expected a step_N.zip of a run's {CHECKPOINTS_DIR}/")
    if run_dir is not None and checkpoint.resolve().parent != (run_dir / CHECKPOINTS_DIR).resolve():
        raise ValueError(f"{checkpoint}: not a checkpoint of --run-dir {run_dir} (its {CHECKPOINTS_DIR}/): the "
                         "sidecar records that run's training")
    files = {MODEL_FILE: checkpoint, STATS_FILE: checkpoint.with_name(f"{checkpoint.stem}_vecnormalize.pkl"),
             SIDECAR_FILE: checkpoint.with_name(f"{checkpoint.stem}_{SIDECAR_FILE}")}
    missing = [path.name for path in files.values() if not path.exists()]
    if missing:
        raise FileNotFoundError(f"{checkpoint}: {', '.join(missing)} missing beside it; a checkpoint ships whole "
                                "or not at all")
    return files


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``; options it does not know go to
    ``agents/evaluate.py``); returns the shipped policy's directory."""
    argv = sys.argv[1:] if argv is None else argv
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--run-dir", type=Path, required=True)
    p.add_argument("--name", required=True, help="directory name under --models")
    p.add_argument("--models", type=output_dir, default=Path("models"))
    p.add_argument("--resumable", action="store_true",
                   help="also copy the run's newest checkpoint and records to models/NAME/run/")
    which = p.add_mutually_exclusive_group()
    which.add_argument("--newest", action="store_true",
                       help="ship the run's newest checkpoint instead of its best by its own evaluation")
    which.add_argument("--checkpoint", type=Path, metavar="STEP_ZIP",
                       help="ship this checkpoint of the run (its step_N.zip), e.g. a registered candidate")
    args, eval_args = p.parse_known_args(argv)
    sources = (_checkpoint_files(args.checkpoint, args.run_dir) if args.checkpoint else
               _newest_files(args.run_dir) if args.newest else _best_files(args.run_dir))
    out = args.models / args.name
    staging = args.models / f".{args.name}.partial"  # becomes `out` only once evaluated: never half-shipped
    shutil.rmtree(staging, ignore_errors=True)
    staging.mkdir(parents=True)
    try:
        for name, source in sources.items():
            shutil.copy2(source, staging / name)
        _as_actor(staging)
        _deflate_in_place(staging / MODEL_FILE)
        # what ships is checked: a run with a privileged critic ships its actor only
        size = _checked_size(staging / MODEL_FILE, shown=f"{sources[MODEL_FILE]} as shipped")
        if args.resumable:  # before the evaluation, so that a run too large to resume is refused at once
            copy_resumable_run(args.run_dir, staging / "run")
        result = {**evaluate.main(["--policy", str(staging), *eval_args]), "policy": str(out)}
        write_json(staging / "evaluation.json", result)
        sidecar = json.loads((staging / SIDECAR_FILE).read_text())
        progress = recorded_progress(args.run_dir)
        if progress is None:
            raise FileNotFoundError(f"{args.run_dir}: neither wall.json nor evaluations.jsonl: no record of its training")
        steps_total, wall_s_total = progress
        sidecar.update(name=args.name, training_wall_s_total=wall_s_total, training_steps_total=steps_total,
                       evaluate_command=shlex.join(["python", "agents/evaluate.py", "--policy", str(out), *eval_args]),
                       evaluation={k: v for k, v in result.items() if k not in ("policy",)})
        write_json(staging / SIDECAR_FILE, sidecar)
        if out.is_dir():  # folders beside the old policy (resumable runs, students) stay beside the new one
            for folder in out.iterdir():
                if folder.is_dir() and not (staging / folder.name).exists():
                    shutil.copytree(folder, staging / folder.name)
        shutil.rmtree(out, ignore_errors=True)
        staging.rename(out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    print(f"shipped {out} ({size / 1e6:.1f} MB)")
    return out


if __name__ == "__main__":
    main()
