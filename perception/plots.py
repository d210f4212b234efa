"""Figures: estimated vGRF with contact bands, footskate before and after cleanup, and gait
timelines like contactvision Fig. 13."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from perception.contacts import CONTACT_NAMES
from perception.gait import PHASES, TOE_PEAK_RAD, gait_phases, toe_reference_angles
from reference_motion.atomic import atomic_write
from reference_motion.humanoid.model import FOOT_CHANNELS
from reference_motion.quality import horizontal_speed


PLOT_SUFFIXES = (".png", ".pdf", ".svg")
"""File types the plots are written as."""


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, path: Path) -> Path:
    """Write ``fig`` to ``path`` (its type from the suffix, one of :data:`PLOT_SUFFIXES`), atomically."""
    path = Path(path)
    fig.tight_layout()
    with atomic_write(path) as tmp:
        fig.savefig(tmp, dpi=120)
    _pyplot().close(fig)
    return path


def plot_contacts(path: Path, forces: np.ndarray, contacts: np.ndarray, fps: float, title: str) -> Path:
    """PNG of per-foot vGRF (body weights) over time with heel/toe contact bands."""
    plt = _pyplot()
    t = np.arange(len(forces)) / fps
    fig, axes = plt.subplots(2, 1, figsize=(10, 5), sharex=True)
    for foot, ax in enumerate(axes):
        side = ("left", "right")[foot]
        ax.plot(t, forces[:, foot].sum(-1), color="k", lw=1.2, label="vGRF (foot total)")
        toe, heel = FOOT_CHANNELS[foot]
        for ch, color, label in ((toe, "tab:orange", "toe contact"), (heel, "tab:blue", "heel contact")):
            ax.fill_between(t, 0, 1, where=contacts[:, ch], transform=ax.get_xaxis_transform(), color=color,
                            alpha=0.25, step="mid", label=label)
        ax.set_ylabel(f"{side} foot (BW)")
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(title)
    return _save(fig, path)


def plot_cleanup(path: Path, soles_before: np.ndarray, soles_after: np.ndarray, contacts: np.ndarray,
                 fps: float, title: str) -> Path:
    """PNG of the horizontal speed (m/s) of each foot's heel and toe contact joints ``(T, 4, 3)``
    before and after footskate cleanup, over bands where ``contacts (T, 4)`` say they are planted
    (there the speed should be 0)."""
    plt = _pyplot()
    t = np.arange(len(contacts)) / fps
    before, after = horizontal_speed(soles_before, fps), horizontal_speed(soles_after, fps)
    fig, axes = plt.subplots(4, 1, figsize=(10, 7), sharex=True)
    for ch, ax in enumerate(axes):
        ax.fill_between(t, 0, 1, where=contacts[:, ch], transform=ax.get_xaxis_transform(), color="tab:green",
                        alpha=0.2, step="mid", label="contact")
        ax.plot(t, before[:, ch], color="tab:red", lw=1.0, label="input")
        ax.plot(t, after[:, ch], color="k", lw=1.2, label="cleaned")
        ax.set_ylabel(f"{CONTACT_NAMES[ch].replace('_', ' ')}\n(m/s)", fontsize=8)
    axes[0].legend(loc="upper right", fontsize=8, ncol=3)
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(title)
    return _save(fig, path)

def plot_tolerance_curves(path: Path, curves: dict[str, dict[str, float]], title: str) -> Path:
    """PNG of overall F1 against temporal tolerance (underpressure Fig. 4): ``curves`` maps a model
    label to ``{tolerance in s: F1}``."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for label, curve in curves.items():
        ax.plot([float(t) for t in curve], list(curve.values()), marker="o", label=label)
    ax.set_xlabel("tolerance around a true contact change (s)")
    ax.set_ylabel("overall F1")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(title, fontsize=10)
    return _save(fig, path)


PHASE_COLOURS = ("#bbbbbb", "#d62728", "#ff7f0e", "#2ca02c", "#17becf", "#9467bd", "#1f77b4", "#8c564b", "#ffffff")
"""One colour per gait phase of :data:`~perception.gait.PHASES` (undefined: white)."""


def plot_gait(path: Path, contacts: np.ndarray, fps: float, title: str) -> Path:
    """PNG timeline of contacts ``(T, 4)``: the four contacts as bars, the gait phase of each
    frame as a coloured band, and the ToeRefEstimator's toe angles below."""
    plt = _pyplot()
    phases, toe_angles = gait_phases(contacts), toe_reference_angles(contacts)
    from matplotlib.patches import Patch

    t = np.arange(len(contacts)) / fps
    fig, axes = plt.subplots(3, 1, figsize=(11, 5.5), sharex=True, gridspec_kw={"height_ratios": [2, 0.6, 1.4]})
    for row, name in enumerate(CONTACT_NAMES):
        axes[0].fill_between(t, row + 0.1, row + 0.9, where=contacts[:, row], step="mid", color="tab:green")
    axes[0].set_yticks(np.arange(4) + 0.5, [n.replace("_", " ") for n in CONTACT_NAMES])
    axes[0].set_ylim(0, 4)
    axes[0].set_title("contacts", fontsize=9, loc="left")
    colours = np.array([PHASE_COLOURS[p] for p in phases])
    dt = 1.0 / fps
    for k in range(len(PHASES)):
        mask = phases == k
        if mask.any():
            axes[1].bar(t[mask], 1.0, width=dt, color=colours[mask], align="edge", linewidth=0)
    axes[1].set_yticks([])
    axes[1].set_title("gait phase (right foot, contactvision Table 2)", fontsize=9, loc="left")
    axes[1].legend(handles=[Patch(color=PHASE_COLOURS[k], label=PHASES[k].replace("_", " "))
                            for k in sorted(set(phases.tolist()))], fontsize=7, ncol=5, loc="upper center",
                   bbox_to_anchor=(0.5, -0.35), frameon=False)
    for foot, colour in ((0, "tab:blue"), (1, "tab:red")):
        axes[2].plot(t, np.degrees(toe_angles[:, foot]), color=colour, label=("left", "right")[foot] + " toe")
    axes[2].set_ylim(-2, np.degrees(TOE_PEAK_RAD) + 5)
    axes[2].set_ylabel("toe reference (°)")
    axes[2].set_xlabel("time (s)")
    axes[2].legend(fontsize=8, loc="upper right")
    fig.suptitle(title)
    return _save(fig, path)
