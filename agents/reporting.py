"""Writing command results as JSON files (evaluate.py, clean.py)."""

from __future__ import annotations

import json
from pathlib import Path


def write_json(path: Path, data: dict) -> Path:
    """Write ``data`` as indented JSON to ``path``, creating its folder; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=1, default=str))
    return path
