"""Writing command results as JSON files (evaluate.py, clean.py, ship.py, ``python -m perception``)."""

from __future__ import annotations

import json
from pathlib import Path

from reference_motion.atomic import atomic_write


def write_json(path: Path, data: dict) -> Path:
    """Write ``data`` as indented JSON to ``path``, atomically, creating its folder; returns the path."""
    path = Path(path)
    with atomic_write(path) as tmp:
        tmp.write_text(json.dumps(data, indent=1, default=str))
    return path
