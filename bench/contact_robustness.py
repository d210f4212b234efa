"""Contact detection under perturbed input, as UnderPressure Figs. 6 and 8: VGRFNet + Γ against the
OT baseline on the test split.

Usage: ``python bench/contact_robustness.py --dataset data/physics [--vgrf models/vgrf] [--json [OUT]]``

* Noise (Fig. 6): isotropic Gaussian noise on every joint and frame; the x axis is the measured
  MPJPE (cm). Reported: F1 per noise level and the F1 drop at 5 cm MPJPE (interpolated).
* Footskate by blending (Fig. 8): pairs of 80-frame test windows (1.33 s) whose contact labels of
  one foot agree on ≥ 90% of frames are blended, B aligned to A's pelvis position and heading at
  the first frame, with a weight that drifts smoothly between 0 and ``w_max``; F1 is computed on
  that foot's channels over the frames where both windows agree, against the amount of foot
  skate introduced (mean horizontal speed of the foot joints during contact).

Plots go to ``bench/results/contact_noise.png`` and ``bench/results/contact_footskate.png``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from json_report import emit_json  # noqa: E402  (bench/json_report.py: the scripts run from bench/)
from perception.contacts import ContactFunction, detection_scores, foot_height_speed  # noqa: E402
from perception.dataset import load_split  # noqa: E402
from perception.evaluation import ContactModels, evaluate_contacts, fit_ot  # noqa: E402
from perception.skeleton import JOINTS  # noqa: E402
from perception.weights import load_network  # noqa: E402
from reference_motion.humanoid.model import FOOT_CHANNELS  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
NOISE_SIGMAS_CM = (0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0)
WINDOW = 80


def noise_study(sequences, models, gamma, seed: int) -> list[dict]:
    rows = []
    for sigma in NOISE_SIGMAS_CM:
        rng = np.random.default_rng(seed)
        shifts = []

        def perturb(p: np.ndarray) -> np.ndarray:
            n = rng.normal(0.0, sigma / 100.0, p.shape).astype(np.float32)
            shifts.append(np.linalg.norm(n, axis=-1).mean())
            return p + n

        result = evaluate_contacts(sequences, models, gamma, perturb=perturb)
        rows.append({"sigma_cm": sigma, "mpjpe_cm": 100 * float(np.mean(shifts)),
                     **{f"f1_{m}": result[m]["overall"]["f1"] for m in models.names}})
    return rows


def _yaw_align(b: np.ndarray, a0: np.ndarray) -> np.ndarray:
    """Window ``b (T, 23, 3)`` rotated about z and moved so its first pelvis position and heading
    (pelvis → mean of the hips, turned a quarter) match frame ``a0 (23, 3)``."""
    def heading(frame):
        across = frame[JOINTS.index("left_hip"), :2] - frame[JOINTS.index("right_hip"), :2]
        return np.arctan2(-across[0], across[1])
    d = heading(a0) - heading(b[0])
    c, s = np.cos(d), np.sin(d)
    xy = b[..., :2] - b[0, 0, :2]
    out = b.copy()
    out[..., 0] = c * xy[..., 0] - s * xy[..., 1] + a0[0, 0]
    out[..., 1] = s * xy[..., 0] + c * xy[..., 1] + a0[0, 1]
    return out


def blending_study(sequences, models, gamma, seed: int, pairs: int) -> list[dict]:
    rng = np.random.default_rng(seed)
    windows = []
    for s in sequences:
        labels = gamma(s.forces, s.fps)
        for start in range(0, len(s.positions) - WINDOW + 1, 20):
            windows.append((s.positions[start:start + WINDOW], labels[start:start + WINDOW], s.fps))
    rows = []
    attempts = 0
    while len(rows) < pairs and attempts < 50 * pairs:
        attempts += 1
        i, j = rng.choice(len(windows), 2, replace=False)
        (pa, la, fps), (pb, lb, _) = windows[i], windows[j]
        channels = list(FOOT_CHANNELS[int(rng.integers(2))])
        agree = (la[:, channels] == lb[:, channels]).all(axis=1)
        if agree.mean() < 0.9 or not la[agree][:, channels].any():
            continue
        w_max = rng.uniform(0.1, 1.0)
        drift = np.cumsum(rng.normal(0, 1, WINDOW))
        w = w_max * (drift - drift.min()) / max(np.ptp(drift), 1e-9)
        blend = ((1 - w)[:, None, None] * pa + w[:, None, None] * _yaw_align(pb, pa[0])).astype(np.float32)
        truth = la[agree][:, channels]
        _, speed = foot_height_speed(blend, fps)
        skate = float(speed[:, channels][la[:, channels] & agree[:, None]].mean())
        row = {"skate_mps": skate}
        for m in models.names:
            pred = models.predict(m, blend, fps, gamma)[agree][:, channels]
            row[f"f1_{m}"] = detection_scores(pred, truth, channels=("toe", "heel"))["overall"]["f1"]
        rows.append(row)
    return sorted(rows, key=lambda r: r["skate_mps"])


def plot(path: Path, x: np.ndarray, curves: dict, xlabel: str, title: str, smooth: int = 1) -> None:
    fig, ax = plt.subplots(figsize=(6, 4))
    for label, y in curves.items():
        y = np.convolve(y, np.ones(smooth) / smooth, mode="valid") if smooth > 1 else y
        ax.plot(x[len(x) - len(y):] if smooth > 1 else x, y, marker="o" if smooth == 1 else None, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("contact F1")
    ax.set_ylim(0, 1)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dataset", type=Path, required=True)
    p.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    p.add_argument("--pairs", type=int, default=600, help="blended window pairs")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    gamma = ContactFunction()
    models = ContactModels(vgrf=load_network(args.vgrf, "vgrf"), ot=fit_ot(load_split(args.dataset, "train"), gamma))
    test = load_split(args.dataset, "test")
    RESULTS.mkdir(parents=True, exist_ok=True)
    noise = noise_study(test, models, gamma, args.seed)
    names = {"vgrf": "VGRFNet + Γ", "ot": "OT baseline"}
    mpjpe = np.array([r["mpjpe_cm"] for r in noise])
    plot(RESULTS / "contact_noise.png", mpjpe, {names[m]: np.array([r[f"f1_{m}"] for r in noise]) for m in names},
         "MPJPE of the added noise (cm)", "Contact F1 under Gaussian noise (test split)")
    drop = {m: float(np.interp(0.0, mpjpe, [r[f"f1_{m}"] for r in noise]) -
                     np.interp(5.0, mpjpe, [r[f"f1_{m}"] for r in noise])) for m in names}
    blends = blending_study(test, models, gamma, args.seed, args.pairs)
    skate = np.array([r["skate_mps"] for r in blends])
    plot(RESULTS / "contact_footskate.png", skate, {names[m]: np.array([r[f"f1_{m}"] for r in blends]) for m in names},
         "foot skate introduced by blending (m/s)", "Contact F1 against foot skate (moving average of 50)",
         smooth=min(50, len(blends)))
    print(f"{'MPJPE (cm)':>10} " + " ".join(f"{names[m]:>12}" for m in names))
    for r in noise:
        print(f"{r['mpjpe_cm']:>10.2f} " + " ".join(f"{r[f'f1_{m}']:>12.3f}" for m in names))
    print("F1 drop at 5 cm MPJPE: " + ", ".join(f"{names[m]} {drop[m]:.3f}" for m in names))
    bins = np.quantile(skate, [0, 1 / 3, 2 / 3, 1])
    for lo, hi in zip(bins[:-1], bins[1:]):
        sel = (skate >= lo) & (skate <= hi)
        print(f"skate {lo:.2f}–{hi:.2f} m/s: " + ", ".join(
            f"{names[m]} F1 {np.mean([r[f'f1_{m}'] for r, s in zip(blends, sel) if s]):.3f}" for m in names))
    emit_json({"noise": noise, "f1_drop_at_5cm": drop, "ot_thresholds": {"height_m": models.ot.height_m,
               "speed_mps": models.ot.speed_mps}, "blending": blends, "dataset": str(args.dataset)}, args.json)


if __name__ == "__main__":
    main()
