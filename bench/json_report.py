"""The ``--json [OUT]`` convention of the bench scripts: print the JSON, or write it to OUT."""

from __future__ import annotations

import json
from pathlib import Path


def emit_json(result: dict, target: str | None) -> bool:
    """Print ``result`` as JSON when ``target == "-"``, write it to file ``target`` otherwise (and
    print it too); do nothing for ``None``. Returns whether JSON was requested."""
    if target is None:
        return False
    text = json.dumps(result, indent=1)
    if target != "-":
        Path(target).parent.mkdir(parents=True, exist_ok=True)
        Path(target).write_text(text)
    print(text)
    return True
