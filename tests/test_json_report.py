"""bench/json_report.emit_json: strict JSON (non-finite figures as null), printed and written whole."""

import json
import sys
from pathlib import Path

import pytest

sys.path.append(str(Path(__file__).resolve().parents[1] / "bench"))

from json_report import emit_json  # noqa: E402


def test_emit_json_writes_strict_json_and_prints_it(tmp_path, capsys):
    target = tmp_path / "deep" / "result.json"
    assert emit_json({"push_off": float("nan"), "rows": [1.5, float("inf"), {"x": -float("inf")}]}, str(target))
    expected = {"push_off": None, "rows": [1.5, None, {"x": None}]}
    assert json.loads(target.read_text()) == expected
    assert json.loads(capsys.readouterr().out) == expected
    assert [p.name for p in target.parent.iterdir()] == ["result.json"]  # no temporary file left beside it


def test_emit_json_prints_only_for_dash_and_does_nothing_for_none(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert emit_json({"a": 1}, "-") and json.loads(capsys.readouterr().out) == {"a": 1}
    assert not emit_json({"a": 1}, None) and capsys.readouterr().out == ""
    assert list(tmp_path.iterdir()) == []


def test_a_write_that_fails_halfway_leaves_the_old_file_whole(tmp_path, monkeypatch):
    """A script polling for the file reads the old result or the whole new one, never half of it."""
    target = tmp_path / "result.json"
    target.write_text('{"old": true}')

    def half_then_fail(path, text, *args, **kwargs):
        with open(path, "w") as f:
            f.write(text[: len(text) // 2])
        raise OSError("disk full")

    monkeypatch.setattr(Path, "write_text", half_then_fail)
    with pytest.raises(OSError, match="disk full"):
        emit_json({"new": list(range(50))}, str(target))
    assert json.loads(target.read_text()) == {"old": True}
    assert [p.name for p in tmp_path.iterdir()] == ["result.json"]
