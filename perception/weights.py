"""Shipped contact networks: ``DIR/model.pt`` (kind, input points, frame rate, constructor
arguments, weights) with a ``DIR/sidecar.json`` (command, seed, epochs, wall time, metrics), and
loading them with clear errors."""

from __future__ import annotations

import json
import sys
from functools import lru_cache
from pathlib import Path

import torch
from torch import nn

from perception.contact_transformer import ContactTransformer
from perception.imu_denoiser import DenoiserEnsemble, denoiser_network
from perception.vgrf import ContactMLP, VGRFNet

KINDS = {"vgrf": VGRFNet, "mlp": ContactMLP, "keypoints": ContactTransformer, "denoiser": denoiser_network}
"""Network constructors by kind (a denoiser may be one network or an ensemble); each network has
``input_names`` (the points or features it reads, in order) and ``fps``."""
TRAIN_COMMANDS = {"vgrf": "train-vgrf", "mlp": "train-mlp", "keypoints": "train-keypoints",
                  "denoiser": "train-denoiser"}
WEIGHTS_FILE, SIDECAR_FILE = "model.pt", "sidecar.json"


def _write_shipped(out: Path, weights: dict, sidecar: dict) -> Path:
    """Write ``out/model.pt`` (``weights``: kind, joints, fps, network, state_dict, as
    :func:`load_network` reads them) and ``out/sidecar.json``; returns ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    torch.save(weights, out / WEIGHTS_FILE)
    (out / SIDECAR_FILE).write_text(json.dumps(sidecar, indent=1))
    return out


def ship(run_dir: Path, out: Path) -> Path:
    """Copy ``run_dir``'s best weights to ``out/model.pt`` with its sidecar."""
    run_dir = Path(run_dir)
    sidecar = json.loads((run_dir / SIDECAR_FILE).read_text())
    return _write_shipped(out, {"kind": sidecar["kind"], "joints": sidecar["joints"], "fps": sidecar["fps"],
                                "network": sidecar.get("network", {"fps": sidecar["fps"]}),
                                "state_dict": torch.load(run_dir / "best.pt")}, sidecar)


def record_metrics(folder: Path, metrics: dict) -> None:
    """Store ``metrics`` under ``"metrics"`` in the sidecar of the shipped network in ``folder``."""
    path = Path(folder) / SIDECAR_FILE
    sidecar = json.loads(path.read_text()) if path.exists() else {}
    path.write_text(json.dumps({**sidecar, "metrics": metrics}, indent=1))


def read_torch_file(file: Path, what: str, missing_hint: str) -> object:
    """``torch.load`` of ``file`` (a ``what``), or a one-line error naming the file."""
    if not file.exists():
        raise FileNotFoundError(f"{file}: no such {what} ({missing_hint})")
    try:
        return torch.load(file, weights_only=False, map_location="cpu")
    except Exception as err:  # noqa: BLE001 (torch raises many types for a corrupt file)
        raise ValueError(f"{file}: not a readable {what} ({err.__class__.__name__}: {err})") from None


def ship_denoiser_ensemble(folders: list[Path], out: Path, mirror_average: bool = False) -> Path:
    """Ship the shipped IMU denoisers in ``folders`` as one :class:`DenoiserEnsemble` in ``out``
    (``model.pt``; ``sidecar.json`` records the command and each folder and its sidecar). A folder
    that holds an ensemble gives its members (each counts once in the mean); ``mirror_average``
    also averages each member's correction of the take's mirror image (then one member will do)."""
    nets = []
    for folder in folders:
        net = load_network(folder, "denoiser")
        if isinstance(net, DenoiserEnsemble) and net.mirror_average and not mirror_average:
            raise ValueError(f"{folder}: its ensemble averages the mirror images too; ask for that again "
                             "(--mirror-average) or give its members' folders")
        nets.extend(net.members if isinstance(net, DenoiserEnsemble) else [net])
    for i, net in enumerate(nets):
        for other in nets[:i]:
            if all(torch.equal(a, b) for a, b in zip(net.state_dict().values(), other.state_dict().values())):
                raise ValueError("the same IMU denoiser is given twice (a folder and an ensemble holding it?); "
                                 "each member counts once")
    ensemble = DenoiserEnsemble([dict(net.config) for net in nets], mirror_average=mirror_average)
    for member, net in zip(ensemble.members, nets):
        member.load_state_dict(net.state_dict())
    members = [{"folder": str(folder), "sidecar": json.loads((Path(folder) / SIDECAR_FILE).read_text())
                if (Path(folder) / SIDECAR_FILE).exists() else None} for folder in folders]
    return _write_shipped(out, {"kind": "denoiser", "joints": list(ensemble.input_names), "fps": ensemble.fps,
                                "network": ensemble.config, "state_dict": ensemble.state_dict()},
                          {"kind": "denoiser", "ensemble_of": members, "mirror_average": ensemble.mirror_average,
                           "command": "python -m perception " + " ".join(sys.argv[1:])})


def load_network(path: Path, kind: str = "vgrf") -> nn.Module:
    """A shipped network (a directory with ``model.pt``, or the file) in eval mode; a clear
    ``ValueError`` when the file is not one, is another kind, or reads other input points."""
    if kind not in KINDS:
        raise ValueError(f"unknown network kind {kind!r}; expected one of {', '.join(KINDS)}")
    path = Path(path)
    file = path / WEIGHTS_FILE if path.is_dir() else path
    saved = read_torch_file(file, "weights file", f"train one with `python -m perception {TRAIN_COMMANDS[kind]}`")
    if not isinstance(saved, dict) or "state_dict" not in saved:
        raise ValueError(f"{file}: not a physmimic network file (expected a dict with 'kind', 'joints', 'state_dict')")
    if saved.get("kind") != kind:
        raise ValueError(f"{file}: holds a {saved.get('kind')!r} network, expected {kind!r}")
    try:
        net = KINDS[kind](**saved.get("network", {"fps": saved.get("fps", 60.0)}))
    except (TypeError, ValueError) as err:
        raise ValueError(f"{file}: field 'network' does not configure a {KINDS[kind].__name__}: {err}") from None
    joints = tuple(saved.get("joints", ()))
    if joints != tuple(net.input_names):
        raise ValueError(f"{file}: weights are for {len(joints)} input points ({', '.join(joints[:3])}, ...), "
                         f"this network reads {len(net.input_names)} ({', '.join(net.input_names[:3])}, ...)")
    try:
        net.load_state_dict(saved["state_dict"])
    except RuntimeError as err:
        raise ValueError(f"{file}: weights do not fit {KINDS[kind].__name__}: {str(err).splitlines()[0]}") from None
    return net.eval()


@lru_cache(maxsize=8)
def shared_network(path: str, kind: str) -> nn.Module:
    """:func:`load_network` of ``path``, once per process and (path, kind): the environments of a
    process share it."""
    return load_network(Path(path), kind)
