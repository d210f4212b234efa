"""Validation's registered choice between policies, computed from the evaluations' JSON files.

Usage: ``python bench/select_policy.py --baseline P --clean A.json B.json ... --draws D1.json D2.json ...
[--confirm C1.json ...] [--json [OUT]]``

Each policy's score is the rule registered in the README ("Wider stances"):

    (validation clean ELR + 2 × mean ELR over the IMU draws behind the denoiser) / 3

``--clean`` takes ``agents/evaluate.py --json`` files (one policy each, read from their ``policy``
field); ``--draws`` and ``--confirm`` take ``bench/imu_draws.py --json`` files, whole or split into
one draw per file (``--draws 1 --first-seed S``, as ``bench/device/score_candidates.sh`` runs them):
the draws of each policy are gathered and put in seed order, and every policy must have been scored
on the same seeds. The winner is the best score; it replaces ``--baseline`` only if it is another
policy and, where ``--confirm`` draws are given, its mean ELR over them is above the baseline's.
Prints a table and the verdict; ``--json`` writes them (``winner``, ``replaces_baseline``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from imu_draws import paired  # bench/imu_draws.py: the scripts run from bench/
from json_report import emit_json

IMU_WEIGHT = 2.0
"""Weight of the IMU draws against validation clean in the registered rule."""


def rule_score(clean_elr: float, imu_elr: float) -> float:
    """The registered rule: ``(clean + IMU_WEIGHT × imu) / (1 + IMU_WEIGHT)``, ELRs in [0, 1]."""
    return (clean_elr + IMU_WEIGHT * imu_elr) / (1.0 + IMU_WEIGHT)


def read_json(path: Path, fields: tuple[str, ...]) -> dict:
    """``path`` parsed, with a clear error if it is not JSON or lacks one of ``fields``."""
    try:
        data = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise SystemExit(f"{path}: not a readable JSON file ({error})") from error
    missing = [f for f in fields if f not in data]
    if missing:
        raise SystemExit(f"{path}: missing field(s) {missing}; expected an evaluation written with --json")
    return data


def gather_draws(paths: list[Path]) -> dict[str, np.ndarray]:
    """Per policy, its ELR on each draw in the given ``imu_draws.py`` files, in order of the draws'
    first-clip seeds ``(draws,)``. Raises if a seed repeats for a policy or the policies' seeds differ."""
    by_policy: dict[str, dict[int, float]] = {}
    for path in paths:
        data = read_json(path, ("seeds_of_first_clip", "rows"))
        for row in data["rows"]:
            draws = by_policy.setdefault(row["policy"], {})
            for seed, elr in zip(data["seeds_of_first_clip"], row["ELR_per_draw"]):
                if seed in draws:
                    raise SystemExit(f"{path}: {row['policy']} has draw seed {seed} twice")
                draws[seed] = elr
    seed_sets = {policy: sorted(draws) for policy, draws in by_policy.items()}
    if len({tuple(s) for s in seed_sets.values()}) > 1:
        raise SystemExit(f"the policies were scored on different draws: {seed_sets}")
    return {policy: np.array([draws[s] for s in sorted(draws)]) for policy, draws in by_policy.items()}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", required=True, help="the policy in use (as named in the JSON files)")
    p.add_argument("--clean", nargs="+", type=Path, required=True, help="validation clean, evaluate.py --json")
    p.add_argument("--draws", nargs="+", type=Path, required=True, help="IMU draws behind the denoiser")
    p.add_argument("--confirm", nargs="*", type=Path, default=[], help="more draws the winner must also lead on")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()

    clean = {d["policy"]: d["ELR_mean"] for d in (read_json(f, ("policy", "ELR_mean")) for f in args.clean)}
    draws = gather_draws(args.draws)
    if set(clean) != set(draws):
        p.error(f"validation clean covers {sorted(clean)} but the draws cover {sorted(draws)}")
    if args.baseline not in clean:
        p.error(f"--baseline {args.baseline} is none of the scored policies {sorted(clean)}")
    rows = [{"policy": policy, "clean_ELR": clean[policy], "imu_ELR": float(draws[policy].mean()),
             "score": rule_score(clean[policy], float(draws[policy].mean())),
             "against_baseline": paired(draws[policy], draws[args.baseline])} for policy in sorted(clean)]
    for r in rows:
        c = r["against_baseline"]
        print(f"{r['policy']:<52} clean {r['clean_ELR']:.3f}  IMU {r['imu_ELR']:.3f} ({c['mean_difference']:+.3f} "
              f"± {c['standard_error']:.3f}, above on {c['draws_above']} of {len(draws[r['policy']])})  "
              f"rule {r['score']:.3f}")
    winner = max(rows, key=lambda r: r["score"])["policy"]
    report = {"baseline": args.baseline, "rows": rows, "winner": winner, "imu_weight": IMU_WEIGHT}
    replaces = winner != args.baseline
    if replaces and args.confirm:
        confirm = gather_draws(args.confirm)
        if winner not in confirm or args.baseline not in confirm:
            p.error(f"--confirm must score both {winner} and {args.baseline}")
        report["confirmation"] = paired(confirm[winner], confirm[args.baseline])
        replaces = report["confirmation"]["mean_difference"] > 0
        c = report["confirmation"]
        print(f"confirmation: {winner} {c['mean_difference']:+.3f} ± {c['standard_error']:.3f} against the baseline, "
              f"above on {c['draws_above']} of {len(confirm[winner])} draws")
    report["replaces_baseline"] = replaces
    verdict = (f"{args.baseline} stays" if not replaces else f"replaces {args.baseline}" if args.confirm
               else "leads the baseline; no confirmation draws given")
    print(f"winner by the rule: {winner}; {verdict}")
    emit_json(report, args.json)


if __name__ == "__main__":
    main()
