"""How well could a *perfect* cleaner do on our synthetic IMU clips under ADAPT's termination rule?

Usage: ``python bench/imu_oracle.py [--clips SOURCE ...] [--strengths 0.5 0.75 1 1.5 2 2.5 3]
[--seeds 4] [--kinds imu skate ...] [--json [OUT]] [--plot OUT.png]``

The "oracle" performs the clean clip exactly (the physically consistent motion the corrupted clip
was made from), started in the corrupted reference's state (ADAPT's reference state
initialisation copies the reference's root position *and heading*): the clean clip is moved so
that its root at the segment's first frame lies on the corrupted root, horizontally, and yawed
to the corrupted heading; it keeps its own height (a physical body stands on the floor). An
episode still ends as soon as e_discount = clamp(1.3 − 1.4‖p_head − p̄_head‖, 0, 1) drops below
0.025 (adapt eqs. 9 and 11), i.e. once the corrupted reference's head is 0.91 m away. Only
artefacts that move the whole body within a segment can do that.

Reported per artefact recipe (``imu`` = every kind, and each kind alone) and strength: the
oracle's ELR and SR90 over 300-frame segments (``--starts`` start frames spread over each clip ×
``--seeds`` seeds × ``--clips``), and the head gap (largest oracle–reference head distance within
a segment; mean and 95th percentile over segments) that shows how far each is from the 0.91 m
limit. An ELR goal above the oracle's cannot be met by any policy that does not skate.

``--clips`` takes SOURCE strings (:func:`reference_motion.library.load_motion`) or names of clip
sets (:func:`reference_motion.library.named_set`); cyclic clips are looped to fit the default
starts, a take shorter than one segment is one segment from its start to its end, as the
environments play it.
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np

from envs.config import MimicConfig
from envs.rewards import fall_discount, lagging
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion import rotations as rot
from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.humanoid.model import load_model
from reference_motion.library import expand_clips, load_motion

CLIPS = ("deepmimic:walker/0walk_forward", "deepmimic:walker/turn_left1", "deepmimic:walker/turn_right1",
         "deepmimic:walk", "deepmimic:walker/turn_left0")
"""ADAPT-style held-out walkers (the perception test/val clips) plus walk and turn_left0."""
STRENGTHS = (0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0)
LOOP_START_STEP = 60
"""Frames between segment starts on a looped cyclic clip (0, 60, …, as ADAPT's offsets)."""


def head_positions(model: mujoco.MjModel, data: mujoco.MjData, head: int, qpos: np.ndarray) -> np.ndarray:
    """World head positions ``(T, 3)`` of ``qpos (T, nq)`` (kinematics only, no contacts)."""
    out = np.empty((len(qpos), 3))
    for t, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        out[t] = data.xpos[head]
    return out


def oracle_segment(clean_qpos: np.ndarray, clean_head: np.ndarray, bad_qpos: np.ndarray, bad_head: np.ndarray,
                   config: MimicConfig) -> tuple[float, float]:
    """(ELR, largest head gap in m) of performing the clean segment against the corrupted one.

    The clean segment (``qpos``, head ``(n, 3)``) is yawed and moved horizontally so that its first
    root pose matches the corrupted reference's first root position and heading (RSI)."""
    turn = float(rot.yaw(bad_qpos[0, 3:7]) - rot.yaw(clean_qpos[0, 3:7]))
    c, s = np.cos(turn), np.sin(turn)
    rel = clean_head[:, :2] - clean_qpos[0, :2]
    performed = np.column_stack([bad_qpos[0, 0] + c * rel[:, 0] - s * rel[:, 1],
                                 bad_qpos[0, 1] + s * rel[:, 0] + c * rel[:, 1], clean_head[:, 2]])
    gaps = np.linalg.norm(performed - bad_head, axis=1)
    elr = 1.0
    for t in range(1, len(performed)):
        if lagging(fall_discount(performed[t], bad_head[t]), config.discount_threshold):
            elr = (t - 1) / (len(performed) - 1)
            break
    return elr, float(gaps.max())


def plot(rows: list[dict], recipes: list[str], limit_m: float, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for recipe in recipes:
        sel = [r for r in rows if r["artefacts"] == recipe]
        x = [r["strength"] for r in sel]
        style = dict(lw=2.5, color="k", zorder=3) if recipe == "imu" else dict(lw=1.2, alpha=0.85)
        axes[0].plot(x, [r["oracle_ELR"] for r in sel], marker="o", label=recipe, **style)
        axes[1].plot(x, [r["oracle_SR90"] for r in sel], marker="o", label=recipe, **style)
        axes[2].plot(x, [r["head_gap_p95_m"] for r in sel], marker="o", label=recipe, **style)
    axes[0].axhline(0.99, color="g", ls=":", lw=1, label="goal 0.99 at strength 1")
    axes[2].axhline(limit_m, color="r", ls="--", lw=1, label=f"termination ({limit_m:.2f} m)")
    for ax, title in zip(axes, ("oracle ELR", "oracle SR90", "head gap, 95th percentile (m)")):
        ax.set_xlabel("artefact strength (1 = a poor but real IMU take)")
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.axvline(1.0, color="grey", lw=0.8)
    axes[0].set_ylim(-0.02, 1.02)
    axes[1].set_ylim(-0.02, 1.02)
    axes[2].set_ylim(0.0, 1.05 * limit_m)
    axes[2].legend(fontsize=7, ncol=2, loc="upper left")
    fig.suptitle("A perfect cleaner (the clean clip, RSI-aligned) against IMU-corrupted references")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}", flush=True)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", default=list(CLIPS), help="SOURCE strings or clip-set names")
    p.add_argument("--strengths", type=float, nargs="+", default=list(STRENGTHS))
    p.add_argument("--seeds", type=int, default=4, help="artefact seeds per clip")
    p.add_argument("--starts", type=int, default=5, help="segment start frames per clip")
    p.add_argument("--kinds", nargs="+", default=["imu", *ARTEFACT_KINDS], choices=["imu", *ARTEFACT_KINDS],
                   help="artefact recipes: imu (every kind) and/or single kinds")
    p.add_argument("--json", nargs="?", const="-", default=None)
    p.add_argument("--plot", metavar="OUT.png", help="write ELR, SR90 and head gap against strength")
    args = p.parse_args()
    config = MimicConfig()
    hm = load_model("humanoid_1seg")
    data = mujoco.MjData(hm.model)
    head = hm.body_id("head")
    n = config.episode_frames + 1
    clips, segments = [], []
    for source in expand_clips(args.clips):
        clean = load_motion(source, min_frames=LOOP_START_STEP * (args.starts - 1) + n + 1)
        if clean.n_frames < n:  # a take shorter than an episode is one segment, as the env plays it
            starts = [0]
        elif clean.loop:
            starts = [LOOP_START_STEP * i for i in range(args.starts)]
        else:
            starts = sorted({int(s) for s in np.linspace(0, clean.n_frames - n, args.starts).round()})
        clips.append((source, clean, head_positions(hm.model, data, head, clean.qpos)))
        segments.append(starts)
    rows = []
    for recipe_name in args.kinds:
        for strength in args.strengths:
            elrs, gaps = [], []
            for c, ((source, clean, clean_head), starts) in enumerate(zip(clips, segments)):
                for seed in range(1000 + 100 * c, 1000 + 100 * c + args.seeds):
                    bad = corrupt(clean, ArtefactRecipe.named(recipe_name, strength), seed)
                    bad_head = head_positions(hm.model, data, head, bad.qpos)
                    for s in starts:
                        elr, gap = oracle_segment(clean.qpos[s:s + n], clean_head[s:s + n],
                                                  bad.qpos[s:s + n], bad_head[s:s + n], config)
                        elrs.append(elr)
                        gaps.append(gap)
            elrs, gaps = np.array(elrs), np.array(gaps)
            rows.append({"artefacts": recipe_name, "strength": strength, "segments": len(elrs),
                         "oracle_ELR": float(elrs.mean()), "oracle_SR90": float((elrs >= 0.9).mean()),
                         "head_gap_mean_m": float(gaps.mean()), "head_gap_p95_m": float(np.percentile(gaps, 95))})
            r = rows[-1]
            print(f"{recipe_name:>10} strength {strength:<4g} oracle ELR {r['oracle_ELR']:.3f}  SR90 {r['oracle_SR90']:.2f}"
                  f"  head gap mean {r['head_gap_mean_m']:.3f} m, p95 {r['head_gap_p95_m']:.3f} m  ({len(elrs)} segments)",
                  flush=True)
    limit_m = (1.3 - config.discount_threshold) / 1.4  # head gap where e_discount falls below the threshold
    if args.plot:
        plot(rows, args.kinds, limit_m, args.plot)
    emit_json({"rows": rows, "clips": [c[0] for c in clips], "starts": segments, "seeds": args.seeds,
               "segment_frames": n, "termination_head_gap_m": limit_m}, args.json)


if __name__ == "__main__":
    main()
