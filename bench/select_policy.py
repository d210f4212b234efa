"""Validation's registered choice between policies, computed from the evaluations' JSON files.

Usage: ``python bench/select_policy.py --baseline P --clean A.json B.json ... --draws D1.json D2.json ...
[--confirm C1.json ...] [--json [OUT]]``

Each policy's score is the rule registered in the README ("Wider stances"):

    (validation clean ELR + 2 × mean ELR over the IMU draws behind the denoiser) / 3

(the rows that track IMU takes with no denoiser in front read draws made with none, README "Round 20")

``--clean`` takes ``agents/evaluate.py --json`` files (one policy each, read from their ``policy``
field); ``--draws`` and ``--confirm`` take ``bench/imu_draws.py --json`` files, whole or split into
one draw per file (``--draws 1 --first-seed S``, as ``bench/device/score_candidates.sh`` runs them):
the draws of each policy are gathered and put in seed order, and every policy must have been scored
on the same seeds, with the same clips, rollouts and denoiser. The winner is the best score (a tie
keeps the baseline); ``leads_by_rule`` says it is another policy, and ``replaces_baseline`` that it
also leads the baseline's mean ELR over the ``--confirm`` draws (false while none are given).
Prints a table and the verdict; ``--json`` writes them.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from paired_draws import overlapping_draws, paired

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


DRAW_FIELDS = ("seeds_of_first_clip", "rows", "clips", "episodes", "denoiser")
"""What an ``imu_draws.py --json`` file holds."""


def read_draw_file(path: Path) -> dict:
    """An ``imu_draws.py --json`` file, with a clear error if it lacks one of :data:`DRAW_FIELDS`
    or a row lacks its ``policy`` or one ``ELR_per_draw`` per seed; its ``style_shifts`` as a tuple,
    empty for plain draws (files from before ``--style-shifts`` have none). Only draws at the IMU rows'
    strength 1 are read (files from before ``--strength`` have none, and were), with every artefact kind on
    (files from before ``--without`` have none, and had)."""
    data = read_json(path, DRAW_FIELDS)
    data["style_shifts"] = tuple(data.get("style_shifts") or ())
    if data.get("strength", 1.0) != 1.0:
        raise SystemExit(f"{path}: draws at IMU strength {data['strength']:g}; the selection rules read the IMU "
                         "rows' draws, at strength 1 (imu_draws.py's default)")
    if data.get("without"):
        raise SystemExit(f"{path}: draws with the artefact kinds {data['without']} switched off; the selection rules "
                         "read the IMU rows' draws, with every kind on (imu_draws.py without --without)")
    for i, row in enumerate(data["rows"]):
        if "policy" not in row or len(row.get("ELR_per_draw", ())) != len(data["seeds_of_first_clip"]):
            raise SystemExit(f"{path}: rows[{i}] needs 'policy' and one 'ELR_per_draw' per seed in "
                             f"'seeds_of_first_clip' ({len(data['seeds_of_first_clip'])})")
    return data


@dataclass(frozen=True)
class Draws:
    """IMU draws gathered from ``imu_draws.py`` files.

    Attributes:
        seeds: the first clip's artefact seed of each draw, ascending.
        settings: ``(clips, rollouts per clip and draw, denoiser, style shifts)``, the same in every file.
        elr: per policy, its ELR on each draw ``(draws,)``, in the order of ``seeds``.
    """

    seeds: list[int]
    settings: tuple
    elr: dict[str, np.ndarray]


def gather_draws(paths: list[Path]) -> Draws:
    """The draws in the given ``imu_draws.py`` files. Raises if the files differ in clips, rollouts,
    denoiser or style shifts (``--style-shifts``), a seed repeats for a policy, or the policies' seeds differ."""
    by_policy: dict[str, dict[int, float]] = {}
    settings: dict[str, tuple] = {}
    for path in paths:
        data = read_draw_file(path)
        settings[str(path)] = (tuple(data["clips"]), data["episodes"], data["denoiser"], data["style_shifts"])
        for row in data["rows"]:
            draws = by_policy.setdefault(row["policy"], {})
            for seed, elr in zip(data["seeds_of_first_clip"], row["ELR_per_draw"]):
                if seed in draws:
                    raise SystemExit(f"{path}: {row['policy']} has draw seed {seed} twice")
                draws[seed] = elr
    if len(set(settings.values())) > 1:
        raise SystemExit(f"the draw files differ in clips, rollouts, denoiser or style shifts: {settings}")
    seed_sets = {policy: sorted(draws) for policy, draws in by_policy.items()}
    if len({tuple(s) for s in seed_sets.values()}) > 1:
        raise SystemExit(f"the policies were scored on different draws: {seed_sets}")
    seeds = next(iter(seed_sets.values()))
    return Draws(seeds=seeds, settings=next(iter(settings.values())),
                 elr={policy: np.array([draws[s] for s in seeds]) for policy, draws in by_policy.items()})


def clean_scores(paths: list[Path]) -> dict[str, float]:
    """Per policy, its validation clean ELR from ``evaluate.py --json`` files (one policy each)."""
    scores: dict[str, float] = {}
    for path in paths:
        data = read_json(path, ("policy", "ELR_mean", "corrupt"))
        if data["corrupt"] is not None:
            raise SystemExit(f"{path}: corrupt is {data['corrupt']!r}; validation clean needs an evaluation of "
                             f"the takes as recorded (corrupt null)")
        if data["policy"] in scores:
            raise SystemExit(f"{path}: a second validation clean evaluation of {data['policy']}")
        scores[data["policy"]] = data["ELR_mean"]
    return scores


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", required=True, help="the policy in use (as named in the JSON files)")
    p.add_argument("--clean", nargs="+", type=Path, required=True, help="validation clean, evaluate.py --json")
    p.add_argument("--draws", nargs="+", type=Path, required=True,
                   help="IMU draws (bench/imu_draws.py --json): behind the denoiser, or with none for the rows "
                        "with none in front")
    p.add_argument("--confirm", nargs="*", type=Path, default=[], help="more draws the winner must also lead on")
    p.add_argument("--draws-per-policy", type=int, default=10, help="draws each policy must have (both sets)")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()

    clean = clean_scores(args.clean)
    gathered = gather_draws(args.draws)
    confirmation = gather_draws(args.confirm) if args.confirm else None
    tracking = {d.settings[2:] for d in (gathered, confirmation) if d is not None}
    if len(tracking) > 1:
        p.error(f"the rule's draws and confirmation draws must be tracked alike (one denoiser, or none for the rows "
                f"with no denoiser; style-shifted or not): these files have (denoiser, style shifts) "
                f"{sorted(map(str, tracking))}")
    draws = gathered.elr
    short = {policy: len(elr) for policy, elr in draws.items() if len(elr) != args.draws_per_policy}
    if short:
        p.error(f"expected {args.draws_per_policy} draws per policy, got {short}")
    if set(clean) != set(draws):
        p.error(f"validation clean covers {sorted(clean)} but the draws cover {sorted(draws)}")
    if args.baseline not in clean:
        p.error(f"--baseline {args.baseline} is none of the scored policies {sorted(clean)}")
    print(f"IMU draws tracked {'behind ' + gathered.settings[2] if gathered.settings[2] else 'as given (no denoiser)'}")
    rows = [{"policy": policy, "clean_ELR": clean[policy], "imu_ELR": float(draws[policy].mean()),
             "score": rule_score(clean[policy], float(draws[policy].mean())),
             "against_baseline": paired(draws[policy], draws[args.baseline])} for policy in sorted(clean)]
    for r in rows:
        c = r["against_baseline"]
        print(f"{r['policy']:<52} clean {r['clean_ELR']:.3f}  IMU {r['imu_ELR']:.3f} ({c['mean_difference']:+.3f} "
              f"± {c['standard_error']:.3f}, above on {c['draws_above']} of {len(draws[r['policy']])})  "
              f"rule {r['score']:.3f}")
    winner = max(rows, key=lambda r: (r["score"], r["policy"] == args.baseline))["policy"]
    leads = winner != args.baseline
    report = {"baseline": args.baseline, "rows": rows, "winner": winner, "imu_weight": IMU_WEIGHT,
              "denoiser": gathered.settings[2], "leads_by_rule": leads}
    replaces = False
    if leads and confirmation is not None:
        confirm = confirmation.elr
        if winner not in confirm or args.baseline not in confirm:
            p.error(f"--confirm must score both {winner} and {args.baseline}")
        if len(confirm[winner]) != args.draws_per_policy:
            p.error(f"expected {args.draws_per_policy} confirmation draws, got {len(confirm[winner])}")
        overlap = overlapping_draws(gathered.seeds, confirmation.seeds)
        if overlap:
            p.error(overlap)
        report["confirmation"] = paired(confirm[winner], confirm[args.baseline])
        replaces = report["confirmation"]["mean_difference"] > 0
        c = report["confirmation"]
        print(f"confirmation: {winner} {c['mean_difference']:+.3f} ± {c['standard_error']:.3f} against the baseline, "
              f"above on {c['draws_above']} of {len(confirm[winner])} draws")
    report["replaces_baseline"] = replaces
    verdict = (f"{args.baseline} stays" if not leads else f"replaces {args.baseline}" if replaces
               else f"{args.baseline} stays: the confirmation draws " + ("were not led" if args.confirm else "are to come"))
    print(f"winner by the rule: {winner}; {verdict}")
    emit_json(report, args.json)


if __name__ == "__main__":
    main()
