"""The legs' left-right asymmetry: the clean takes' prior that ``--even-legs`` reads, and what evening
does to the leg hinges of IMU takes (``reference_motion/leg_symmetry.py``).

Usage: ``python bench/leg_symmetry.py [--fit library:data/library/train] [--clips library:data/library/val]
[--seeds 690001 690101 690201] [--json [OUT]]``

``--fit``: the mean and spread (degrees) of :func:`leg_asymmetry` over the clean takes given, side by
side with :data:`LIBRARY_ASYMMETRY` (the defaults, fitted on the library's training split). Then, on
the ``--clips`` corrupted at IMU strength 1 with each seed, each leg hinge's RMS error (degrees)
against the clean take with the legs parted (``--part-legs``), and evened then parted
(``--even-legs --part-legs``, the order evaluation prepares raw takes in), side by side.
"""

from __future__ import annotations

import argparse

import numpy as np

from agents.evaluate import reference_clips
from envs.config import MimicConfig
from json_report import emit_json
from reference_motion.leg_gap import part_legs
from reference_motion.leg_symmetry import LEG_HINGES, LIBRARY_ASYMMETRY, even_legs, leg_asymmetry
from reference_motion.humanoid.model import load_model
from reference_motion.transforms import mirror_twin

MODEL = "humanoid_1seg"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--fit", nargs="+", default=["library:data/library/train"], help="clean takes to fit the prior on")
    p.add_argument("--clips", nargs="+", default=["library:data/library/val"], help="takes to corrupt and even")
    p.add_argument("--seeds", type=int, nargs="+", default=[690001, 690101, 690201],
                   help="artefact seeds of the first clip (clip i gets seed + i)")
    p.add_argument("--json", nargs="?", const="-", help="print JSON (or write it to this file)")
    args = p.parse_args()
    config = MimicConfig()
    fitted = np.degrees([leg_asymmetry(c) for c in reference_clips(args.fit, MODEL, config, None, 1.0, 0)])
    defaults = {hinge: (mean, spread) for hinge, mean, spread in LIBRARY_ASYMMETRY}
    prior = {h: {"mean_deg": float(m), "std_deg": float(s), "default": defaults[h]}
             for h, m, s in zip(LEG_HINGES, fitted.mean(axis=0), fitted.std(axis=0))}
    print(f"clean asymmetry over {len(fitted)} takes of {' '.join(args.fit)} (degrees; default in brackets)")
    for h, row in prior.items():
        print(f"  {h:<10} mean {row['mean_deg']:+6.2f} ({row['default'][0]:+6.2f})  std {row['std_deg']:5.2f} "
              f"({row['default'][1]:5.2f})", flush=True)
    model = load_model(MODEL)
    columns = [model.qpos_index(h) for h in LEG_HINGES] + [model.qpos_index(mirror_twin(h)) for h in LEG_HINGES]
    names = list(LEG_HINGES) + [mirror_twin(h) for h in LEG_HINGES]
    clean = reference_clips(args.clips, MODEL, config, None, 1.0, 0)
    given, evened = [], []
    for seed in args.seeds:
        for take, truth in zip(reference_clips(args.clips, MODEL, config, "imu", 1.0, seed), clean):
            for out, motion in ((given, part_legs(take)), (evened, part_legs(even_legs(take)))):
                out.append(np.sqrt(np.mean((motion.qpos[:, columns] - truth.qpos[:, columns]) ** 2, axis=0)))
    given, evened = np.degrees(np.mean(given, axis=0)), np.degrees(np.mean(evened, axis=0))
    print(f"leg hinges' RMS error against the clean take, {len(clean)} takes x {len(args.seeds)} seeds (degrees)")
    for name, a, b in zip(names, given, evened):
        print(f"  {name:<10} as given {a:5.2f}  evened {b:5.2f}")
    print(f"  {'all':<10} as given {given.mean():5.2f}  evened {evened.mean():5.2f}")
    emit_json({"fit": args.fit, "clips": args.clips, "seeds": args.seeds, "prior": prior,
               "rms_error_deg": {n: {"given": float(a), "evened": float(b)} for n, a, b in zip(names, given, evened)},
               "rms_error_deg_mean": {"given": float(given.mean()), "evened": float(evened.mean())}}, args.json)


if __name__ == "__main__":
    main()
