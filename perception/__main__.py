"""Command line: ``python -m perception COMMAND ...``.

Examples::

    python -m perception train-vgrf --dataset data/physics --run-dir runs/vgrf --out models/vgrf
    python -m perception train-mlp --dataset data/physics --run-dir runs/contact_mlp --out models/contact_mlp
    python -m perception evaluate-contacts --dataset data/physics --split test --json out/contacts.json
    python -m perception train-keypoints --dataset data/physics --run-dir runs/contact_transformer
    python -m perception train-denoiser --run-dir runs/imu_denoiser --out models/imu_denoiser
    python -m perception ensemble-denoisers models/imu_denoiser_soles runs/denoiser_soles_s1/shipped --out DIR
    python -m perception ensemble-denoisers models/imu_denoiser_soles_trio --mirror-average --out DIR
    python -m perception evaluate-keypoints --dataset data/physics --split test --json out/keypoints.json
    python -m perception contacts deepmimic:walk --plot out/walk_contacts.png --json out/walk_contacts.json
    python -m perception cleanup deepmimic:walker/turn_left1 --corrupt imu --out out/turn_left1_clean.npz
    python -m perception gait walk.mp4 --json out/gait.json --plot out/gait.png
"""

from __future__ import annotations

import argparse
from functools import partial
from pathlib import Path

import numpy as np

from tqdm import tqdm

from perception.cleanup import CleanupConfig, cleanup
from perception.contacts import CONTACT_NAMES, ContactFunction
from perception.dataset import SPLITS, load_split
from perception.denoiser_training import DENOISER_TRAIN_CLIPS, DENOISER_VAL_CLIPS, DenoiserTrainConfig, train_denoiser
from perception.contact_transformer import detect_contacts
from perception.evaluation import ContactModels, evaluate_contacts, fit_ot
from perception.gait import gait_report
from perception.keypoint_data import load_keypoint_split, held_out_views
from perception.keypoint_evaluation import GAIT_RATIOS, evaluate_keypoint_contacts, film_split
from perception.keypoint_training import SAMPLINGS, KeypointTrainConfig, train_keypoints
from perception.keypoints import KEYPOINT_SETS
from perception.plots import PLOT_SUFFIXES, plot_cleanup, plot_contacts, plot_gait, plot_tolerance_curves
from perception.skeleton import motion_joint_positions
from perception.training import TrainConfig, train
from perception.underpressure_data import load_underpressure
from perception.vgrf import estimate
from perception.video import VIDEO_SUFFIXES, video_keypoints
from perception.weights import load_network, record_metrics, ship, ship_denoiser_ensemble
from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.atomic import atomic_write, write_json
from reference_motion.bvh_export import write_bvh
from reference_motion.cli import (CliParser, add_mocap_options, fraction, mocap_options, non_negative_float,
                                  non_negative_int, one_line_errors, output_dir, output_file, positive_float,
                                  positive_int)
from reference_motion.library import check_stance_extra, load_motion
from reference_motion.motion import Motion, read_npz

JSON_OUT = output_file(".json")
PLOT_OUT = output_file(*PLOT_SUFFIXES)


def _add_source(p: argparse.ArgumentParser) -> None:
    p.add_argument("source", help="deepmimic:NAME, library:DIR#TAKE, a .npz Motion, a .bvh / .amc file, or an "
                                  "UnderPressure .pth sequence")
    add_mocap_options(p)
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS, help="add synthetic IMU artefacts first")
    p.add_argument("--strength", type=non_negative_float, default=1.0, help="artefact strength")
    p.add_argument("--seed", type=int, default=1000, help="artefact seed")
    p.add_argument("--min-frames", type=non_negative_int, default=0,
                   help="loop a cyclic clip to at least this many frames")


def build_parser(prog: str = "python -m perception") -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0],
                  formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    for name, kind, default_out in (("train-vgrf", "vgrf", "models/vgrf"), ("train-mlp", "mlp", "models/contact_mlp")):
        t = TrainConfig(kind=kind)
        g = sub.add_parser(name, help=f"train the {'vGRF network' if kind == 'vgrf' else '3-layer MLP baseline'}",
                           formatter_class=argparse.ArgumentDefaultsHelpFormatter)
        g.add_argument("--dataset", type=Path, required=True)
        g.add_argument("--run-dir", type=output_dir, required=True, help="checkpoints (resumes if it exists)")
        g.add_argument("--out", type=output_dir, default=Path(default_out), help="where the best weights are shipped")
        g.add_argument("--epochs", type=positive_int, default=t.max_epochs, help="most epochs")
        g.add_argument("--patience", type=non_negative_int, default=t.patience, help="early-stopping patience (epochs)")
        g.add_argument("--lr", type=positive_float, default=t.lr, help="initial Adam learning rate")
        g.add_argument("--lr-patience", type=non_negative_int, default=t.lr_patience,
                       help="halve the learning rate after this many epochs without improvement")
        g.add_argument("--seed", type=int, default=t.seed)
        g.add_argument("--no-augment", action="store_true", help="train without UnderPressure's augmentations")
        g.add_argument("--no-progress", action="store_true")
        g.set_defaults(kind=kind)
    d = DenoiserTrainConfig()
    g = sub.add_parser("train-denoiser", help="train the IMU denoiser on library takes it corrupts itself",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g.add_argument("--clips", nargs="+", default=list(DENOISER_TRAIN_CLIPS),
                   help="training clips: SOURCE strings or clip sets")
    g.add_argument("--val-clips", nargs="+", default=list(DENOISER_VAL_CLIPS),
                   help="validation clips (early stopping, the shipped epoch)")
    g.add_argument("--run-dir", type=output_dir, required=True, help="checkpoints (resumes if it exists)")
    g.add_argument("--out", type=output_dir, default=Path("models/imu_denoiser"), help="where the best weights are shipped")
    g.add_argument("--epochs", type=positive_int, default=d.max_epochs, help="most epochs")
    g.add_argument("--patience", type=non_negative_int, default=d.patience, help="early-stopping patience (epochs)")
    g.add_argument("--windows-per-epoch", type=positive_int, default=d.windows_per_epoch)
    g.add_argument("--hidden", type=positive_int, default=d.hidden,
                   help="channels of every layer of the network (DenoiserTrainConfig.hidden)")
    g.add_argument("--dilations", type=positive_int, nargs="+", default=list(d.dilations),
                   help="dilation of each residual convolution (DenoiserTrainConfig.dilations)")
    g.add_argument("--window", type=positive_int, default=d.window,
                   help="longest training window, frames (DenoiserTrainConfig.window)")
    g.add_argument("--sole-weight", type=non_negative_float, default=d.sole_weight,
                   help="weight of the sole points' error relative to the pelvis in the loss "
                        "(DenoiserTrainConfig.sole_weight)")
    g.add_argument("--height-weight", type=non_negative_float, default=d.height_weight,
                   help="weight of the pelvis height's error (m²) in the loss, beside its share as one channel "
                        "(DenoiserTrainConfig.height_weight)")
    g.add_argument("--strength", type=non_negative_float, nargs=2, default=list(d.strength), metavar=("LOW", "HIGH"),
                   help="uniform artefact strength of a corrupted training window (DenoiserTrainConfig.strength)")
    g.add_argument("--clean-fraction", type=fraction, default=d.clean_fraction,
                   help="share of training windows left clean (DenoiserTrainConfig.clean_fraction)")
    g.add_argument("--speeds", type=positive_float, nargs="+", default=list(d.speeds), metavar="S",
                   help="train on every take played at each of these speeds (1.0 = as recorded: include it to "
                        "keep the takes as they are; DenoiserTrainConfig.speeds)")
    g.add_argument("--postures", type=non_negative_int, default=d.postures, metavar="N",
                   help="also train on N copies of every take carried with a random posture "
                        "(DenoiserTrainConfig.postures)")
    g.add_argument("--stances", type=non_negative_int, default=d.stances, metavar="N",
                   help="also train on N copies of every take walked with the feet further apart "
                        "(DenoiserTrainConfig.stances)")
    g.add_argument("--stance-extra", type=float, nargs=2, default=list(d.stance_extra_m), metavar=("LOW", "HIGH"),
                   help="range of the stance copies' extra width, m (DenoiserTrainConfig.stance_extra_m)")
    g.add_argument("--seed", type=int, default=d.seed)
    g.add_argument("--no-progress", action="store_true")
    g = sub.add_parser("ensemble-denoisers", help="ship shipped IMU denoisers as one that averages their corrections",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g.add_argument("members", nargs="+", type=Path,
                   help="shipped IMU denoiser folders (two or more, or one with --mirror-average); an ensemble's "
                        "folder gives its members")
    g.add_argument("--mirror-average", action="store_true",
                   help="also average each member's correction of the take's mirror image, mirrored back")
    g.add_argument("--out", type=output_dir, required=True, help="where the ensemble is shipped")
    k = KeypointTrainConfig()
    g = sub.add_parser("train-keypoints", help="train the ContactTransformer on filmed physics data (ContactVision)",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g.add_argument("--dataset", type=Path, required=True)
    g.add_argument("--run-dir", type=output_dir, required=True, help="checkpoints (resumes if it exists)")
    g.add_argument("--out", type=output_dir, default=Path("models/contact_transformer"),
                   help="where the best weights are shipped")
    g.add_argument("--keypoints", choices=tuple(KEYPOINT_SETS), default=k.keypoints,
                   help="lower body (13, ContactVision) or full body (25; ablation)")
    g.add_argument("--positional", choices=("learnable", "sinusoidal"), default=k.positional)
    g.add_argument("--sampling", choices=SAMPLINGS, default=k.sampling,
                   help="random subsequences (ContactVision) or stride-1 sliding windows (ablation)")
    g.add_argument("--epochs", type=positive_int, default=k.max_epochs, help="most epochs")
    g.add_argument("--patience", type=non_negative_int, default=k.patience, help="early-stopping patience (epochs)")
    g.add_argument("--lr", type=positive_float, default=k.lr, help="Adam learning rate")
    g.add_argument("--windows-per-epoch", type=positive_int, default=k.windows_per_epoch)
    g.add_argument("--init-from", help="a shipped ContactTransformer to fine-tune instead of starting from scratch")
    g.add_argument("--seed", type=int, default=k.seed)
    g.add_argument("--no-progress", action="store_true")
    g = sub.add_parser("evaluate-keypoints", help="contact F1 and gait-ratio errors of the ContactTransformer on "
                       "views never used in training", formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g.add_argument("--dataset", type=Path, required=True)
    g.add_argument("--split", choices=SPLITS, default="test")
    g.add_argument("--net", type=Path, default=Path("models/contact_transformer"))
    g.add_argument("--views", choices=("rig", "handheld"), nargs="+", default=["rig", "handheld"],
                   help="static test cameras and/or hand-held ones, at the test azimuths")
    g.add_argument("--seed", type=int, default=0, help="detector noise seed")
    g.add_argument("--json", type=JSON_OUT)
    g.add_argument("--record", action="store_true", help="also store the scores as 'metrics' in the net's sidecar.json")
    g = sub.add_parser("evaluate-contacts", help="F1 of VGRFNet+Γ, OT and MLP; vGRF RMSE",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g.add_argument("--dataset", type=Path, required=True)
    g.add_argument("--split", choices=SPLITS, default="test")
    g.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    g.add_argument("--mlp", type=Path, default=Path("models/contact_mlp"))
    g.add_argument("--json", type=JSON_OUT)
    g.add_argument("--plot", type=PLOT_OUT, help="PNG: F1 against temporal tolerance (underpressure Fig. 4)")
    g.add_argument("--record", action="store_true",
                   help="also store each network's scores as 'metrics' in its sidecar.json (when shipping)")
    g = sub.add_parser("contacts", help="per-frame vGRF per foot and the four contacts of a clip",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    _add_source(g)
    g.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    g.add_argument("--json", type=JSON_OUT)
    g.add_argument("--plot", type=PLOT_OUT, help="PNG: vGRF curves with contact bands")
    g = sub.add_parser("gait", help="per-frame contacts, gait phases and parameters, and a timeline plot",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g.add_argument("source", help="a video (MediaPipe, `video` extra), a keypoint .npz (fields keypoints (T, 13, 3) "
                   "= pixels and confidence, fps), or a 3D motion (deepmimic:NAME, Motion .npz, .bvh; contacts "
                   "from VGRFNet + Γ)")
    g.add_argument("--net", type=Path, default=Path("models/contact_transformer"), help="keypoint contact network")
    g.add_argument("--vgrf", type=Path, default=Path("models/vgrf"), help="vGRF network for 3D motions")
    g.add_argument("--keypoints-out", type=output_file(".npz"),
                   help="also save a video's keypoints (.npz) for later runs")
    add_mocap_options(g)
    g.add_argument("--json", type=JSON_OUT)
    g.add_argument("--plot", type=PLOT_OUT, help="PNG timeline: contacts, gait phases, toe reference angles")
    g = sub.add_parser("cleanup", help="remove foot skate with the vGRF network (UnderPressure §6)",
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    _add_source(g)
    g.add_argument("--out", type=output_file(".npz"), required=True, help="the cleaned Motion (.npz)")
    g.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    g.add_argument("--iterations", type=positive_int, default=CleanupConfig().iterations)
    g.add_argument("--pose-weight", type=non_negative_float, default=CleanupConfig().w_pose,
                   help="how hard the joints are kept near the input: lower removes more skate and moves the "
                        "body more (0: not kept; the body follows the planted feet)")
    g.add_argument("--json", type=JSON_OUT)
    g.add_argument("--plot", type=PLOT_OUT, help="PNG: heel and toe speeds before and after, over the contacts")
    g.add_argument("--bvh", type=output_file(".bvh"), help="also write the cleaned clip as BVH")
    return p


def motion_of(args: argparse.Namespace) -> Motion:
    """The ``source`` argument as a Motion, corrupted when ``--corrupt`` is given."""
    motion = load_motion(args.source, min_frames=args.min_frames, mocap=mocap_options(args))
    if args.corrupt:
        motion = corrupt(motion, ArtefactRecipe.named(args.corrupt, args.strength), args.seed)
    return motion


def positions_of(args: argparse.Namespace) -> tuple[np.ndarray, float, str]:
    """Joint positions ``(T, 23, 3)``, frame rate and name of the ``source`` argument."""
    if str(args.source).endswith(".pth"):
        seq = load_underpressure(args.source)
        return seq.positions, seq.fps, seq.clip
    motion = motion_of(args)
    return motion_joint_positions(motion), motion.fps, motion.name


SCORE_LABELS = {"vgrf": "VGRFNet + Γ", "ot": "OT baseline", "mlp": "3-layer MLP"}


def _print_scores(result: dict) -> None:
    print(f"{result['frames']} frames, {result['sequences']} sequences")
    print(f"  {'model':<14}" + "".join(f"{c:>12}" for c in CONTACT_NAMES) + f"{'overall':>10}")
    for key, label in SCORE_LABELS.items():
        if key in result:
            print(f"  {label:<14}" + "".join(f"{result[key][c]['f1']:>12.3f}" for c in CONTACT_NAMES)
                  + f"{result[key]['overall']['f1']:>10.3f}")
    if "vgrf_rmse_percent_bw" in result:
        print(f"  vGRF RMSE (per-foot total): {result['vgrf_rmse_percent_bw']:.1f}% body weight")
    print("  overall F1 forgiving errors within t s of a true contact change (underpressure Fig. 4):")
    for key, curve in result["f1_by_tolerance_s"].items():
        print(f"  {SCORE_LABELS[key]:<14}" + "".join(f"  t={t}: {f1:.3f}" for t, f1 in curve.items()))


def keypoint_file(path: Path) -> tuple[np.ndarray, float] | None:
    """``(keypoints, fps)`` of a keypoint ``.npz``; ``None`` when ``path`` is another kind of file
    (a Motion ``.npz`` among them)."""
    if Path(path).suffix != ".npz" or not Path(path).exists():
        return None
    z = read_npz(path, "keypoint or motion")
    if "keypoints" not in z:
        return None
    if "fps" not in z:
        raise ValueError(f"{path}: keypoint file has no field 'fps'")
    return z["keypoints"], float(z["fps"])


def source_contacts(args: argparse.Namespace) -> tuple[np.ndarray, float, str]:
    """Contacts ``(T, 4)``, frame rate, and how they were found, for the ``gait`` command's source."""
    keypoints = keypoint_file(args.source)
    if keypoints is None and Path(args.source).suffix.lower() in VIDEO_SUFFIXES:
        keypoints = video_keypoints(args.source, progress=True)
        if args.keypoints_out:
            with atomic_write(args.keypoints_out) as tmp:
                np.savez(tmp, keypoints=keypoints[0], fps=keypoints[1])
    if keypoints is not None:
        net = load_network(args.net, "keypoints")
        return detect_contacts(net, *keypoints), keypoints[1], f"keypoints ({args.net})"
    motion = load_motion(args.source, mocap=mocap_options(args))
    forces = estimate(load_network(args.vgrf, "vgrf"), motion_joint_positions(motion))
    return ContactFunction()(forces, motion.fps), motion.fps, f"VGRFNet + Γ ({args.vgrf})"


def _print_keypoint_scores(kind: str, result: dict) -> None:
    overall = result["scores"]["overall"]
    print(f"{kind} views: {result['frames']} frames in {result['sequences']} filmed sequences: precision "
          f"{overall['precision']:.3f}, recall {overall['recall']:.3f}, F1 {overall['f1']:.3f}")
    print("  F1 per channel: " + ", ".join(f"{c} {result['scores'][c]['f1']:.3f}" for c in CONTACT_NAMES))
    print("  F1 forgiving errors within t s of a true contact change: "
          + ", ".join(f"t={t}: {f1:.3f}" for t, f1 in result["f1_by_tolerance_s"].items()))
    for scope, what in (("cycle", "gait cycles"), ("sequence", "sequences")):
        gait = result["gait"][scope]
        print(f"  gait-ratio MAE per {scope} (pp): " + ", ".join(f"{g} {gait[f'{g}_mae_pp']:.1f}" for g in GAIT_RATIOS)
              + f" over {gait['count']} {what}")


def _train_and_ship(args: argparse.Namespace, trainer, config, describe) -> dict:
    """Run ``trainer(run_dir, config, progress=...)``, ship the best epoch to ``--out`` and say so;
    ``describe(best_val)`` words the validation score."""
    sidecar = trainer(args.run_dir, config, progress=not args.no_progress)
    ship(args.run_dir, args.out)
    print(f"best epoch {sidecar['best_epoch']} of {sidecar['epochs']} ({describe(sidecar['best_val'])}, "
          f"{sidecar['wall_s']:.0f} s); shipped to {args.out}")
    return sidecar


@one_line_errors
def main(argv: list[str] | None = None, prog: str = "python -m perception") -> dict | None:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the command's result."""
    args = build_parser(prog).parse_args(argv)
    if args.command == "train-keypoints":
        config = KeypointTrainConfig(keypoints=args.keypoints, positional=args.positional, sampling=args.sampling,
                                     max_epochs=args.epochs, patience=args.patience, lr=args.lr,
                                     windows_per_epoch=args.windows_per_epoch, init_from=args.init_from,
                                     seed=args.seed)
        return _train_and_ship(args, partial(train_keypoints, args.dataset), config, lambda best: f"val F1 {1 - best:.3f}")
    if args.command == "evaluate-keypoints":
        net = load_network(args.net, "keypoints")
        sequences = load_keypoint_split(args.dataset, args.split)
        result = {"split": args.split, "net": str(args.net)}
        for kind in args.views:
            filmed = film_split(sequences, held_out_views(kind=kind), net.config["keypoints"], args.seed, test=True)
            result[kind] = evaluate_keypoint_contacts(net, filmed, progress=True)
            _print_keypoint_scores(kind, result[kind])
        if args.json:
            write_json(args.json, result)
        if args.record:
            record_metrics(args.net, result)
        return result
    if args.command == "train-denoiser":
        config = DenoiserTrainConfig(max_epochs=args.epochs, patience=args.patience,
                                     windows_per_epoch=args.windows_per_epoch, hidden=args.hidden,
                                     dilations=tuple(args.dilations), window=args.window,
                                     sole_weight=args.sole_weight, height_weight=args.height_weight,
                                     strength=tuple(args.strength),
                                     clean_fraction=args.clean_fraction,
                                     speeds=tuple(args.speeds), postures=args.postures, stances=args.stances,
                                     stance_extra_m=check_stance_extra(args.stance_extra, "--stance-extra"),
                                     seed=args.seed)
        trainer = partial(train_denoiser, args.clips, args.val_clips)
        return _train_and_ship(args, trainer, config, lambda best: f"val root of the loss {np.sqrt(best):.4f}")
    if args.command == "ensemble-denoisers":
        out = ship_denoiser_ensemble(args.members, args.out, mirror_average=args.mirror_average)
        print(f"an ensemble of {len(load_network(out, 'denoiser').members)} IMU denoisers"
              f"{' averaged with their mirror images' if args.mirror_average else ''} shipped to {out}")
        return {"out": str(out), "members": [str(m) for m in args.members]}
    if args.command in ("train-vgrf", "train-mlp"):
        config = TrainConfig(kind=args.kind, max_epochs=args.epochs, patience=args.patience, lr=args.lr,
                             lr_patience=args.lr_patience,
                             seed=args.seed, augment=not args.no_augment)
        return _train_and_ship(args, partial(train, args.dataset), config, lambda best: f"val loss {best:.5f}")
    if args.command == "evaluate-contacts":
        models = ContactModels(vgrf=load_network(args.vgrf, "vgrf"), ot=fit_ot(load_split(args.dataset, "train")),
                               mlp=load_network(args.mlp, "mlp") if Path(args.mlp).exists() else None)
        result = evaluate_contacts(load_split(args.dataset, args.split), models)
        result = {"split": args.split, "dataset": str(args.dataset),
                  "ot_thresholds": {"height_m": models.ot.height_m, "speed_mps": models.ot.speed_mps}, **result}
        _print_scores(result)
        if args.json:
            write_json(args.json, result)
        if args.plot:
            curves = {SCORE_LABELS[key]: curve for key, curve in result["f1_by_tolerance_s"].items()}
            plot_tolerance_curves(args.plot, curves, f"contacts on the {args.split} split: F1 against tolerance")
        if args.record:
            for key, folder in (("vgrf", args.vgrf), ("mlp", args.mlp)):
                if key in result:
                    metrics = {"split": args.split, "dataset": str(args.dataset), "frames": result["frames"],
                               "f1": {c: v["f1"] for c, v in result[key].items()}}
                    if key == "vgrf":
                        metrics["vgrf_rmse_percent_bw"] = result["vgrf_rmse_percent_bw"]
                    record_metrics(folder, metrics)
        return result
    if args.command == "contacts":
        positions, fps, name = positions_of(args)
        forces = estimate(load_network(args.vgrf, "vgrf"), positions)
        contacts = ContactFunction()(forces, fps)
        totals = forces.sum(-1)
        print(f"{name}: {len(positions)} frames at {fps:g} Hz; contact share " + ", ".join(
            f"{c} {contacts[:, i].mean():.0%}" for i, c in enumerate(CONTACT_NAMES))
            + f"; mean vGRF left {totals[:, 0].mean():.2f} right {totals[:, 1].mean():.2f} BW")
        result = {"source": str(args.source), "fps": fps, "channels": list(CONTACT_NAMES),
                  "vgrf_bw": totals.round(4).tolist(), "contacts": contacts.astype(int).tolist()}
        if args.json:
            write_json(args.json, result)
        if args.plot:
            plot_contacts(args.plot, forces, contacts, fps, f"{name}: estimated vGRF and contacts")
        return result
    if args.command == "gait":
        contacts, fps, method = source_contacts(args)
        report = {"source": str(args.source), "contacts_from": method, "channels": list(CONTACT_NAMES),
                  "contacts": contacts.astype(int).tolist(), **gait_report(contacts, fps)}
        p = report["parameters"]
        print(f"{args.source}: {len(contacts)} frames at {fps:g} Hz, contacts from {method}")
        print(f"  stance {p['stance']:.1%}, swing {p['swing']:.1%}, single support {p['single_support']:.1%}, "
              f"double support {p['double_support']:.1%} ({p['valid_frames']} gait frames, "
              f"{len(report['cycles'])} complete cycles)")
        if args.json:
            write_json(args.json, report)
        if args.plot:
            plot_gait(args.plot, contacts, fps, f"{Path(str(args.source)).name}: gait from {method.split(' (')[0]}")
        return report
    if args.command == "cleanup":
        if str(args.source).endswith(".pth"):
            raise ValueError(f"{args.source}: cleanup edits a Motion (joint angles); UnderPressure sequences are "
                             "read as joint positions only")
        config = CleanupConfig(iterations=args.iterations, w_pose=args.pose_weight)
        motion = motion_of(args)
        with tqdm(desc=f"cleaning {motion.name}", unit="evaluation") as bar:
            result = cleanup(motion, load_network(args.vgrf, "vgrf"), config,
                             progress=lambda it, loss: (bar.update(1),
                                                        bar.set_postfix(loss=f"{loss:.4f}", refresh=False)))
        result.motion.save(args.out)
        reduction = 1 - result.foot_speed_after / result.foot_speed_before if result.foot_speed_before else 0.0
        print(f"contact foot speed {result.foot_speed_before:.3f} -> {result.foot_speed_after:.3f} m/s "
              f"({reduction:.0%} less); joints moved {100 * result.joint_shift_m:.1f} cm on average; "
              f"written {args.out}")
        if args.bvh:
            print(f"wrote {write_bvh(result.motion, args.bvh)}")
        if args.plot:
            plot_cleanup(args.plot, result.soles_before, result.soles_after, result.contacts, motion.fps,
                         f"{motion.name}: foot speed before and after cleanup")
        summary = {"source": str(args.source), "corrupt": args.corrupt, "strength": args.strength if args.corrupt else 0,
                   "foot_speed_before_mps": result.foot_speed_before, "foot_speed_after_mps": result.foot_speed_after,
                   "reduction": reduction, "joint_shift_m": result.joint_shift_m, "out": str(args.out)}
        if args.json:
            write_json(args.json, summary)
        return summary
    raise AssertionError(args.command)


if __name__ == "__main__":
    main()
