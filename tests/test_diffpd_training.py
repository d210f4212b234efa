"""Training the diff-PD networks (`agents/train_diffpd.py`), resuming, and cleaning with them
(`agents/clean.py --method diffpd`), on pybullet's DeepMimic walk with tiny networks (no
data/library needed)."""

from __future__ import annotations

import json

import pytest
import torch

from agents import clean, train_diffpd
from agents.diffpd_clean import DiffPDModelError, load_cycle
from agents.train_diffpd import TrainConfig, Trainer, dyn_loss, grf_losses, load_pairs, train

TINY = TrainConfig(clips=("deepmimic:walk",), window=4, batch=2, variants=1, dynet_hidden=(16, 16),
                   grfnet_hidden=(16, 16, 16), lr=3e-3, checkpoint_every=1000)
"""Two streams of 4-frame windows through DeepMimic walk (clean and one IMU-corrupted copy)."""


pytestmark = pytest.mark.usefixtures("one_thread")


@pytest.fixture(scope="module")
def pairs():
    return load_pairs(TINY)


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """A tiny model trained for 3 steps (weights, sidecar and checkpoint)."""
    out = tmp_path_factory.mktemp("diffpd")
    train(TINY, out, steps=3, command="test", progress=False)
    return out


def test_training_steps_decrease_the_losses(pairs):
    """On a fixed batch of windows, a few steps lower L_Dyn (DyNet) and L_GRF (GRFNet)."""
    trainer = Trainer(TINY, pairs)
    target, truth = trainer.windows()
    q0, qd0 = trainer.q.clone(), trainer.qd.clone()

    def losses() -> tuple[float, float]:
        with torch.no_grad():
            result = trainer.cycle.rollout(q0, qd0, target)
        dyn = dyn_loss(result, truth, target, TINY.tau_weight)
        grf = grf_losses(result, trainer.cycle.weight, trainer.cycle.config.mu)
        assert float(grf["cone"]) == 0.0  # λ is in the cone by construction
        return float(dyn["pose"] + dyn["tau"]), float(sum(grf.values()))

    dyn0, grf0 = losses()
    rows = [trainer.train_step() for _ in range(6)]
    dyn1, grf1 = losses()
    assert dyn1 < dyn0 and grf1 < grf0, (dyn0, dyn1, grf0, grf1)
    assert rows[-1]["s_g"] > 0.5  # the gains rise from the baseline's ½
    assert all(r["cone"] == 0.0 for r in rows)


def test_resume_continues_exactly(tmp_path, trained):
    """3 steps then 2 resumed = the same weights as 5 steps straight; the sidecar records both commands."""
    straight = tmp_path / "straight"
    train(TINY, straight, steps=5, progress=False)
    resumed = tmp_path / "resumed"
    resumed.mkdir()
    for name in ("checkpoint.pt", "diffpd.pt", "sidecar.json"):
        (resumed / name).write_bytes((trained / name).read_bytes())
    train(TINY, resumed, steps=5, resume=True, command="again", progress=False)
    a, b = load_cycle(straight), load_cycle(resumed)
    for net in ("dynet", "grfnet"):
        for (k, x), (_, y) in zip(getattr(a, net).state_dict().items(), getattr(b, net).state_dict().items()):
            torch.testing.assert_close(x, y, rtol=0, atol=0, msg=f"{net}.{k}")
    sidecar = json.loads((resumed / "sidecar.json").read_text())
    assert sidecar["steps"] == 5 and sidecar["commands"] == ["test", "again"] and sidecar["seed"] == TINY.seed
    assert sidecar["wall_s"] > 0 and sidecar["metrics"]["last20_pose"] > 0


def test_clean_with_diffpd_writes_the_outputs(tmp_path, trained):
    out = tmp_path / "c.npz"
    result = clean.main(["deepmimic:walk", "--method", "diffpd", "--policy", str(trained), "--corrupt", "imu",
                         "--out", str(out), "--json", str(tmp_path / "c.json"), "--bvh", str(tmp_path / "c.bvh")])
    assert out.exists() and (tmp_path / "c.bvh").exists()
    record = json.loads((tmp_path / "c.json").read_text())
    for key in ("source", "policy", "cleaned_by", "input", "cleaned", "simulated_fraction", "reanchors",
                "recoveries", "adaptation", "method", "diffpd"):
        assert key in record
    assert record["method"] == "diffpd" and record["input"].keys() == record["cleaned"].keys()
    assert record["diffpd"]["frames_per_s"] > 0 and result["simulated_fraction"] <= 1.0
    # the root residual is bounded by default, and its bound and saturation are reported
    sidecar = json.loads((trained / "sidecar.json").read_text())
    assert sidecar["cycle_config"]["residual_bound"] == [343.35, 200.0]
    assert record["diffpd"]["residual_bound_linear_bw"] == pytest.approx(0.5, abs=1e-3)
    assert record["diffpd"]["residual_bound_angular_nm"] == 200.0
    assert 0.0 <= record["diffpd"]["residual_linear_saturated_share"] <= 1.0


def _error(main, argv) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    message = str(exit_info.value.code)
    assert message.startswith("error: ") and "\n" not in message
    return message


def test_bad_inputs_give_one_line_errors(tmp_path, trained):
    common = ["deepmimic:walk", "--out", str(tmp_path / "x.npz")]
    assert "use --method ppo" in _error(clean.main, [*common, "--method", "diffpd", "--policy", "models/mimic_walk"])
    assert "invalid choice" in _error(clean.main, [*common, "--method", "magic", "--policy", str(trained)])
    assert "--no-adapt applies to --method ppo" in _error(
        clean.main, [*common, "--method", "diffpd", "--policy", str(trained), "--no-adapt"])
    assert "model.zip" in _error(clean.main, [*common, "--policy", str(trained)])  # diff-PD weights, PPO method
    # weights that do not fit their configuration
    state = torch.load(trained / "diffpd.pt", weights_only=False)
    state["config"]["dynet_hidden"] = [32, 32]
    bad = tmp_path / "bad"
    bad.mkdir()
    torch.save(state, bad / "diffpd.pt")
    with pytest.raises(DiffPDModelError, match="do not fit"):
        load_cycle(bad)
    assert "do not fit" in _error(clean.main, [*common, "--method", "diffpd", "--policy", str(bad)])
    (bad / "diffpd.pt").write_text("not torch")
    assert "cannot read diff-PD weights" in _error(clean.main, [*common, "--method", "diffpd", "--policy", str(bad)])
    assert "no checkpoint to resume" in _error(train_diffpd.main, ["--out", str(tmp_path / "none"), "--resume",
                                                                   "--steps", "1", "--no-progress"])
    assert "give a budget" in _error(train_diffpd.main, ["--out", str(tmp_path / "none"), "--clips", "deepmimic:walk"])
    assert "already holds a diff-PD model; pass --resume" in _error(
        train_diffpd.main, ["--out", str(bad), "--steps", "1", "--clips", "deepmimic:walk", "--no-progress"])
    (bad / "checkpoint.pt").write_text("not torch")
    assert "cannot read the checkpoint" in _error(
        train_diffpd.main, ["--out", str(bad), "--resume", "--steps", "1", "--no-progress"])
