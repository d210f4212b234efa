"""The registered choice between IMU denoisers, computed from one policy's IMU draws behind each.

Usage: ``python bench/select_denoiser.py --baseline B.json[:POLICY] --candidates C1.json C2.json ...
[--confirm-baseline B2.json[:POLICY] --confirm C.json] [--json [OUT]]``

Each file is a ``bench/imu_draws.py --json`` file of one policy tracking validation's IMU draws
behind one denoiser (``FILE:POLICY`` picks the row of a file that holds several policies). All the
files of a step must hold the same draws (seeds, clips, rollouts) of the same policy weights; their
denoisers must differ. The rule registered in the README ("A denoiser for the drift"): the candidate
with the highest mean ELR over the draws leads if that mean is above the baseline's (a tie keeps
the baseline); it replaces the baseline only if it also leads the baseline on the ``--confirm``
draws. Prints each candidate's mean and its paired difference from the baseline (± standard error,
draws above) and the verdict; ``--json`` writes them.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from paired_draws import overlapping_draws, paired
from select_policy import read_draw_file


@dataclass(frozen=True)
class DenoiserDraws:
    """One policy's ELR per draw ``(draws,)`` behind ``denoiser``, with the draws' ``settings``
    ``(seeds, clips, rollouts per clip and draw, style shifts, the actor's label)``: the label names the policy
    and what it tracked (``(mirror-averaged)``, ``+ grounded``, ``+ swing lift ...``), so two files
    compare denoisers only if one actor tracked both."""

    path: str
    denoiser: str
    settings: tuple
    elr: np.ndarray


def read_draws(spec: str) -> DenoiserDraws:
    """``FILE`` or ``FILE:POLICY`` → its draws; a clear error if the file holds several policies and
    none is named, or lacks the named one or a denoiser."""
    path, colon, policy = spec.rpartition(":")
    if not colon or not path.endswith(".json"):  # no policy named (or a colon inside the path itself)
        path, policy = spec, ""
    data = read_draw_file(Path(path))
    rows = [r for r in data["rows"] if not policy or r["policy"] == policy]
    if len(rows) != 1:
        found = [r["policy"] for r in data["rows"]]
        raise SystemExit(f"{path}: holds policies {found}; name exactly one of them once as {path}:POLICY"
                         + (f" ({policy!r} is there {found.count(policy)} times)" if policy else ""))
    if data["denoiser"] is None:
        raise SystemExit(f"{path}: its draws were tracked without a denoiser")
    settings = (tuple(data["seeds_of_first_clip"]), tuple(data["clips"]), data["episodes"], data["style_shifts"],
                rows[0]["policy"])
    return DenoiserDraws(path, str(data["denoiser"]), settings, np.asarray(rows[0]["ELR_per_draw"], dtype=float))


def compare(baseline: DenoiserDraws, candidates: list[DenoiserDraws]) -> list[dict]:
    """Each candidate's mean ELR and paired difference from ``baseline``; raises unless all hold the
    same draws behind different denoisers."""
    for c in candidates:
        if c.settings != baseline.settings:
            raise SystemExit(f"{c.path} and {baseline.path} hold different draws (seeds, clips, rollouts or style "
                             "shifts) or were "
                             f"tracked by different actors ({c.settings[-1]!r}, {baseline.settings[-1]!r})")
    denoisers = [baseline.denoiser] + [c.denoiser for c in candidates]
    if len(set(denoisers)) != len(denoisers):
        raise SystemExit(f"each file must be behind another denoiser, got {denoisers}")
    return [{"denoiser": c.denoiser, "file": c.path, "ELR": float(c.elr.mean()),
             "against_baseline": paired(c.elr, baseline.elr)} for c in candidates]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", required=True, help="the baseline denoiser's draws: FILE[:POLICY]")
    p.add_argument("--candidates", nargs="+", required=True, help="the candidates' draws: FILE[:POLICY] ...")
    p.add_argument("--confirm-baseline", help="the baseline's confirmation draws: FILE[:POLICY]")
    p.add_argument("--confirm", help="the leader's confirmation draws: FILE[:POLICY]")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    if (args.confirm is None) != (args.confirm_baseline is None):
        p.error("--confirm and --confirm-baseline go together")

    baseline = read_draws(args.baseline)
    rows = compare(baseline, [read_draws(s) for s in args.candidates])
    print(f"baseline {baseline.denoiser}: ELR {baseline.elr.mean():.4f} over {len(baseline.elr)} draws")
    for r in rows:
        c = r["against_baseline"]
        print(f"{r['denoiser']:<40} ELR {r['ELR']:.4f} ({c['mean_difference']:+.4f} ± {c['standard_error']:.4f}, "
              f"above on {c['draws_above']} of {len(baseline.elr)})")
    best = max(rows, key=lambda r: r["ELR"])
    leads = best["ELR"] > float(baseline.elr.mean())
    verdict = {"baseline": baseline.denoiser, "rows": rows, "leader": best["denoiser"] if leads else baseline.denoiser,
               "leads_by_rule": leads, "replaces_baseline": False}
    if args.confirm:
        if not leads:
            p.error(f"no candidate leads {baseline.denoiser} by the rule; there is nothing to confirm")
        confirm_baseline = read_draws(args.confirm_baseline)
        if confirm_baseline.denoiser != baseline.denoiser:
            p.error(f"--confirm-baseline is behind {confirm_baseline.denoiser}, --baseline behind {baseline.denoiser}")
        overlap = overlapping_draws(list(baseline.settings[0]), list(confirm_baseline.settings[0]))
        if overlap:
            p.error(overlap)
        confirmation = compare(confirm_baseline, [read_draws(args.confirm)])[0]
        if confirmation["denoiser"] != verdict["leader"]:
            p.error(f"--confirm holds {confirmation['denoiser']}'s draws, but the rule's leader is {verdict['leader']}")
        verdict["confirmation"] = confirmation
        verdict["replaces_baseline"] = confirmation["against_baseline"]["mean_difference"] > 0
        c = confirmation["against_baseline"]
        print(f"confirmation: {confirmation['denoiser']} {c['mean_difference']:+.4f} ± {c['standard_error']:.4f} "
              f"(above on {c['draws_above']} of {c['draws_above'] + c['draws_equal'] + c['draws_below']})")
    if verdict["replaces_baseline"]:
        print(f"verdict: {verdict['leader']} replaces {baseline.denoiser}")
    elif not leads:
        print(f"verdict: {baseline.denoiser} stays")
    elif args.confirm:
        print(f"verdict: {verdict['leader']} leads by the rule but not the confirmation; {baseline.denoiser} stays")
    else:
        print(f"verdict: {verdict['leader']} leads by the rule; confirmation not run yet")
    emit_json(verdict, args.json)


if __name__ == "__main__":
    main()
