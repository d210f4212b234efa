"""bench/imu_draws.py: ELR by style-shifted version, on hand-made rollouts; a policy set's draw, routed."""

import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "bench"
sys.path.append(str(BENCH))
import imu_draws  # noqa: E402
from imu_draws import Routed, evaluate_draw, shift_means, take_means  # noqa: E402

from agents.evaluation import Rollout, evaluate_tracking  # noqa: E402
from agents.policy import load_policy  # noqa: E402
from agents.policy_set import PolicySet  # noqa: E402
from reference_motion.library import load_motion  # noqa: E402
from reference_motion.library import STYLE_SHIFT_NAMES  # noqa: E402


def run(clip: str, elr: float) -> Rollout:
    return Rollout(clip=clip, start_frame=0, elr=elr, sr90=float(elr >= 0.9), rde=0.0, mrr=0.0, ended_by="",
                   simulated=None, reference=None)


def test_rollouts_are_averaged_by_the_version_of_their_take():
    """Two takes in five versions each (take by take, as style_shifted returns them): each version's
    mean is over both takes' rollouts of it, whatever order the rollouts come in."""
    names = [f"{take} v{k}" for take in ("a", "b") for k in range(len(STYLE_SHIFT_NAMES))]
    tracked = [SimpleNamespace(name=n) for n in names]
    elr = {"a v0": 1.0, "b v0": 0.8, "a v1": 0.5, "b v1": 0.7, "a v2": 1.0, "b v2": 1.0,
           "a v3": 0.2, "b v3": 0.4, "a v4": 0.9, "b v4": 0.9}
    runs = [run(n, elr[n]) for n in reversed(names)] + [run("a v3", 0.6)]
    means = shift_means(runs, tracked)
    assert list(means) == list(STYLE_SHIFT_NAMES)
    assert means["as given"] == pytest.approx(0.9)
    assert means["wider"] == pytest.approx(0.6)
    assert means["slower"] == pytest.approx(1.0)
    assert means["faster"] == pytest.approx(0.4)  # (0.2 + 0.4 + 0.6) / 3
    assert means["postured"] == pytest.approx(0.9)


def test_a_policy_sets_draw_is_each_take_performed_by_the_policy_it_is_routed_to(tmp_path):
    """A set sending DeepMimic's run to its fast policy (mimic_imu) and the walk to its default (mimic_walk): the
    draw's walk rollouts are mimic_walk's own, the run's mimic_imu's (which mimic_walk would not score), and the mean
    is over both takes' rollouts."""
    models = Path(__file__).resolve().parents[1] / "models"
    PolicySet(tmp_path / "set", models / "mimic_walk", models / "mimic_walk", fast=models / "mimic_imu").save()
    routed = Routed(str(tmp_path / "set"))
    walk, run_clip = (load_motion(f"deepmimic:{name}", "humanoid_1seg") for name in ("walk", "run"))
    groups = routed.groups([walk, run_clip, walk], None)
    assert [(policy.path.name, indices) for policy, indices, _ in groups] == [("mimic_walk", [0, 2]), ("mimic_imu", [1])]
    assert all(takes == [[walk, run_clip, walk][i] for i in indices] for _, indices, takes in groups)
    routing = routed.routing([([walk, run_clip, walk], None), ([run_clip], [walk])])  # the second judged as a walk
    walker, runner = str(models / "mimic_walk"), str(models / "mimic_imu")
    assert routing == {walk.name: {walker: 2}, run_clip.name: {runner: 1, walker: 1}}
    wider = [walk.with_qpos(walk.qpos, name=f"{walk.name} (stance +{m} m)") for m in (0.2, 0.3)]  # drawn anew
    versions = routed.routing([([walk, wider[0]], None), ([walk, wider[1]], None)], versions=("as given", "wider"))
    assert versions == {f"{walk.name} [as given]": {walker: 2}, f"{walk.name} [wider]": {walker: 2}}
    mean, runs = evaluate_draw(routed, [walk, run_clip], None, episodes=1, actor=None, mirror_average=False)
    alone = {name: evaluate_tracking(load_policy(models / name), [clip], episodes=1)[1][0].elr
             for name, clip in (("mimic_walk", walk), ("mimic_imu", run_clip))}
    assert alone["mimic_imu"] != evaluate_tracking(load_policy(models / "mimic_walk"), [run_clip], episodes=1)[1][0].elr
    by_clip = {r.clip: r.elr for r in runs}
    assert by_clip == {walk.name: alone["mimic_walk"], run_clip.name: alone["mimic_imu"]}
    assert mean == pytest.approx((alone["mimic_walk"] + alone["mimic_imu"]) / 2)


def test_each_takes_elr_is_averaged_over_the_draws_a_version_whose_name_is_drawn_anew_being_one_take():
    """Two draws of a walk in two versions, the wider one named with a stance drawn anew: ``take_means`` pools each
    version's rollouts over both draws under one name; a take no rollout scored is NaN, not dropped."""
    walk = SimpleNamespace(name="bvh:walk")
    draws = [([walk, SimpleNamespace(name=f"bvh:walk (stance +{m} m)")], None) for m in (0.2, 0.3)]
    scored = [(0.0, [run("bvh:walk", 1.0), run("bvh:walk", 0.8), run("bvh:walk (stance +0.2 m)", 0.4)]),
              (0.0, [run("bvh:walk", 0.6), run("bvh:walk (stance +0.3 m)", 0.2)])]
    assert take_means(scored, draws, ("as given", "wider")) == pytest.approx(
        {"bvh:walk [as given]": 0.8, "bvh:walk [wider]": 0.3})
    unversioned = take_means(scored, draws, None)
    assert unversioned == pytest.approx({"bvh:walk": 0.8, "bvh:walk (stance +0.2 m)": 0.4, "bvh:walk (stance +0.3 m)": 0.2})
    with pytest.warns(RuntimeWarning):  # the mean of no rollouts
        empty = take_means([(0.0, [])], [([walk], None)], None)
    assert list(empty) == ["bvh:walk"] and np.isnan(empty["bvh:walk"])


def test_artefacts_switched_off_need_artefacts(monkeypatch, capsys):
    """``--without KIND`` at ``--strength 0`` (clean takes, nothing to switch off) is refused by name."""
    monkeypatch.setattr(sys, "argv", ["imu_draws.py", "--policies", "models/mimic_general", "--strength", "0",
                                      "--without", "skate"])
    with pytest.raises(SystemExit) as ended:
        imu_draws.main()
    assert ended.value.code == 2
    assert "--without skate switches IMU artefacts off: the takes are clean at --strength 0" in capsys.readouterr().err


def test_a_member_the_set_slows_tracks_its_takes_prepared_anew_behind_its_slowing(tmp_path):
    """A set slowing its fast policy's denoiser corrections to 0.5 s: in a draw tracked behind the whole denoiser, the
    walk's takes are the draw's own, the run's are the run as given denoised behind the slowed corrections."""
    from agents.evaluate import tracked_and_judged
    from envs.preparation import no_preparation
    from perception.imu_denoiser import SlowCorrections, denoise
    from perception.weights import load_network

    models = Path(__file__).resolve().parents[1] / "models"
    PolicySet(tmp_path / "set", models / "mimic_walk", models / "mimic_walk", fast=models / "mimic_imu",
              denoise_slow_s=(("fast", 0.5),)).save()
    net = load_network(models / "imu_denoiser_dm", "denoiser")
    with pytest.raises(ValueError, match="give the draw's preparation steps with its denoiser"):
        Routed(str(tmp_path / "set"), net)
    routed = Routed(str(tmp_path / "set"), net, no_preparation())
    walk, run_clip = (load_motion(f"deepmimic:{name}", "humanoid_1seg") for name in ("walk", "run"))
    tracked, judged = tracked_and_judged([walk, run_clip], net)
    (walker, walk_indices, walks), (runner, run_indices, runs) = routed.groups(tracked, judged)
    assert (walk_indices, run_indices, walker.path.name, runner.path.name) == ([0], [1], "mimic_walk", "mimic_imu")
    assert walks[0] is tracked[0]
    slow = denoise(SlowCorrections(net, 0.5), run_clip)
    np.testing.assert_allclose(runs[0].qpos, slow.qpos)
    assert np.abs(runs[0].qpos - tracked[1].qpos).max() > 1e-3  # not the whole corrections
