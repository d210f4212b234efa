"""bench/select_denoiser.py: the registered choice between IMU denoisers, on hand-made draw files."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "bench"
sys.path.append(str(BENCH))
from select_denoiser import compare, read_draws  # noqa: E402


def draws_file(path: Path, denoiser: str | None, elr: dict[str, list[float]], seeds=(100, 107, 114),
               style_shifts: list[str] | None = None) -> str:
    path.write_text(json.dumps({"seeds_of_first_clip": list(seeds), "clips": ["val"], "episodes": 2,
                                "denoiser": denoiser, "style_shifts": style_shifts,
                                "rows": [{"policy": p, "ELR_per_draw": e} for p, e in elr.items()]}))
    return str(path)


def select(*args: str) -> tuple[int, dict | None, str]:
    run = subprocess.run([sys.executable, str(BENCH / "select_denoiser.py"), *args, "--json"], capture_output=True,
                         text=True, cwd=BENCH)
    text = run.stdout
    return run.returncode, json.loads(text[text.index("{"):]) if run.returncode == 0 else None, run.stderr


def test_paired_difference_and_named_rows(tmp_path):
    base = draws_file(tmp_path / "b.json", "dm", {"pi": [0.8, 0.6, 0.7], "other": [0.1, 0.1, 0.1]})
    cand = draws_file(tmp_path / "c.json", "new", {"pi": [0.9, 0.6, 0.9]})
    with pytest.raises(SystemExit, match="name exactly one"):
        read_draws(base)
    row = compare(read_draws(base + ":pi"), [read_draws(cand)])[0]
    assert row["ELR"] == pytest.approx(0.8)
    assert row["against_baseline"]["mean_difference"] == pytest.approx(0.1)
    assert (row["against_baseline"]["draws_above"], row["against_baseline"]["draws_equal"]) == (2, 1)


def test_other_draws_or_the_same_denoiser_are_refused(tmp_path):
    base = read_draws(draws_file(tmp_path / "b.json", "dm", {"pi": [0.8, 0.6, 0.7]}))
    with pytest.raises(SystemExit, match="different draws"):
        compare(base, [read_draws(draws_file(tmp_path / "c.json", "new", {"pi": [0.9, 0.6, 0.9]}, seeds=(1, 2, 3)))])
    with pytest.raises(SystemExit, match="tracked by different actors .'pi \\+ grounded', 'pi'"):
        compare(base, [read_draws(draws_file(tmp_path / "g.json", "new", {"pi + grounded": [0.9, 0.6, 0.9]}))])
    shifted = draws_file(tmp_path / "s.json", "new", {"pi": [0.9, 0.6, 0.9]}, style_shifts=["as given", "wider"])
    with pytest.raises(SystemExit, match="different draws .seeds, clips, rollouts or style shifts"):
        compare(base, [read_draws(shifted)])
    with pytest.raises(SystemExit, match="another denoiser"):
        compare(base, [read_draws(draws_file(tmp_path / "d.json", "dm", {"pi": [0.9, 0.6, 0.9]}))])
    with pytest.raises(SystemExit, match="without a denoiser"):
        read_draws(draws_file(tmp_path / "e.json", None, {"pi": [0.9, 0.6, 0.9]}))
    with pytest.raises(SystemExit, match=r"f\.json: rows\[0\] needs 'policy' and one 'ELR_per_draw' per seed"):
        read_draws(draws_file(tmp_path / "f.json", "dm", {"pi": [0.9, 0.6]}))


def test_the_best_candidate_leads_and_replaces_only_if_it_leads_the_confirmation_too(tmp_path):
    base = draws_file(tmp_path / "b.json", "dm", {"pi": [0.8, 0.6, 0.7]})
    weak = draws_file(tmp_path / "w.json", "weak", {"pi": [0.7, 0.6, 0.7]})
    strong = draws_file(tmp_path / "s.json", "strong", {"pi": [0.9, 0.7, 0.7]})
    rc, verdict, _ = select("--baseline", base, "--candidates", weak, strong)
    assert rc == 0 and verdict["leader"] == "strong" and verdict["leads_by_rule"] and not verdict["replaces_baseline"]
    confirm_base = draws_file(tmp_path / "cb.json", "dm", {"pi": [0.5, 0.5, 0.5]}, seeds=(200, 207, 214))
    for confirm_elr, replaces in (([0.6, 0.5, 0.5], True), ([0.4, 0.5, 0.5], False)):
        confirm = draws_file(tmp_path / "cs.json", "strong", {"pi": confirm_elr}, seeds=(200, 207, 214))
        rc, verdict, _ = select("--baseline", base, "--candidates", weak, strong, "--confirm-baseline", confirm_base,
                                "--confirm", confirm)
        assert rc == 0 and verdict["replaces_baseline"] is replaces
    rc, _, err = select("--baseline", base, "--candidates", weak, "--confirm-baseline", confirm_base,
                        "--confirm", draws_file(tmp_path / "cw.json", "weak", {"pi": [0.9, 0.9, 0.9]},
                                                seeds=(200, 207, 214)))
    assert rc != 0 and "no candidate leads dm" in err
    tie = draws_file(tmp_path / "t.json", "tie", {"pi": [0.7, 0.7, 0.7]})
    rc, verdict, _ = select("--baseline", base, "--candidates", tie)
    assert rc == 0 and verdict["leader"] == "dm" and not verdict["leads_by_rule"]  # a tie keeps the baseline


def test_a_confirmation_on_the_rule_s_draws_or_behind_another_baseline_is_refused(tmp_path):
    base = draws_file(tmp_path / "b.json", "dm", {"pi": [0.8, 0.6, 0.7]})
    strong = draws_file(tmp_path / "s.json", "strong", {"pi": [0.9, 0.7, 0.7]})
    rc, _, err = select("--baseline", base, "--candidates", strong, "--confirm-baseline", base, "--confirm", strong)
    assert rc != 0 and "overlap the rule's draws" in err
    other = draws_file(tmp_path / "ob.json", "other", {"pi": [0.5, 0.5, 0.5]}, seeds=(200, 207, 214))
    confirm = draws_file(tmp_path / "cs.json", "strong", {"pi": [0.6, 0.5, 0.5]}, seeds=(200, 207, 214))
    rc, _, err = select("--baseline", base, "--candidates", strong, "--confirm-baseline", other, "--confirm", confirm)
    assert rc != 0 and "--confirm-baseline is behind other" in err
