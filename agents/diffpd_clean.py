"""Trained diff-PD cycles on disk, and cleaning motions with one (``agents/clean.py --method diffpd``).

A trained model is a directory (``models/diffpd``) holding

* ``diffpd.pt`` — ``{"format", "config", "dynet", "grfnet"}``: the :class:`~agents.diffpd.DiffPDConfig`
  as a JSON-able dict (:func:`config_to_dict`) and the two networks' ``state_dict``\\ s (``dynet``
  is ``None`` for a fixed-gains model);
* ``sidecar.json`` — how it was trained (written by ``agents/train_diffpd.py``);
* ``checkpoint.pt`` — the training state for ``--resume`` (optional; not read here).

Cleaning (:func:`clean_motions`) runs the dynamic cycle through a batch of reference clips at once,
each from its own first frame (``qpos[0]``, ``qvel[0]``) with the reference frames as targets, by the
cycle's NumPy forward pass (:class:`agents.diffpd_fast.FastCycle`; no autograd): one continuous
simulation per clip. The root residual's bound and how often it saturates go into each cleaned
motion's ``source["diffpd_root_residual"]``. Where a clip's simulated root strays more than
:attr:`DiffPDCleanConfig.reanchor_m` from the reference (or the state is not finite) it restarts
from the reference state of that frame; such re-anchors are recorded as in the PPO path
(:class:`agents.clean.Reanchor`, ``reason`` ``"lagging"`` or ``"unstable"``, ``retries`` 0).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import torch
from tqdm import tqdm

from agents.diffpd import DiffPDConfig, DynamicCycle
from agents.diffpd_fast import FastCycle
from reference_motion.motion import Motion

WEIGHTS_FILE = "diffpd.pt"
SIDECAR_FILE = "sidecar.json"
CHECKPOINT_FILE = "checkpoint.pt"
WEIGHTS_FORMAT = "physmimic.diffpd/1"


class DiffPDModelError(ValueError):
    """A diff-PD model directory is missing, malformed, or does not fit its configuration."""


# ------------------------------------------------------------------ config <-> JSON
def config_to_dict(config: DiffPDConfig) -> dict[str, Any]:
    """``config`` as JSON-able values: tuples as lists, infinities as ``"inf"``, the dtype by name."""
    def plain(v: Any) -> Any:
        if isinstance(v, torch.dtype):
            return str(v).removeprefix("torch.")
        if isinstance(v, (tuple, list)):
            return [plain(x) for x in v]
        if isinstance(v, float) and math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return v
    return {f.name: plain(getattr(config, f.name)) for f in dataclasses.fields(config)}


def config_from_dict(values: dict[str, Any]) -> DiffPDConfig:
    """The inverse of :func:`config_to_dict` (unknown keys are refused)."""
    names = {f.name for f in dataclasses.fields(DiffPDConfig)}
    unknown = set(values) - names
    if unknown:
        raise DiffPDModelError(f"unknown DiffPDConfig fields {sorted(unknown)}")

    def back(v: Any) -> Any:
        if isinstance(v, list):
            return tuple(back(x) for x in v)
        if v in ("inf", "-inf"):
            return float(v)
        return v
    out = {k: back(v) for k, v in values.items()}
    if "dtype" in out:
        out["dtype"] = getattr(torch, out["dtype"])
    return DiffPDConfig(**out)


# ------------------------------------------------------------------ weights
def save_cycle(cycle: DynamicCycle, path: str | Path) -> Path:
    """Write ``cycle``'s configuration and networks to ``path`` (a ``.pt`` file), atomically."""
    from reference_motion.atomic import atomic_write

    state = {"format": WEIGHTS_FORMAT, "config": config_to_dict(cycle.config),
             "dynet": None if cycle.dynet is None else cycle.dynet.state_dict(),
             "grfnet": None if cycle.grfnet is None else cycle.grfnet.state_dict()}
    with atomic_write(path) as tmp:
        torch.save(state, tmp)
    return Path(path)


def load_cycle(path: str | Path) -> DynamicCycle:
    """The trained cycle in model directory ``path`` (or its ``diffpd.pt``), in eval mode;
    :class:`DiffPDModelError` says what is wrong in one line."""
    path = Path(path)
    file = path if path.suffix == ".pt" else path / WEIGHTS_FILE
    if not file.exists():
        hint = " (that is a PPO policy: use --method ppo)" if (file.parent / "model.zip").exists() else ""
        raise DiffPDModelError(f"{file}: no such diff-PD weights file (a diff-PD model is a directory with "
                               f"{WEIGHTS_FILE}, written by agents/train_diffpd.py){hint}")
    try:
        state = torch.load(file, map_location="cpu", weights_only=False)
    except Exception as err:  # a damaged or foreign file
        raise DiffPDModelError(f"{file}: cannot read diff-PD weights: {err}") from err
    if not isinstance(state, dict) or state.get("format") != WEIGHTS_FORMAT:
        raise DiffPDModelError(f"{file}: not diff-PD weights (format {WEIGHTS_FORMAT} expected)")
    missing = [k for k in ("config", "dynet", "grfnet") if k not in state]
    if missing:
        raise DiffPDModelError(f"{file}: incomplete diff-PD weights: no {', '.join(missing)}")
    try:
        config = config_from_dict(state["config"])
    except (TypeError, ValueError, AttributeError) as err:
        raise DiffPDModelError(f"{file}: bad configuration: {err}") from err
    cycle = DynamicCycle.neural(config, dynet=state["dynet"] is not None, grfnet=state["grfnet"] is not None)
    for name in ("dynet", "grfnet"):
        net = getattr(cycle, name)
        if net is None:
            continue
        try:
            net.load_state_dict(state[name])
        except RuntimeError as err:
            first = str(err).splitlines()[1].strip() if len(str(err).splitlines()) > 1 else str(err)
            raise DiffPDModelError(f"{file}: the {name} weights do not fit a {config.model} cycle with "
                                   f"hidden sizes {getattr(config, name + '_hidden')}: {first}") from err
    return cycle.eval()


# ------------------------------------------------------------------ cleaning
@dataclass(frozen=True)
class DiffPDCleanConfig:
    """How :func:`clean_motions` re-performs clips.

    Attributes:
        reanchor_m: re-anchor a clip to its reference state when the simulated pelvis is farther
            than this (m) from the reference pelvis (1.0).
        progress: show a progress bar over the frames.
    """

    reanchor_m: float = 1.0
    progress: bool = True


@dataclass(frozen=True)
class Performance:
    """A batch of clips performed by a cycle.

    Attributes:
        motions: the cleaned motions (same lengths as the references).
        vgrf: per clip ``(T, P)`` the vertical GRF λ_z per contact point (N), averaged over each
            frame's iterations (row 0: zeros, the start state).
        reports: per clip, :meth:`~agents.diffpd.ClipResult.report`-style root-force magnitudes.
        gains: per clip, the mean gain scale ``s_g`` over the hinges and frames.
        floor_vgrf: per clip ``(T, P)`` the vertical force (N) of the floor projection's impulses
            (``p/Δt``, mass metric): the support the contact constraint adds to λ.
    """

    motions: list[Motion]
    vgrf: list[np.ndarray]
    reports: list[dict[str, float]]
    gains: list[float]
    floor_vgrf: list[np.ndarray] | None = None


def clean_motions(cycle: DynamicCycle, references: Sequence[Motion], config: DiffPDCleanConfig = DiffPDCleanConfig(),
                  cleaned_by: str = "diffpd") -> Performance:
    """Re-perform ``references`` (each of ``cycle.config.model``, at ``cycle.config.fps``, at least
    2 frames) with ``cycle``, all in one batch (shorter clips hold their last frame as target
    after their end; those frames are dropped). See the module docstring."""
    from agents.clean import Reanchor  # agents.clean imports this module lazily: no cycle

    cfg = cycle.config
    for r in references:
        if r.model != cfg.model:
            raise ValueError(f"{r.name}: a {r.model} motion, but the diff-PD model is for {cfg.model}")
        if abs(r.fps - cfg.fps) > 1e-6:
            raise ValueError(f"{r.name}: {r.fps:g} Hz, but the diff-PD model runs at {cfg.fps:g} Hz")
        if r.n_frames < 2:
            raise ValueError(f"{r.name}: {r.n_frames} frames; cleaning needs at least 2")
    B, T = len(references), max(r.n_frames for r in references)
    targets = np.stack([np.concatenate([r.qpos, np.repeat(r.qpos[-1:], T - r.n_frames, 0)]) for r in references])
    velocities = np.stack([np.concatenate([r.qvel, np.zeros((T - r.n_frames, r.qvel.shape[1]))]) for r in references])
    fast = FastCycle(cycle)  # the same iteration in NumPy: no autograd wanted here, 3x less overhead
    q, qd = targets[:, 0].copy(), velocities[:, 0].copy()
    out_q = np.empty_like(targets)
    out_q[:, 0] = targets[:, 0]
    vgrf = np.zeros((B, T, cycle.n_points))
    floor = np.zeros((B, T, cycle.n_points))
    keys = ("res_lin", "res_ang", "virt_lin", "virt_ang", "grf", "s_g", "sat_lin", "sat_ang")
    sums = {k: np.zeros(B) for k in keys}
    rho = fast.rho
    lengths = np.array([r.n_frames for r in references])
    reanchors: list[list] = [[] for _ in references]
    bar = tqdm(total=T - 1, desc="cleaning (diff-PD)", unit="frame", disable=not config.progress)
    for t in range(1, T):
        out = fast.frame(q, qd, targets[:, t])
        q, qd = out.q, out.qd
        vgrf[:, t] = out.force[..., 2].mean(1)
        if cfg.projection_metric == "mass":  # the floor's impulses are N·s: as forces over the step
            floor[:, t] = out.impulse.mean(1) / cfg.dt
        r, v = out.root_residual, out.root_virtual
        alive = t < lengths  # padded frames past a clip's end do not count
        # saturated: the residual at ≥ tanh(1) = 76% of its bound in some component
        for key, value in (("res_lin", np.linalg.norm(r[..., :3], axis=-1)),
                           ("res_ang", np.linalg.norm(r[..., 3:], axis=-1)),
                           ("virt_lin", np.linalg.norm(v[..., :3], axis=-1)),
                           ("virt_ang", np.linalg.norm(v[..., 3:], axis=-1)),
                           ("grf", out.force[..., 2].sum(-1)), ("s_g", out.s_g[..., 6:].mean(-1)),
                           ("sat_lin", (np.abs(v[..., :3]) >= rho[:3]).any(-1)),
                           ("sat_ang", (np.abs(v[..., 3:]) >= rho[3:]).any(-1))):
            sums[key] += alive * value.mean(1)
        finite = np.isfinite(q).all(1) & np.isfinite(qd).all(1)
        stray = np.linalg.norm(q[:, :3] - targets[:, t, :3], axis=1)
        bad = ~finite | ~(stray <= config.reanchor_m)
        for b in np.nonzero(bad)[0].tolist():
            if t < references[b].n_frames:
                jump = float(stray[b]) if finite[b] else None
                reanchors[b].append(Reanchor(frame=t, reason="lagging" if finite[b] else "unstable", retries=0,
                                             failed_at=t, best_reached=t, jump_m=jump))
            q[b], qd[b] = targets[b, t], velocities[b, t]
        out_q[:, t] = q
        bar.update(1)
    bar.close()
    motions, reports, gains = [], [], []
    bound = {"residual_bound_linear_bw": float(rho[0]) / cycle.weight if np.isfinite(rho[0]) else None,
             "residual_bound_angular_nm": float(rho[3]) if np.isfinite(rho[3]) else None,  # None: unbounded
             "no_slip_height_m": cfg.no_slip_height}
    for b, ref in enumerate(references):
        n = ref.n_frames - 1
        w = cycle.weight
        report = {"residual_linear_bw_mean": sums["res_lin"][b] / n / w,
                  "residual_angular_nm_mean": sums["res_ang"][b] / n,
                  "residual_linear_saturated_share": sums["sat_lin"][b] / n,
                  "residual_angular_saturated_share": sums["sat_ang"][b] / n,
                  "root_virtual_linear_bw_mean": sums["virt_lin"][b] / n / w,
                  "root_virtual_angular_nm_mean": sums["virt_ang"][b] / n,
                  "grf_vertical_bw_mean": sums["grf"][b] / n / w}
        source = {**ref.source, "cleaned_by": cleaned_by, "method": "diffpd",
                  "reanchors": [dataclasses.asdict(a) for a in reanchors[b]], "recoveries": [],
                  "simulated_fraction": 1.0 - len(reanchors[b]) / n,
                  "diffpd_root_residual": {**bound, **{k: float(v) for k, v in report.items()}}}
        motions.append(ref.with_qpos(out_q[b, :ref.n_frames], name=f"{ref.name} (cleaned)", loop=False, source=source))
        reports.append({k: float(v) for k, v in report.items()})
        gains.append(float(sums["s_g"][b] / n))
    return Performance(motions, [vgrf[b, :lengths[b]] for b in range(B)], reports, gains,
                       [floor[b, :lengths[b]] for b in range(B)])


# ------------------------------------------------------------------ agents/clean.py --method diffpd
PPO_ONLY_OPTIONS = {"no_adapt": "--no-adapt", "rewind_s": "--rewind-s", "retries": "--retries",
                    "adapt_budget_s": "--adapt-budget-s", "adapt_target": "--adapt-target",
                    "adapt_steps": "--adapt-steps", "adapt_chunk": "--adapt-chunk", "adapt_cache": "--adapt-cache",
                    "adapt_variance": "--adapt-variance", "adapt_lr": "--adapt-lr", "adapt_keep": "--adapt-keep"}
"""``agents/clean.py`` options (argparse dest → flag) that only the PPO path uses."""


def clean_from_args(args, parser) -> tuple[Motion, Motion, dict]:
    """``agents/clean.py --method diffpd``: the reference (loaded for the model's humanoid, looped,
    corrupted as asked), the cleaned motion and the result's extra entries (``diffpd``: root forces,
    mean gain scale, wall time). A PPO-only option set away from its default is refused."""
    import time

    from agents.clean import load_clip  # (at least MIN_FRAMES frames)

    for dest, flag in PPO_ONLY_OPTIONS.items():
        if getattr(args, dest) != parser.get_default(dest):
            raise ValueError(f"{flag} applies to --method ppo only (diff-PD neither adapts nor retries)")
    cycle = load_cycle(args.policy)
    reference = load_clip(cycle.config.model, args)
    start = time.perf_counter()
    with torch.no_grad():
        performance = clean_motions(cycle, [reference], cleaned_by=str(args.policy))
    wall = time.perf_counter() - start
    bound = {k: v for k, v in performance.motions[0].source["diffpd_root_residual"].items() if "bound" in k or "slip" in k}
    extra = {"diffpd": {**bound, **performance.reports[0], "gain_scale_mean": performance.gains[0],
                        "fixed_gains": cycle.dynet is None, "wall_s": wall,
                        "frames_per_s": (reference.n_frames - 1) / wall}}
    return reference, performance.motions[0], extra
