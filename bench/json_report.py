"""The ``--json [OUT]`` convention of the bench scripts: print the JSON, or write it to OUT."""

from __future__ import annotations

import json
import math

from reference_motion.atomic import atomic_write


def emit_json(result: dict, target: str | None) -> bool:
    """Print ``result`` as JSON when ``target == "-"``, write it to file ``target`` otherwise (and
    print it too), atomically: a script polling for ``target`` never reads it half-written; do
    nothing for ``None``. Returns whether JSON was requested. NaN and ±inf (a
    figure that does not exist, e.g. the push-off of a foot without toes) are written as ``null``,
    so the file is strict JSON."""
    if target is None:
        return False
    text = json.dumps(_finite(result), indent=1, allow_nan=False)
    if target != "-":
        with atomic_write(target) as tmp:
            tmp.write_text(text)
    print(text)
    return True


def _finite(value):
    """``value`` with every non-finite float (in dicts and lists, recursively) replaced by ``None``."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value
