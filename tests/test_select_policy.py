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


def draws_file(path: Path, seeds: list[int], elr: dict[str, list[float]], denoiser: str | None = "dm",
               style_shifts: list[str] | None = None) -> Path:
    return write(path, {"seeds_of_first_clip": seeds, "clips": ["val"], "episodes": 2, "denoiser": denoiser,
                        "style_shifts": style_shifts,
                        "rows": [{"policy": p, "ELR_per_draw": e} for p, e in elr.items()]})


def clean_file(path: Path, policy: str, elr: float) -> Path:
    return write(path, {"policy": policy, "ELR_mean": elr, "corrupt": None})


def test_rule_weights_the_imu_draws_twice():
    assert rule_score(0.9, 0.6) == pytest.approx(0.7)
    assert rule_score(1.0, 1.0) == pytest.approx(1.0)


def test_split_draws_are_gathered_in_seed_order(tmp_path):
    late = draws_file(tmp_path / "b.json", [107], {"a": [0.2], "b": [0.4]})
    early = draws_file(tmp_path / "a.json", [100], {"a": [0.8], "b": [0.6]})
    gathered = gather_draws([late, early])
    assert gathered.seeds == [100, 107]
    assert gathered.elr["a"].tolist() == [0.8, 0.2]
    assert gathered.elr["b"].tolist() == [0.6, 0.4]


def test_policies_on_different_draws_are_refused(tmp_path):
    one = draws_file(tmp_path / "a.json", [100], {"a": [0.8]})
    other = draws_file(tmp_path / "b.json", [107], {"b": [0.6]})
    with pytest.raises(SystemExit, match="different draws"):
        gather_draws([one, other])


def test_a_repeated_draw_is_refused(tmp_path):
    one = draws_file(tmp_path / "a.json", [100], {"a": [0.8]})
    with pytest.raises(SystemExit, match="twice"):
        gather_draws([one, one])


def test_draws_with_other_settings_or_missing_fields_are_refused(tmp_path):
    one = draws_file(tmp_path / "a.json", [100], {"a": [0.8]})
    raw = draws_file(tmp_path / "b.json", [107], {"a": [0.6]}, denoiser=None)
    with pytest.raises(SystemExit, match="differ in clips, rollouts, denoiser or style shifts"):
        gather_draws([one, raw])
    shifted = draws_file(tmp_path / "s.json", [107], {"a": [0.6]}, style_shifts=["as given", "wider"])
    with pytest.raises(SystemExit, match="differ in clips, rollouts, denoiser or style shifts"):
        gather_draws([one, shifted])
    clean_takes = write(tmp_path / "z.json", {**json.loads(one.read_text()), "strength": 0.0})
    with pytest.raises(SystemExit, match=r"z\.json: draws at IMU strength 0; the selection rules read .* strength 1"):
        gather_draws([clean_takes])
    assert gather_draws([write(tmp_path / "one.json", {**json.loads(one.read_text()), "strength": 1.0})]).seeds == [100]
    probe = write(tmp_path / "w.json", {**json.loads(one.read_text()), "without": ["skate"]})
    with pytest.raises(SystemExit, match=r"w\.json: draws with the artefact kinds \['skate'\] switched off"):
        gather_draws([probe])
    assert gather_draws([write(tmp_path / "all.json", {**json.loads(one.read_text()), "without": []})]).seeds == [100]
    short = draws_file(tmp_path / "c.json", [100, 107], {"a": [0.8]})
    with pytest.raises(SystemExit, match=r"c\.json: rows\[0\] needs 'policy' and one 'ELR_per_draw' per seed"):
        gather_draws([short])


def select(tmp_path: Path, *extra: str, draws_per_policy: int = 2) -> tuple[subprocess.CompletedProcess, dict]:
    """select_policy.py on two policies: base (0.96 clean, 0.75 IMU: rule 0.820) and new (0.93, 0.85:
    rule 0.877); returns the process and its JSON report."""
    clean = [clean_file(tmp_path / "c_base.json", "base", 0.96), clean_file(tmp_path / "c_new.json", "new", 0.93)]
    draws = draws_file(tmp_path / "d.json", [100, 107], {"base": [0.70, 0.80], "new": [0.85, 0.85]})
    result = subprocess.run([sys.executable, str(BENCH / "select_policy.py"), "--baseline", "base",
                             "--clean", *map(str, clean), "--draws", str(draws), "--draws-per-policy",
                             str(draws_per_policy), "--json", "-", *extra], capture_output=True, text=True, timeout=120)
    report = json.loads(result.stdout[result.stdout.index("{"):]) if result.returncode == 0 else {}
    return result, report


def test_the_winner_replaces_the_baseline_only_once_it_also_leads_the_confirmation(tmp_path):
    result, unconfirmed = select(tmp_path)
    assert result.returncode == 0, result.stderr
    assert unconfirmed["rows"][1]["score"] == pytest.approx((0.93 + 2 * 0.85) / 3)
    assert unconfirmed["winner"] == "new" and unconfirmed["leads_by_rule"] is True
    assert unconfirmed["replaces_baseline"] is False
    lost = draws_file(tmp_path / "k1.json", [200, 207], {"base": [0.9, 0.9], "new": [0.8, 0.9]})
    result, report = select(tmp_path, "--confirm", str(lost))
    assert result.returncode == 0, result.stderr
    assert report["replaces_baseline"] is False and report["confirmation"]["draws_below"] == 1
    won = draws_file(tmp_path / "k2.json", [200, 207], {"base": [0.7, 0.9], "new": [0.8, 0.9]})
    result, report = select(tmp_path, "--confirm", str(won))
    assert result.returncode == 0, result.stderr
    assert report["replaces_baseline"] is True


def test_confirmation_draws_must_be_unused_and_complete(tmp_path):
    reused = draws_file(tmp_path / "k.json", [107, 114], {"base": [0.7, 0.7], "new": [0.8, 0.8]})
    result, _ = select(tmp_path, "--confirm", str(reused))
    assert result.returncode != 0 and "overlap the rule's draws" in result.stderr
    result, _ = select(tmp_path, draws_per_policy=10)
    assert result.returncode != 0 and "expected 10 draws per policy" in result.stderr


def test_a_tie_keeps_the_baseline(tmp_path):
    clean = [clean_file(tmp_path / "c_base.json", "base", 0.9), clean_file(tmp_path / "c_zzz.json", "a", 0.9)]
    draws = draws_file(tmp_path / "d.json", [100], {"base": [0.7], "a": [0.7]})
    result = subprocess.run([sys.executable, str(BENCH / "select_policy.py"), "--baseline", "base", "--clean",
                             *map(str, clean), "--draws", str(draws), "--draws-per-policy", "1"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "winner by the rule: base; base stays" in result.stdout


def test_a_baseline_that_was_not_scored_is_a_clear_error(tmp_path):
    clean = clean_file(tmp_path / "c.json", "base", 0.9)
    draws = draws_file(tmp_path / "d.json", [100], {"base": [0.7]})
    result = subprocess.run([sys.executable, str(BENCH / "select_policy.py"), "--baseline", "other", "--clean",
                             str(clean), "--draws", str(draws), "--draws-per-policy", "1"],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode != 0 and "--baseline other is none of the scored policies" in result.stderr


def test_draws_with_no_denoiser_are_scored_but_not_confirmed_by_denoised_ones(tmp_path):
    """The rows with no denoiser in front are chosen on raw draws (denoiser null); confirmation draws
    tracked otherwise are refused."""
    clean = [clean_file(tmp_path / "c_base.json", "base", 0.96), clean_file(tmp_path / "c_new.json", "new", 0.93)]
    raw = draws_file(tmp_path / "d.json", [100, 107], {"base": [0.6, 0.6], "new": [0.45, 0.4]}, denoiser=None)
    command = [sys.executable, str(BENCH / "select_policy.py"), "--baseline", "base", "--clean", *map(str, clean),
               "--draws", str(raw), "--draws-per-policy", "2", "--json", "-"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout[result.stdout.index("{"):])
    assert report["rows"][0]["score"] == pytest.approx((0.96 + 2 * 0.6) / 3) and report["winner"] == "base"
    assert report["denoiser"] is None and "tracked as given (no denoiser)" in result.stdout
    denoised = draws_file(tmp_path / "k.json", [200, 207], {"base": [0.9, 0.9], "new": [0.9, 0.9]})
    result = subprocess.run([*command, "--confirm", str(denoised)], capture_output=True, text=True, timeout=120)
    assert result.returncode != 0 and "must be tracked alike" in result.stderr
