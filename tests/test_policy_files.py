"""agents/policy.py: a policy loaded from a run's checkpoint names that checkpoint's files, and
what reads the weights again (adaptation's cache key, its training copy) reads the checkpoint's,
not a ``model.zip`` the checkpoints folder does not have."""

import shutil
from dataclasses import replace
from pathlib import Path

import pytest
import torch

from agents import adaptation
from agents.adaptation import adaptation_key
from agents.foot_transfer import transfer
from agents.policy import PolicyError, load_policy, policy_files

MODELS = Path(__file__).parents[1] / "models"


def _run_with_two_checkpoints(tmp_path: Path) -> Path:
    """``tmp_path/run/checkpoints`` holding mimic_walk as ``step_10`` and, with one bias moved, as ``step_20``."""
    checkpoints = tmp_path / "run" / "checkpoints"
    checkpoints.mkdir(parents=True)
    for step in (10, 20):
        shutil.copy2(MODELS / "mimic_walk" / "model_vecnormalize.pkl", checkpoints / f"step_{step}_vecnormalize.pkl")
        shutil.copy2(MODELS / "mimic_walk" / "sidecar.json", checkpoints / f"step_{step}_sidecar.json")
    shutil.copy2(MODELS / "mimic_walk" / "model.zip", checkpoints / "step_10.zip")
    moved = load_policy(MODELS / "mimic_walk").model
    with torch.no_grad():
        moved.policy.action_net.bias += 0.01
    moved.save(checkpoints / "step_20.zip")
    return checkpoints


def test_policy_files_of_a_directory_its_model_zip_and_a_checkpoint():
    directory = Path("models/x")
    assert policy_files(directory) == policy_files(directory / "model.zip") == (
        directory, directory / "model.zip", directory / "model_vecnormalize.pkl")
    step = Path("run/checkpoints/step_20.zip")
    assert policy_files(step) == (step.parent, step, step.parent / "step_20_vecnormalize.pkl")


def test_a_checkpoint_loaded_policy_is_named_and_keyed_by_its_own_files(tmp_path, walk):
    checkpoints = _run_with_two_checkpoints(tmp_path)
    first, second = load_policy(checkpoints / "step_10.zip"), load_policy(checkpoints / "step_20.zip")
    assert first.path == second.path == checkpoints  # one directory for both ...
    assert (first.model_file, first.stats_file, first.name) == (
        checkpoints / "step_10.zip", checkpoints / "step_10_vecnormalize.pkl", str(checkpoints / "step_10.zip"))
    assert second.name == str(checkpoints / "step_20.zip")  # ... but each named by its file
    assert (first.short_name, second.short_name) == ("run/step_10", "run/step_20")
    derived = second.simulating(240.0).observing("reference")  # a derived policy keeps its file
    assert (derived.model_file, derived.name) == (second.model_file, second.name)
    in_memory = replace(second, source=None)  # built in memory: named by its directory
    assert (in_memory.model_file, in_memory.name) == (checkpoints / "model.zip", str(checkpoints))
    assert adaptation_key(walk, first) != adaptation_key(walk, second)  # the weights differ, so do the keys
    shipped = load_policy(MODELS / "mimic_walk")
    by_archive = load_policy(MODELS / "mimic_walk" / "model.zip")
    assert shipped.name == by_archive.name == str(MODELS / "mimic_walk") and by_archive.short_name == "mimic_walk"
    assert shipped.model_file == by_archive.model_file == MODELS / "mimic_walk" / "model.zip"
    assert adaptation_key(walk, by_archive) == adaptation_key(walk, shipped)


def test_adaptation_trains_a_copy_of_the_checkpoint_it_was_given(tmp_path, walk, monkeypatch):
    """``_adapt`` loads the training copy's statistics from the checkpoint's own file (stopped there)."""
    checkpoints = _run_with_two_checkpoints(tmp_path)
    read = []

    class Loaded(Exception):
        pass

    def load(path, venv):
        read.append(path)
        venv.close()
        raise Loaded

    monkeypatch.setattr(adaptation.VecNormalize, "load", load)
    with pytest.raises(Loaded):
        adaptation.adapt_policy(load_policy(checkpoints / "step_20.zip"), walk,
                                adaptation.AdaptConfig(cache_dir=tmp_path / "cache"), progress=False)
    assert read == [str(checkpoints / "step_20_vecnormalize.pkl")]


def test_errors_about_a_checkpoint_name_its_file(tmp_path):
    """A message about a policy loaded from a run's checkpoint names the checkpoint, not the folder of all of them."""
    checkpoints = _run_with_two_checkpoints(tmp_path)
    policy = load_policy(checkpoints / "step_20.zip")
    with pytest.raises(PolicyError, match=r"checkpoints/step_20\.zip: already a foot='one' policy"):
        transfer(policy, policy.foot, tmp_path / "carried")
