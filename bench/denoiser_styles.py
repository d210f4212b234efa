"""Does the IMU denoiser carry to a style it never saw? A leave-one-style-out measurement.

Usage: ``python bench/denoiser_styles.py --denoisers no_sad=runs/loso/no_sad/shipped
no_chimpira=runs/loso/no_chimpira/shipped --styles sad chimpira [--draws 10] [--json [OUT]]``

Each denoiser was trained like the others but with the takes of one style of the library's train
split left out (``python -m perception train-denoiser --clips`` without them). Every take of each
``--styles`` style (Bandai Namco takes named ``*_STYLE_*`` in ``library:LIBRARY/train``) is
corrupted with every IMU artefact kind at ``--strength`` on ``--draws`` seeds (``--seed`` + 100·take
+ draw), and passed clean too; each denoiser corrects it. Reported per denoiser and style, against
the clean take, as :mod:`bench.imu_denoiser` reports them: the RMS error of the hinge angles (deg),
the mean pelvis height error (cm), the hip adduction offset (deg) and the RMS error of the sole
points relative to the pelvis (cm). A denoiser that left a style out reads it as an unseen style
(the test split's old, tired and giant are unseen to every shipped denoiser); the others read it as
a trained one, so "unseen − seen" on one style, same takes and draws, is what leaving it out cost.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from imu_denoiser import errors, pooled, soles  # bench/imu_denoiser.py: the scripts run from bench/
from json_report import emit_json
from perception.imu_denoiser import denoise
from perception.weights import load_network
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion

METRICS = ("hinge_rms_deg", "height_cm", "hip_offset_deg", "sole_rms_cm")


def labelled(text: str) -> tuple[str, Path]:
    """``LABEL=DIR`` → ``(LABEL, DIR)``."""
    label, sep, path = text.partition("=")
    if not sep or not label or not path:
        raise argparse.ArgumentTypeError(f"expected LABEL=DIR, got {text!r}")
    return label, Path(path)


def style_clips(library: str, style: str) -> list[str]:
    """The train split's takes of ``style`` (SOURCE strings); a clear error when there are none."""
    clips = [s for s in expand_clips([f"library:{library}/train"]) if f"_{style}_" in s]
    if not clips:
        raise SystemExit(f"no take of style {style!r} in library:{library}/train")
    return clips


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--denoisers", type=labelled, nargs="+", required=True, metavar="LABEL=DIR")
    p.add_argument("--styles", nargs="+", required=True)
    p.add_argument("--library", default="data/library")
    p.add_argument("--strength", type=float, default=1.0)
    p.add_argument("--draws", type=int, default=10, help="artefact seeds per take")
    p.add_argument("--seed", type=int, default=680_000, help="artefact seed of draw 0 of take 0")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args(argv)
    nets = {label: load_network(path, "denoiser") for label, path in args.denoisers}
    model = next(iter(nets.values())).model
    hm = load_model(model)
    hips = [hm.qpos_index("l_thigh_x"), hm.qpos_index("r_thigh_x")]
    table: dict[str, dict] = {}
    print(f"{'style':<15}{'kind':<7}{'denoiser':<14}" + "".join(f"{m:>16}" for m in METRICS))
    for style in args.styles:
        takes = [load_motion(s, model) for s in style_clips(args.library, style)]
        take_soles = [soles(clean) for clean in takes]
        for kind, draws in (("clean", 1), ("imu", args.draws)):
            given = [(clean, clean_soles, clean if kind == "clean" else
                      corrupt(clean, ArtefactRecipe.imu(args.strength), args.seed + 100 * i + d))
                     for i, (clean, clean_soles) in enumerate(zip(takes, take_soles)) for d in range(draws)]
            rows = {"input": [errors(clean, s, g, hips) for clean, s, g in given]}
            rows |= {label: [errors(clean, s, denoise(net, g), hips) for clean, s, g in given]
                     for label, net in nets.items()}
            for label, r in rows.items():
                table[f"{style}/{kind}/{label}"] = {"takes": len(takes), "draws": draws,
                                                    **{m: pooled(r, m) for m in METRICS}}
                print(f"{style:<15}{kind:<7}{label:<14}" + "".join(f"{pooled(r, m):>16.3f}" for m in METRICS))
    result = {"denoisers": {label: str(path) for label, path in args.denoisers}, "styles": args.styles,
              "strength": args.strength, "draws": args.draws, "seed": args.seed, "table": table}
    emit_json(result, args.json)
    return result


if __name__ == "__main__":
    main()
