"""How much a run warm-started onto wider hidden layers reads its new units, checkpoint by checkpoint.

Usage: ``python bench/widened_units.py --run-dir runs/general_wide [--old 256] [--json [OUT]]``

``train_ppo.py --init-from POLICY --net 512,512`` (``agents/warm_start.py``) embeds a 256-unit
policy in the wider network with zero weights from every new unit into an old unit or an output,
so the run starts as the source; the new units contribute only once training grows those weights.
For each checkpoint of the run this prints the Frobenius norm of the weights that read the new units
(columns ``old:`` of the action head, the value head and the second hidden layer's old rows)
beside that of the weights reading the old ones (columns ``:old``).
"""

from __future__ import annotations

import argparse
import io
import re
import zipfile
from pathlib import Path

import torch

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/

HEADS = {"action head": "action_net.weight", "value head": "value_net.weight",
         "actor layer 2": "mlp_extractor.policy_net.2.weight"}
"""Weights that may read new units: the two heads, and the second hidden layer (its old units' rows)."""


def unit_norms(state: dict[str, torch.Tensor], old: int) -> dict[str, dict[str, float]]:
    """``{head: {"old": norm, "new": norm}}``: norms of the columns reading the first ``old`` units
    and the rest, for the rows of outputs and old units only."""
    out = {}
    for label, name in HEADS.items():
        weight = state[name][:old] if name.startswith("mlp_extractor") else state[name]
        out[label] = {"old": float(weight[:, :old].norm()), "new": float(weight[:, old:].norm())}
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--run-dir", type=Path, required=True)
    p.add_argument("--old", type=int, default=256, help="hidden units of the source policy")
    p.add_argument("--json", nargs="?", const="-", default=None, help="write the results as JSON (to OUT, or print)")
    args = p.parse_args()
    step = re.compile(r"step_(\d+)\.zip$")
    checkpoints = sorted(((int(step.search(c.name).group(1)), c) for c in (args.run_dir / "checkpoints").glob("step_*.zip")
                          if step.search(c.name)))
    if not checkpoints:
        raise SystemExit(f"error: {args.run_dir / 'checkpoints'}: no step_*.zip checkpoint")
    rows = []
    print(f"{'steps':>10}" + "".join(f"{label + ' (old / new)':>28}" for label in HEADS))
    for steps, path in checkpoints:
        with zipfile.ZipFile(path) as archive:
            state = torch.load(io.BytesIO(archive.read("policy.pth")), map_location="cpu")
        norms = unit_norms(state, args.old)
        rows.append({"steps": steps, **norms})
        print(f"{steps:>10}" + "".join(f"{n['old']:>18.3f} / {n['new']:<7.3f}" for n in norms.values()))
    emit_json({"run_dir": str(args.run_dir), "old_units": args.old, "checkpoints": rows}, args.json)


if __name__ == "__main__":
    main()
