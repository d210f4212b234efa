"""bench/select_policy.py: the registered rule and the gathering of split IMU draws, on hand-made files."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "bench"
sys.path.append(str(BENCH))
from select_policy import gather_draws, rule_score  # noqa: E402


def write(path: Path, data: dict) -> Path:
    path.write_text(json.dumps(data))
    return path


def draws_file(path: Path, seeds: list[int], elr: dict[str, list[float]]) -> Path:
    return write(path, {"seeds_of_first_clip": seeds,
                        "rows": [{"policy": p, "ELR_per_draw": e} for p, e in elr.items()]})


def test_rule_weights_the_imu_draws_twice():
    assert rule_score(0.9, 0.6) == pytest.approx(0.7)
    assert rule_score(1.0, 1.0) == pytest.approx(1.0)


def test_split_draws_are_gathered_in_seed_order(tmp_path):
    late = draws_file(tmp_path / "b.json", [107], {"a": [0.2], "b": [0.4]})
    early = draws_file(tmp_path / "a.json", [100], {"a": [0.8], "b": [0.6]})
    gathered = gather_draws([late, early])
    assert gathered["a"].tolist() == [0.8, 0.2]
    assert gathered["b"].tolist() == [0.6, 0.4]


def test_policies_on_different_draws_are_refused(tmp_path):
    one = draws_file(tmp_path / "a.json", [100], {"a": [0.8]})
    other = draws_file(tmp_path / "b.json", [107], {"b": [0.6]})
    with pytest.raises(SystemExit, match="different draws"):
        gather_draws([one, other])


def test_a_repeated_draw_is_refused(tmp_path):
    one = draws_file(tmp_path / "a.json", [100], {"a": [0.8]})
    with pytest.raises(SystemExit, match="twice"):
        gather_draws([one, one])


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(BENCH / "select_policy.py"), *args], capture_output=True, text=True)


def test_the_winner_replaces_the_baseline_only_if_it_also_leads_the_confirmation(tmp_path):
    clean = [write(tmp_path / "c_base.json", {"policy": "base", "ELR_mean": 0.96}),
             write(tmp_path / "c_new.json", {"policy": "new", "ELR_mean": 0.93})]
    draws = draws_file(tmp_path / "d.json", [100, 107], {"base": [0.70, 0.80], "new": [0.85, 0.85]})
    # base: (0.96 + 2 * 0.75) / 3 = 0.820; new: (0.93 + 2 * 0.85) / 3 = 0.877
    common = ["--baseline", "base", "--clean", *map(str, clean), "--draws", str(draws), "--json", "-"]
    lost = run(*common, "--confirm", str(draws_file(tmp_path / "k1.json", [200], {"base": [0.9], "new": [0.8]})))
    assert lost.returncode == 0, lost.stderr
    report = json.loads(lost.stdout[lost.stdout.index("{"):])
    assert report["winner"] == "new" and report["replaces_baseline"] is False
    assert report["rows"][1]["score"] == pytest.approx((0.93 + 2 * 0.85) / 3)
    won = run(*common, "--confirm", str(draws_file(tmp_path / "k2.json", [200], {"base": [0.7], "new": [0.8]})))
    assert json.loads(won.stdout[won.stdout.index("{"):])["replaces_baseline"] is True


def test_a_baseline_that_was_not_scored_is_a_clear_error(tmp_path):
    clean = write(tmp_path / "c.json", {"policy": "base", "ELR_mean": 0.9})
    draws = draws_file(tmp_path / "d.json", [100], {"base": [0.7]})
    result = run("--baseline", "other", "--clean", str(clean), "--draws", str(draws))
    assert result.returncode != 0 and "--baseline other is none of the scored policies" in result.stderr
