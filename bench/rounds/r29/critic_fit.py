"""Round 29: how well each run's critic explains the returns it is trained on, PV (asymmetric critic) against PC
(round 27: PPO from WW with WW's settings and its own critic), from their TensorBoard logs: SB3's explained
variance of the value targets and the value loss, averaged over windows of steps.

Usage: python bench/rounds/r29/critic_fit.py [RUN=DIR ...]  (default: PV=runs/r29/ppo_pv PC=runs/r27/ppo_pc)
"""

import sys
from pathlib import Path

import numpy as np
from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

WINDOW = 250_000


def scalars(run: Path, tag: str) -> tuple[np.ndarray, np.ndarray]:
    events = sorted((run / "tb").glob("*/events*"))
    steps, values = [], []
    for f in events:
        acc = EventAccumulator(str(f))
        acc.Reload()
        for e in acc.Scalars(tag):
            steps.append(e.step)
            values.append(e.value)
    return np.asarray(steps), np.asarray(values)


def main() -> None:
    runs = dict(a.split("=", 1) for a in sys.argv[1:]) or {"PV": "runs/r29/ppo_pv", "PC": "runs/r27/ppo_pc"}
    for tag in ("train/explained_variance", "train/value_loss"):
        print(tag)
        for name, run in runs.items():
            steps, values = scalars(Path(run), tag)
            cells = []
            for start in range(0, int(steps.max()) + 1, WINDOW):
                inside = (steps > start) & (steps <= start + WINDOW)
                if inside.any():
                    cells.append(f"{start / 1e6:.2f}-{(start + WINDOW) / 1e6:.2f} M: {values[inside].mean():.3f}")
            print(f"  {name}: " + "; ".join(cells))


if __name__ == "__main__":
    main()
