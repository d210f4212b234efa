"""A round's candidate policy set: a policy set with some of its fields replaced, written to a new directory.

Usage: ``python bench/rounds/derived_set.py BASE OUT FIELD=VALUE ...``, e.g. ``backward=models/mimic_general_back`` or
``sideways=PATH sideways_speed_mps=0.2``: a policy directory (or run checkpoint) for a rule's field, a number for a
threshold field (``*_speed_mps`` in m/s, ``turn_rate_rad_s`` in rad/s), ``denoise_slow_s=ROLE:SECONDS[,ROLE:SECONDS]``
(e.g. ``denoise_slow_s=dash:0.5``: the members whose denoiser corrections the set slows, replacing BASE's;
``denoise_slow_s=`` empty: none). A role whose policy is replaced drops the slowing BASE gave it unless
``denoise_slow_s`` is given: the slowing belongs to the member it was chosen for. Every other field of BASE
(:class:`agents.policy_set.PolicySet`), its clips' globs included, is kept (:func:`dataclasses.replace`);
``OUT/policy_set.json`` is written.
"""

from __future__ import annotations

import sys
from dataclasses import fields, replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from agents.policy import PolicyError  # noqa: E402
from agents.policy_set import THRESHOLD_FIELDS, PolicySet, load_policy_set  # noqa: E402

FIELDS = sorted({f.name for f in fields(PolicySet)} - {"path", "clips"})
"""The fields a change may name."""


def main(argv: list[str]) -> Path:
    if len(argv) < 3:
        raise SystemExit(__doc__)
    base, out, *changes = argv
    values: dict[str, Path | float | tuple[tuple[str, float], ...]] = {}
    for change in changes:
        name, sep, value = change.partition("=")
        if not sep or name not in FIELDS:
            raise SystemExit(f"derived_set.py: expected FIELD=VALUE with FIELD one of {', '.join(FIELDS)}, "
                             f"got {change!r}")
        try:
            if name == "denoise_slow_s":
                pairs = [pair.partition(":") for pair in value.split(",")] if value else []
                roles = [role for role, _, _ in pairs]
                if not all(role and sep for role, sep, _ in pairs) or len(set(roles)) < len(roles):
                    raise ValueError
                values[name] = tuple((role, float(seconds)) for role, _, seconds in pairs)
            else:
                values[name] = float(value) if name in THRESHOLD_FIELDS else Path(value)
        except ValueError:
            expected = "ROLE:SECONDS[,ROLE:SECONDS] with each ROLE once" if name == "denoise_slow_s" else "a number"
            raise SystemExit(f"derived_set.py: {name} is {expected}, got {value!r}") from None
    try:
        base_set = load_policy_set(base)
        if "denoise_slow_s" not in values:  # a replaced member does not inherit its role's slowing
            values["denoise_slow_s"] = tuple((role, seconds) for role, seconds in base_set.denoise_slow_s
                                             if role not in values)
        return replace(base_set, path=Path(out), **values).save()
    except PolicyError as err:
        raise SystemExit(f"derived_set.py: {err}") from None


if __name__ == "__main__":
    print(main(sys.argv[1:]))
