"""One error path for every CLI: bad input ends in exit status 1 and one line on stderr naming the
file (or argument) and what is wrong, with no traceback and nothing half-written.

Each CLI's ``main`` is fed every bad input in-process (it ends with ``SystemExit("error: ...")``,
which Python prints as that one line with status 1), and once through its real entry point in a
subprocess."""

import functools
import json
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
import torch
from stable_baselines3 import PPO

import perception.__main__ as perception_cli
from agents import make_dataset
import reference_motion.__main__ as motion_cli
from agents import clean, evaluate, physmimic, policy_set, ship, train_ppo
from agents.policy import load_policy
from reference_motion.atomic import atomic_write
from reference_motion.cli import TRACEBACK_VARIABLE
from reference_motion.motion import MODEL_NQ, Motion

ROOT = Path(__file__).resolve().parents[1]
POLICY = str(ROOT / "models" / "mimic_walk")

BAD_BVH = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n"
"""A BVH file cut off inside its hierarchy."""


def _standing(frames: int) -> np.ndarray:
    """``(frames, nq)`` qpos of humanoid_1seg standing still."""
    qpos = np.zeros((frames, MODEL_NQ["humanoid_1seg"]))
    qpos[:, 2], qpos[:, 3] = 0.9, 1.0
    return qpos


@pytest.fixture(scope="module")
def bad(tmp_path_factory) -> dict[str, str]:
    """Paths of bad inputs, and of outputs that cannot be written, by name."""
    root = tmp_path_factory.mktemp("bad_input")
    whole = Motion("still", 60.0, _standing(20), "humanoid_1seg").save(root / "whole.npz").read_bytes()
    (root / "truncated.npz").write_bytes(whole[: len(whole) // 2])
    (root / "text.npz").write_text("this is a text file, not a motion\n")
    (root / "broken.bvh").write_text(BAD_BVH)
    nan = _standing(20)
    nan[5, 12] = np.nan
    np.savez(root / "nan.npz", qpos=nan, fps=60.0, model="humanoid_1seg", name="nan", loop=False, source="{}")
    Motion("two", 60.0, _standing(2), "humanoid_1seg").save(root / "two_frames.npz")
    (root / "blocker").write_text("a file where an output folder should be made\n")
    names = ("truncated.npz", "text.npz", "broken.bvh", "nan.npz", "two_frames.npz")
    return {**{name.split(".")[0]: str(root / name) for name in names},
            "blocked": str(root / "blocker" / "out"), "root": str(root)}


@pytest.fixture(autouse=True)
def _no_traceback_override(monkeypatch):
    monkeypatch.delenv(TRACEBACK_VARIABLE, raising=False)


@pytest.fixture(autouse=True, scope="module")
def _policy_loaded_once():
    """evaluate.py and clean.py (through agents.policy_set) load the shipped walk policy once for
    all cases (it takes seconds)."""
    cached = functools.cache(load_policy)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(policy_set, "load_policy", cached)
        yield


def _fill(argv: tuple[str, ...], bad: dict[str, str]) -> list[str]:
    return [a.format(**bad) for a in argv]


def _error_line(main, argv: list[str], capsys) -> str:
    """The one line ``main(argv)`` ends with: Python prints ``SystemExit``'s message to stderr and
    exits with status 1."""
    with pytest.raises(SystemExit) as ended:
        main(argv)
    line = ended.value.code
    assert isinstance(line, str) and line.startswith("error: ") and "\n" not in line, line
    assert "Traceback" not in capsys.readouterr().err
    return line


def _subprocess_error_line(*command: str) -> str:
    """The stderr of ``python COMMAND`` run from the repository, which must fail with one line."""
    done = subprocess.run([sys.executable, *command], cwd=ROOT, capture_output=True, text=True, timeout=300)
    lines = done.stderr.splitlines()
    assert done.returncode == 1 and len(lines) == 1 and lines[0].startswith("error: "), done.stderr
    return lines[0]


# case: (argv with {name} for the files of `bad`, text the line must contain)
MOTION_CASES = {
    "truncated npz": (("info", "{truncated}"), "{truncated}: not a readable .npz motion file: not a valid .npz (zip)"),
    "text named .npz": (("info", "{text}"), "{text}: not a readable .npz motion file: not a valid .npz (zip)"),
    "bad BVH": (("quality", "{broken}"), "{broken}: malformed or truncated BVH"),
    "NaN": (("info", "{nan}"), "{nan}: motion 'nan': qpos has NaN/inf (first at frame 5, column 12)"),
    "unknown clip": (("info", "deepmimic:wlak"), "unknown DeepMimic clip 'wlak'"),
    "negative strength": (("quality", "deepmimic:walk", "--corrupt", "imu", "--strength", "-3"),
                          "argument --strength: expected a non-negative number, got '-3'"),
    "unsupported video": (("render", "deepmimic:walk", "--out", "x.avi"), "x.avi: cannot write a .avi file"),
    "output folder": (("render", "deepmimic:walk", "--out", "{blocked}/walk.mp4"), "{blocked}/walk.mp4: cannot create"),
}


@pytest.mark.parametrize("case", MOTION_CASES)
def test_reference_motion_cli(case, bad, capsys):
    argv, expected = MOTION_CASES[case]
    assert expected.format(**bad) in _error_line(motion_cli.main, _fill(argv, bad), capsys)


PERCEPTION_CASES = {
    "truncated npz": (("gait", "{truncated}"), "{truncated}: not a readable .npz keypoint or motion file"),
    "text named .npz": (("contacts", "{text}"), "{text}: not a readable .npz motion file: not a valid .npz (zip)"),
    "bad BVH": (("contacts", "{broken}"), "{broken}: malformed or truncated BVH"),
    "NaN": (("gait", "{nan}"), "{nan}: motion 'nan': qpos has NaN/inf"),
    "unknown clip": (("cleanup", "deepmimic:wlak", "--out", "{root}/c.npz"), "unknown DeepMimic clip 'wlak'"),
    "negative strength": (("cleanup", "deepmimic:walk", "--out", "{root}/c.npz", "--strength", "-3"),
                          "argument --strength: expected a non-negative number"),
    "negative min-frames": (("contacts", "deepmimic:walk", "--min-frames", "-5"),
                            "argument --min-frames: expected a non-negative integer, got '-5'"),
    "unsupported plot": (("gait", "deepmimic:walk", "--plot", "gait.avi"), "gait.avi: cannot write a .avi file"),
    "output folder": (("cleanup", "deepmimic:walk", "--out", "{blocked}/c.npz"), "{blocked}/c.npz: cannot create"),
}


@pytest.mark.parametrize("case", PERCEPTION_CASES)
def test_perception_cli(case, bad, capsys):
    argv, expected = PERCEPTION_CASES[case]
    assert expected.format(**bad) in _error_line(perception_cli.main, _fill(argv, bad), capsys)
    assert not Path(bad["root"], "c.npz").exists()


def test_make_dataset_cli(bad, capsys):
    line = _error_line(make_dataset.main, ["--out", f"{bad['root']}/d", "--episodes", "0"], capsys)
    assert "argument --episodes: expected a positive integer, got '0'" in line
    assert not Path(bad["root"], "d").exists()


CLIP_CASES = {
    "truncated npz": ("{truncated}", "{truncated}: not a readable .npz motion file: not a valid .npz (zip)"),
    "text named .npz": ("{text}", "{text}: not a readable .npz motion file: not a valid .npz (zip)"),
    "bad BVH": ("{broken}", "{broken}: malformed or truncated BVH"),
    "NaN": ("{nan}", "{nan}: motion 'nan': qpos has NaN/inf"),
    "unknown clip": ("deepmimic:wlak", "unknown DeepMimic clip 'wlak'"),
}
"""A bad clip given to evaluate.py, clean.py or train_ppo.py: (clip, text the line must contain)."""

EVALUATE_CASES = {
    **{name: (("--clips", clip), expected) for name, (clip, expected) in CLIP_CASES.items()},
    "2-frame clip": (("--clips", "{two_frames}"),
                     "{two_frames}: the clip has 2 frames at 60 Hz; a mimic episode needs at least"),
    "zero episodes": (("--clips", "deepmimic:walk", "--episodes", "0"),
                      "argument --episodes: expected a positive integer, got '0'"),
    "negative strength": (("--clips", "deepmimic:walk", "--corrupt", "imu", "--strength", "-3"),
                          "argument --strength: expected a non-negative number"),
    "output folder": (("--clips", "deepmimic:walk", "--json", "{blocked}/e.json"), "{blocked}/e.json: cannot create"),
}


@pytest.mark.parametrize("case", EVALUATE_CASES)
def test_evaluate_cli(case, bad, capsys):
    argv, expected = EVALUATE_CASES[case]
    line = _error_line(evaluate.main, ["--policy", POLICY, *_fill(argv, bad)], capsys)
    assert expected.format(**bad) in line


CLEAN_CASES = {
    **{name: ((clip,), expected) for name, (clip, expected) in CLIP_CASES.items()},
    "2-frame clip": (("{two_frames}",), "{two_frames}: the clip has 2 frames at 60 Hz; cleaning needs at least 3"),
    "negative strength": (("deepmimic:walk", "--corrupt", "imu", "--strength", "-3"),
                          "argument --strength: expected a non-negative number, got '-3'"),
    "negative min-frames": (("deepmimic:walk", "--min-frames", "-5"), "argument --min-frames: expected a non-negative"),
    "unsupported video": (("deepmimic:walk", "--video", "{root}/x.avi"),
                          "{root}/x.avi: cannot write a .avi file; use .mp4, .gif or .png"),
    "output folder": (("deepmimic:walk", "--bvh", "{blocked}/c.bvh"), "{blocked}/c.bvh: cannot create the folder"),
}


@pytest.mark.parametrize("case", CLEAN_CASES)
def test_clean_cli(case, bad, capsys):
    argv, expected = CLEAN_CASES[case]
    out = Path(bad["root"], "cleaned.npz")
    line = _error_line(clean.main, [*_fill(argv, bad), "--policy", POLICY, "--out", str(out)], capsys)
    assert expected.format(**bad) in line
    assert not out.exists()  # refused before any work was done


TRAIN_CASES = {
    **{name: (("--clips", clip), expected) for name, (clip, expected) in CLIP_CASES.items()},
    "zero steps": (("--total-steps", "0"), "argument --total-steps: expected a positive integer, got '0'"),
    "negative strength": (("--strength", "-3", "1"), "argument --strength: expected a non-negative number"),
    "run folder": (("--run-dir", "{blocked}/run"), "{blocked}/run: cannot create the folder"),
}


@pytest.mark.parametrize("case", TRAIN_CASES)
def test_train_cli(case, bad, capsys):
    argv, expected = TRAIN_CASES[case]
    run = Path(bad["root"], "run")
    line = _error_line(train_ppo.main, ["--run-dir", str(run), "--no-progress", *_fill(argv, bad)], capsys)
    assert expected.format(**bad) in line
    assert not run.exists()  # no run is recorded for bad input


@pytest.fixture(scope="module")
def trained_run(tmp_path_factory) -> Path:
    """A run directory whose best policy is the shipped walk policy."""
    run = tmp_path_factory.mktemp("run")
    shutil.copytree(POLICY, run / "best")
    (run / "evaluations.jsonl").write_text('{"steps": 1, "wall_s": 1.0}\n')
    return run


SHIP_CASES = {
    "bad clip": (("--clips", "{truncated}"), "{truncated}: not a readable .npz motion file"),
    "zero episodes": (("--clips", "deepmimic:walk", "--episodes", "0"), "argument --episodes: expected a positive"),
    "models folder": (("--models", "{blocked}/models"), "{blocked}/models: cannot create the folder"),
}


@pytest.mark.parametrize("case", SHIP_CASES)
def test_ship_cli(case, bad, trained_run, tmp_path, capsys):
    argv, expected = SHIP_CASES[case]
    models = tmp_path / "models"
    line = _error_line(ship.main, ["--run-dir", str(trained_run), "--name", "walk", "--models", str(models),
                                   *_fill(argv, bad)], capsys)
    assert expected.format(**bad) in line
    assert not any(models.glob("*"))  # nothing half-shipped


def test_each_entry_point_ends_with_one_line(bad):
    """The real entry points, run as a user runs them."""
    cases = [
        (["-m", "reference_motion", "info", bad["text"]], bad["text"]),
        (["-m", "perception", "gait", bad["truncated"]], bad["truncated"]),
        (["agents/evaluate.py", "--policy", POLICY, "--clips", bad["two_frames"]], bad["two_frames"]),
        (["agents/clean.py", "deepmimic:walk", "--policy", POLICY, "--out", "c.npz", "--video", "c.avi"], "c.avi"),
        (["agents/train_ppo.py", "--run-dir", bad["blocked"]], bad["blocked"]),
        (["agents/ship.py", "--run-dir", bad["root"], "--name", "walk"], bad["root"]),
        (["-m", "agents.physmimic", "evaluate", "--policy", POLICY, "--clips", "x", "--episodes", "0"],
         "physmimic evaluate --help"),
    ]
    for command, named in cases:
        assert named in _subprocess_error_line(*command), command


def test_physmimic_command_fronts_every_cli(capsys):
    with pytest.raises(SystemExit) as ended:
        physmimic.main(["--help"])
    assert ended.value.code == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in physmimic.COMMANDS)
    script = Path(sys.executable).with_name("physmimic")
    done = subprocess.run([str(script), "motion", "info", "deepmimic:walk", "--json"], capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0 and '"frames": 76' in done.stdout, done.stderr
    assert physmimic.main(["motion", "list", "--set", "locomotion"]) == 0
    assert "deepmimic:walker/turn_left1" in capsys.readouterr().out


def test_an_interrupted_write_leaves_the_old_file(tmp_path):
    target = tmp_path / "result.json"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_write(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("killed mid-write")
    assert target.read_text() == "old" and list(tmp_path.iterdir()) == [target]


def _same_policy_weights(first: Path, second: Path) -> bool:
    """Whether SB3 loads the same policy weights, name for name, from the two saved models."""
    a = PPO.load(first, device="cpu").policy.state_dict()
    b = PPO.load(second, device="cpu").policy.state_dict()
    return a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)


def test_ship_copies_the_resumable_run_and_keeps_it_on_a_later_ship(trained_run, tmp_path):
    """``--resumable`` puts the newest checkpoint and the run's records beside the policy; a later
    ship without it keeps that ``run/`` and any other folder rather than deleting them with the old
    policy; a later ``--resumable`` replaces ``run/`` only."""
    checkpoints = trained_run / "checkpoints"
    checkpoints.mkdir(exist_ok=True)
    for step in (10, 20):
        shutil.copy2(trained_run / "best" / "model.zip", checkpoints / f"step_{step}.zip")
        (checkpoints / f"step_{step}_vecnormalize.pkl").write_bytes(b"stats")
    (checkpoints / "step_20_sidecar.json").write_text("{}")
    (trained_run / "args.json").write_text('{"seed": 3}')
    models = tmp_path / "models"
    common = ["--run-dir", str(trained_run), "--name", "walk", "--models", str(models),
              "--clips", "deepmimic:walk", "--episodes", "1"]
    ship.main([*common, "--resumable"])
    run = models / "walk" / "run"
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == ["step_20.zip", "step_20_sidecar.json",
                                                                      "step_20_vecnormalize.pkl"]
    assert (run / "args.json").read_text() == '{"seed": 3}'
    assert (run / "evaluations.jsonl").exists() and not (run / "wall.json").exists()
    for shipped in (run / "checkpoints" / "step_20.zip", models / "walk" / "model.zip"):  # deflated, both
        with zipfile.ZipFile(shipped) as copy:
            assert {member.compress_type for member in copy.infolist()} == {zipfile.ZIP_DEFLATED}
    assert _same_policy_weights(run / "checkpoints" / "step_20.zip", checkpoints / "step_20.zip")
    assert _same_policy_weights(models / "walk" / "model.zip", trained_run / "best" / "model.zip")
    (models / "walk" / "student").mkdir()  # another folder kept beside the policy (a student, another run)
    (models / "walk" / "student" / "model.zip").write_text("student")
    ship.main(common)
    assert (models / "walk" / "run" / "checkpoints" / "step_20.zip").exists()
    assert (models / "walk" / "sidecar.json").exists()
    assert (models / "walk" / "student" / "model.zip").read_text() == "student"
    (checkpoints / "step_30.zip").write_bytes((checkpoints / "step_20.zip").read_bytes())
    (checkpoints / "step_30_vecnormalize.pkl").write_bytes(b"stats")
    ship.main([*common, "--resumable"])  # the run is replaced by the newer one, the other folder kept
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == ["step_30.zip", "step_30_vecnormalize.pkl"]
    assert (models / "walk" / "student" / "model.zip").read_text() == "student"


def test_ship_refuses_a_policy_over_the_size_limit_and_leaves_nothing(trained_run, tmp_path, monkeypatch):
    """The limit applies to what ships (the model as shipped, and with --resumable its run's checkpoint as
    copied, deflated), before the evaluation; either refused leaves nothing in models/."""
    ship._deflated_copy(trained_run / "best" / "model.zip", tmp_path / "deflated.zip")
    size = (tmp_path / "deflated.zip").stat().st_size  # the model as it ships
    monkeypatch.setattr(ship, "MAX_MODEL_BYTES", size - 1)
    models = tmp_path / "models"
    with pytest.raises(SystemExit, match=r"best/model\.zip as shipped: .* MB, over the .* MB limit for models/"):
        ship.main(["--run-dir", str(trained_run), "--name", "walk", "--models", str(models),
                   "--clips", "deepmimic:walk", "--episodes", "1"])
    assert list(models.iterdir()) == []
    monkeypatch.setattr(ship, "MAX_MODEL_BYTES", size)  # the policy fits; its run's checkpoint, deflated, does not
    run = tmp_path / "run"  # a copy: the shared run keeps its checkpoints
    shutil.copytree(trained_run, run, ignore=shutil.ignore_patterns("checkpoints"))
    checkpoints = run / "checkpoints"
    checkpoints.mkdir()
    (checkpoints / "step_10.zip").write_bytes(np.random.default_rng(0).bytes(size + 1))  # random bytes do not deflate
    with zipfile.ZipFile(checkpoints / "step_20.zip", "w") as big:
        big.writestr("policy.pth", np.random.default_rng(1).bytes(size + 1))
    with pytest.raises(SystemExit, match=r"checkpoints/step_20\.zip \(deflated\): .* MB, over the .* MB limit"):
        ship.main(["--run-dir", str(run), "--name", "walk", "--models", str(models),
                   "--clips", "deepmimic:walk", "--episodes", "1", "--resumable"])
    assert list(models.iterdir()) == []


def _zip_members(path: Path) -> dict[str, bytes]:
    """The zip archive ``path``'s members, name to bytes (the same however each is compressed)."""
    with zipfile.ZipFile(path) as archive:
        return {name: archive.read(name) for name in archive.namelist()}


def test_ship_newest_ships_the_newest_checkpoint_whole(tmp_path, capsys):
    """``--newest`` ships the run's newest checkpoint (a choice registered on it), not ``best/``, and
    refuses one whose observation statistics are missing."""
    run = tmp_path / "run"
    checkpoints = run / "checkpoints"
    checkpoints.mkdir(parents=True)
    for step in (10, 30):
        shutil.copy2(Path(POLICY, "model.zip"), checkpoints / f"step_{step}.zip")
        shutil.copy2(Path(POLICY, "model_vecnormalize.pkl"), checkpoints / f"step_{step}_vecnormalize.pkl")
        sidecar = json.loads(Path(POLICY, "sidecar.json").read_text())
        (checkpoints / f"step_{step}_sidecar.json").write_text(json.dumps({**sidecar, "steps": step}))
    (run / "wall.json").write_text('{"steps": 30, "wall_s": 2.0}')
    models = tmp_path / "models"
    common = ["--run-dir", str(run), "--models", str(models), "--clips", "deepmimic:walk", "--episodes", "1"]
    ship.main([*common, "--name", "walk", "--newest"])
    shipped = json.loads((models / "walk" / "sidecar.json").read_text())
    assert shipped["steps"] == 30 and shipped["training_steps_total"] == 30
    assert _zip_members(models / "walk" / "model.zip") == _zip_members(checkpoints / "step_30.zip")
    (checkpoints / "step_40.zip").write_bytes((checkpoints / "step_30.zip").read_bytes())
    line = _error_line(ship.main, [*common, "--name", "other", "--newest"], capsys)
    assert "step_40_vecnormalize.pkl, step_40_sidecar.json missing beside it" in line
    assert not (models / "other").exists()
    ship.main([*common, "--name", "registered", "--checkpoint", str(checkpoints / "step_10.zip")])  # not the newest
    assert json.loads((models / "registered" / "sidecar.json").read_text())["steps"] == 10
    line = _error_line(ship.main, [*common, "--name", "other", "--checkpoint", str(checkpoints / "step_99.zip")], capsys)
    assert "step_99.zip: no such checkpoint" in line
    elsewhere = tmp_path / "other_run" / "checkpoints"
    elsewhere.mkdir(parents=True)
    shutil.copy2(checkpoints / "step_10.zip", elsewhere / "step_10.zip")
    line = _error_line(ship.main, [*common, "--name", "other", "--checkpoint", str(elsewhere / "step_10.zip")], capsys)
    assert f"not a checkpoint of --run-dir {run}" in line
    with pytest.raises(SystemExit):  # one checkpoint or the other, not both
        ship.main([*common, "--name", "other", "--newest", "--checkpoint", str(checkpoints / "step_10.zip")])
    assert not (models / "other").exists()
