"""Train DyNet and GRFNet of the differentiable PD branch (neural_physcap §3.4–3.5) on reference clips.

Usage::

    python agents/train_diffpd.py --clips library:data/library/train --out models/diffpd \\
        --minutes 12 --seed 0 [--resume] [--fixed-gains]

Data: every clip of ``--clips`` (SOURCE strings, clip sets expanded) for the cycle's model, clean and
``--variants`` IMU-corrupted copies (``corrupt(clip, ArtefactRecipe.imu().scaled(strength), seed)``);
the corrupted copy is the *target* the PD controller follows, the clean clip the *ground truth*.

Truncated back-propagation through time: ``--batch`` streams each walk through a clip in windows of
``--window`` frames (``k = 6`` cycle iterations a frame); a window starts from the state where the
stream's previous window ended (detached), so the networks learn on the states the controller
itself reaches, and the gradient spans one window. A stream restarts from the target's state at a
random frame of a random clip/variant when its clip ends or its pelvis strays more than
``reset_m`` from the ground truth. Losses per window (means over streams, frames, iterations):

* ``L_Dyn = ‖d(q_gt, q)‖² + φ‖τ‖²`` (eq. 25, φ = 1e-6; ``d`` is
  :func:`~agents.diffpd.pose_difference`, qvel layout: m and rad). The ground-truth pose takes its
  pelvis x, y and orientation from the target: the IMU artefacts drift the root's horizontal
  position and heading, which no tracking controller can observe, so only height and hinges are
  held to the clean clip. ``‖τ‖²`` is taken over the hinge rows only: the root rows are the virtual
  root force (a 0.4 m root lag at 5000 N/m is 2000 N, a penalty 4 against pose losses of ~0.3), and
  with them DyNet learned to stop tracking the root (measured on DeepMimic run after 150 steps: root
  lag 0.43 → 0.99 m); ``L_force`` is what keeps the root force small, by explaining it with GRF.
  Trains DyNet only.
* ``L_GRF = L_force + L_smooth + L_cone`` (eq. 8, 10–12), forces in body weights (``w``):
  ``L_force = ‖τ*_root / w‖²`` (the root force GRF leave unexplained; angular rows in w·m),
  ``L_smooth = ‖(λ_i − λ_{i−1}) / w‖²`` over consecutive iterations, ``L_cone`` the squared
  angle of λ beyond the cone (rad²; zero by construction of :func:`~agents.diffpd.friction_cone`,
  computed as a check). Trains GRFNet only.

Choices for a CPU and a budget of minutes (the paper trains for days on a GPU):

* windows of 8 frames (48 iterations; 0.13 s) × 8 streams: one step (forward and both backward
  passes) took 0.51 s on one thread of this 2-core machine with the 8 sole corners as contact
  points (the shipped ``models/diffpd``: 1914 steps in 14 minutes; 0.47 s with the 4 foot points);
  8 frames cover the 4-frame lag of the fixed gains twice over;
* DyNet hidden (64, 64), GRFNet hidden (64, 64, 64): 102k + 21k parameters with 8 contact points
  (1 MB in float64; DyNet's input is 1423 wide, mostly the mass matrix);
  the cycle's Python overhead, not the networks, bounds the speed at these sizes;
* Adam, learning rate 1e-3, gradient norm clipped to 1 (the paper's 3e-6 is for its long training);
* contact points at the 8 sole corners (:data:`~agents.diffpd.SOLE_CORNER_SITES`), not the 4
  centre-line points: a rolled foot then stays out of the floor too;
* the root applies a *bounded* residual ``ρ tanh(τ*_root/ρ)`` with ``ρ`` = 0.5 body weight and
  200 N·m (``--residual-bound``; the paper's root is unbounded, a virtual force puppeteering the
  pelvis); the rest of the root's support comes from GRFNet's λ and the floor projection, whose
  contact points in contact stick (``--no-slip-height`` 1 cm: no foot skate); and
  ``damping = "constant"`` (``k_d`` stays the MJCF's: the lag a gain change can remove is then
  not capped at 29%; see :attr:`~agents.diffpd.DiffPDConfig.damping`).

``--fixed-gains`` trains the baseline: the same loop without DyNet (``s_g = ½, s_f = 0``; GRFNet only).

Output in ``--out``: ``diffpd.pt`` (weights, :mod:`agents.diffpd_clean`), ``sidecar.json`` (commands,
seed, steps, wall time, configuration, metrics) and ``checkpoint.pt`` (everything ``--resume``
needs: networks, optimisers, the data RNG and the streams, so a resumed run continues exactly).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import shlex
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

if __package__ in (None, ""):  # `python agents/train_diffpd.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
import torch

from agents.diffpd import FOOT_POINT_SITES, ROOT_DOF, SOLE_CORNER_SITES, DiffPDConfig, DynamicCycle, pose_difference
from agents.diffpd_clean import (CHECKPOINT_FILE, SIDECAR_FILE, WEIGHTS_FILE, config_to_dict,
                                 save_cycle)
from reference_motion.artefacts import ArtefactRecipe, corrupt
from reference_motion.atomic import atomic_write, write_json
from reference_motion.cli import (CliParser, fraction, non_negative_float, one_line_errors, output_dir,
                                  positive_float, positive_int)
from reference_motion.library import expand_clips, load_motion

try:
    from tqdm import tqdm
except ImportError:  # pragma: no cover - tqdm is a dependency, but the loop does not need it
    tqdm = None

SIDECAR_FORMAT = "physmimic.diffpd-training/1"
CHECKPOINT_FORMAT = "physmimic.diffpd-checkpoint/1"
CONTACTS = {"corners": SOLE_CORNER_SITES, "points": FOOT_POINT_SITES}
"""Contact point sets of ``--contacts``: the 8 sole corners (default) or the 4 centre-line foot points."""


@dataclass(frozen=True)
class TrainConfig:
    """What and how to train (defaults: the shipped ``models/diffpd``; see the module docstring).

    Attributes:
        clips: SOURCE strings or clip sets of the training clips.
        model: humanoid model (``humanoid_1seg`` / ``humanoid_2seg``).
        window: frames per truncated-BPTT window.
        batch: parallel streams (clips) per step.
        corrupted_fraction: share of stream starts on an IMU-corrupted target (the rest clean).
        strength: IMU artefact strength (``ArtefactRecipe.imu().scaled(strength)``).
        variants: corrupted copies per clip (artefact seeds ``1000·seed + i``).
        lr: Adam learning rate of both networks.
        grad_clip: gradient norm clip per network.
        tau_weight: φ of ``L_Dyn`` (1e-6, the paper's).
        reset_m: a stream restarts when its pelvis is farther than this (m) from the ground truth.
        dynet_hidden, grfnet_hidden: network widths.
        residual_bound, no_slip_height, damping, contact_sites: the cycle's
            (:class:`~agents.diffpd.DiffPDConfig`); the root residual is bounded by 0.5 body weight
            (343.35 N for the 70 kg humanoid) and 200 N·m, planted sole points stick;
            the contact points are the sole corners (:data:`~agents.diffpd.SOLE_CORNER_SITES`).
        fixed_gains: train the baseline (no DyNet).
        seed: seeds the networks' initialisation, the artefacts and the data sampling.
        checkpoint_every: steps between checkpoints (also written at the end).
    """

    clips: tuple[str, ...] = ("library:data/library/train",)
    model: str = "humanoid_1seg"
    window: int = 8
    batch: int = 8
    corrupted_fraction: float = 0.5
    strength: float = 1.0
    variants: int = 2
    lr: float = 1e-3
    grad_clip: float = 1.0
    tau_weight: float = 1e-6
    reset_m: float = 0.5
    dynet_hidden: tuple[int, int] = (64, 64)
    grfnet_hidden: tuple[int, int, int] = (64, 64, 64)
    residual_bound: tuple[float, float] = (343.35, 200.0)
    no_slip_height: float = 0.01
    damping: str = "constant"
    contact_sites: tuple[str, ...] = SOLE_CORNER_SITES
    fixed_gains: bool = False
    seed: int = 0
    checkpoint_every: int = 50

    def cycle_config(self) -> DiffPDConfig:
        return DiffPDConfig(model=self.model, residual_bound=self.residual_bound, damping=self.damping,
                            no_slip_height=self.no_slip_height, contact_sites=self.contact_sites,
                            dynet_hidden=self.dynet_hidden, grfnet_hidden=self.grfnet_hidden)

    def as_dict(self) -> dict:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()}

    @classmethod
    def from_dict(cls, values: dict) -> "TrainConfig":
        fields = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in values.items() if k in fields})


# ------------------------------------------------------------------ data
@dataclass(frozen=True)
class Pair:
    """A training clip: ``target (T, nq)`` (what the PD follows; clean or corrupted), its velocities
    ``target_qvel (T, nv)`` (a stream's start state) and the clean ``truth (T, nq)``."""

    name: str
    target: np.ndarray
    target_qvel: np.ndarray
    truth: np.ndarray
    corrupted: bool


def load_pairs(config: TrainConfig) -> list[Pair]:
    """The clean and corrupted :class:`Pair` of every clip long enough for a window."""
    recipe = ArtefactRecipe.imu().scaled(config.strength)
    pairs = []
    for source in expand_clips(list(config.clips)):
        clean = load_motion(source, config.model)
        if clean.n_frames < config.window + 2:
            continue
        pairs.append(Pair(source, clean.qpos, clean.qvel, clean.qpos, False))
        for i in range(config.variants):
            noisy = corrupt(clean, recipe, 1000 * config.seed + i)
            pairs.append(Pair(f"{source} (imu {i})", noisy.qpos, noisy.qvel, clean.qpos, True))
    if not pairs:
        raise ValueError(f"no clip of {list(config.clips)} has the {config.window + 2} frames a window needs")
    return pairs


# ------------------------------------------------------------------ losses
def grf_losses(result, weight: float, mu: float) -> dict[str, torch.Tensor]:
    """``L_force``, ``L_smooth``, ``L_cone`` (see the module docstring) of a
    :class:`~agents.diffpd.ClipResult` ``(B, W, k, …)``."""
    force = (result.root_virtual / weight).pow(2).sum(-1).mean()
    lam = result.force.flatten(1, 2) / weight                                     # (B, W·k, P, 3)
    smooth = (lam[:, 1:] - lam[:, :-1]).pow(2).sum((-1, -2)).mean() if lam.shape[1] > 1 else lam.new_zeros(())
    tangential = lam[..., :2].norm(dim=-1)
    angle = torch.atan2(tangential, lam[..., 2].clamp(min=0.0))
    loaded = lam.norm(dim=-1) > 1e-9
    cone = torch.where(loaded, (angle - math.atan(mu)).clamp(min=0.0).pow(2), torch.zeros_like(angle)).mean()
    return {"force": force, "smooth": smooth, "cone": cone}


def dyn_loss(result, truth: torch.Tensor, target: torch.Tensor, tau_weight: float) -> dict[str, torch.Tensor]:
    """``L_Dyn`` parts: ``pose`` (``‖d(q_gt', q)‖²`` over frames 1…W, ``q_gt'`` the ground truth with the
    target's pelvis x, y and orientation) and ``tau`` (``φ‖τ_hinges‖²``, the hinge rows of τ: see the
    module docstring); ``truth, target (B, W+1, nq)``."""
    gt = torch.cat([target[:, 1:, :2], truth[:, 1:, 2:3], target[:, 1:, 3:7], truth[:, 1:, 7:]], dim=-1)
    pose = pose_difference(gt, result.q[:, 1:]).pow(2).sum(-1).mean()
    tau = tau_weight * result.tau[..., ROOT_DOF:].pow(2).sum(-1).mean()
    return {"pose": pose, "tau": tau}


# ------------------------------------------------------------------ the trainer
class Trainer:
    """Networks, optimisers, data streams and history of one training run (resumable)."""

    def __init__(self, config: TrainConfig, pairs: list[Pair]):
        self.config, self.pairs = config, pairs
        torch.manual_seed(config.seed)
        self.cycle: DynamicCycle = DynamicCycle.neural(config.cycle_config(), dynet=not config.fixed_gains)
        self.dtype = self.cycle.config.dtype
        self.opt_dyn = torch.optim.Adam(self.cycle.dynet.parameters(), lr=config.lr) if self.cycle.dynet else None
        self.opt_grf = torch.optim.Adam(self.cycle.grfnet.parameters(), lr=config.lr)
        self.rng = np.random.default_rng(config.seed)
        self.step, self.wall_s, self.history = 0, 0.0, []
        self.skipped = 0
        """Windows whose loss was not finite: no update, their streams restarted."""
        self.commands: list[str] = []
        B = config.batch
        self.stream_pair = np.zeros(B, dtype=int)
        self.stream_frame = np.zeros(B, dtype=int)
        self.q = torch.zeros(B, self.cycle.nq, dtype=self.dtype)
        self.qd = torch.zeros(B, self.cycle.nv, dtype=self.dtype)
        for b in range(B):
            self._restart(b)

    # -------------------------------------------------------------- streams
    def _restart(self, b: int) -> None:
        """Stream ``b`` at a random window start of a random pair, in the target's state there."""
        cfg = self.config
        corrupted = [i for i, p in enumerate(self.pairs) if p.corrupted]
        clean = [i for i, p in enumerate(self.pairs) if not p.corrupted]
        pool = corrupted if corrupted and (not clean or self.rng.random() < cfg.corrupted_fraction) else clean
        i = int(pool[self.rng.integers(len(pool))])
        pair = self.pairs[i]
        t = int(self.rng.integers(0, len(pair.target) - cfg.window - 1))
        self.stream_pair[b], self.stream_frame[b] = i, t
        self.q[b] = torch.as_tensor(pair.target[t], dtype=self.dtype)
        self.qd[b] = torch.as_tensor(pair.target_qvel[t], dtype=self.dtype)

    def windows(self) -> tuple[torch.Tensor, torch.Tensor]:
        """Targets and ground truth ``(B, W+1, nq)`` of the streams' current windows."""
        W = self.config.window
        tgt = [self.pairs[i].target[t:t + W + 1] for i, t in zip(self.stream_pair, self.stream_frame)]
        gt = [self.pairs[i].truth[t:t + W + 1] for i, t in zip(self.stream_pair, self.stream_frame)]
        return torch.as_tensor(np.stack(tgt), dtype=self.dtype), torch.as_tensor(np.stack(gt), dtype=self.dtype)

    # -------------------------------------------------------------- one step
    def train_step(self) -> dict[str, float]:
        """One window for every stream: losses, one Adam step per network, streams advanced."""
        cfg, cycle = self.config, self.cycle
        target, truth = self.windows()
        result = cycle.rollout(self.q, self.qd, target)
        dyn = dyn_loss(result, truth, target, cfg.tau_weight)
        grf = grf_losses(result, cycle.weight, cycle.config.mu)
        l_dyn, l_grf = dyn["pose"] + dyn["tau"], grf["force"] + grf["smooth"] + grf["cone"]
        if not bool(torch.isfinite(l_dyn) and torch.isfinite(l_grf)):  # a state blew up: no update from it
            for b in range(cfg.batch):
                self._restart(b)
            self.skipped += 1
            return {"step": self.step, "skipped": self.skipped}
        nets = [(cycle.grfnet, self.opt_grf, l_grf)]
        if cycle.dynet is not None:
            nets.insert(0, (cycle.dynet, self.opt_dyn, l_dyn))
        for i, (net, _, loss) in enumerate(nets):  # every gradient first: a step changes the graph's weights
            params = list(net.parameters())
            grads = torch.autograd.grad(loss, params, retain_graph=i < len(nets) - 1, allow_unused=True)
            for p, g in zip(params, grads):
                p.grad = torch.zeros_like(p) if g is None else g
            torch.nn.utils.clip_grad_norm_(params, cfg.grad_clip)
        for _, opt, _ in nets:
            opt.step()
        # advance the streams; restart those at a clip's end or astray
        q_end, qd_end = result.q[:, -1].detach(), result.qd[:, -1].detach()
        root = torch.cat([target[:, -1, :2], truth[:, -1, 2:3]], dim=1)  # as in dyn_loss
        stray = (q_end[:, :3] - root).norm(dim=1)
        self.q, self.qd = q_end.clone(), qd_end.clone()
        self.stream_frame += cfg.window
        for b in range(cfg.batch):
            finite = bool(torch.isfinite(self.q[b]).all() and torch.isfinite(self.qd[b]).all())
            end = self.stream_frame[b] + cfg.window + 1 > len(self.pairs[self.stream_pair[b]].target)
            if end or not finite or float(stray[b]) > cfg.reset_m:
                self._restart(b)
        self.step += 1
        row = {"step": self.step, "l_dyn": float(l_dyn.detach()), "pose": float(dyn["pose"].detach()),
               "tau": float(dyn["tau"].detach()), "l_grf": float(l_grf.detach()),
               **{k: float(v.detach()) for k, v in grf.items()},
               "s_g": float(result.s_g[..., ROOT_DOF:].detach().mean()), "stray_m": float(stray.mean())}
        self.history.append(row)
        return row

    # -------------------------------------------------------------- persistence
    def state(self) -> dict:
        return {"format": CHECKPOINT_FORMAT, "config": self.config.as_dict(), "step": self.step,
                "wall_s": self.wall_s, "history": self.history, "commands": self.commands,
                "dynet": self.cycle.dynet.state_dict() if self.cycle.dynet else None,
                "grfnet": self.cycle.grfnet.state_dict(),
                "opt_dyn": self.opt_dyn.state_dict() if self.opt_dyn else None, "opt_grf": self.opt_grf.state_dict(),
                "rng": self.rng.bit_generator.state, "stream_pair": self.stream_pair.copy(),
                "stream_frame": self.stream_frame.copy(), "q": self.q.clone(), "qd": self.qd.clone()}

    def load_state(self, state: dict) -> None:
        if self.cycle.dynet is not None:
            self.cycle.dynet.load_state_dict(state["dynet"])
            self.opt_dyn.load_state_dict(state["opt_dyn"])
        self.cycle.grfnet.load_state_dict(state["grfnet"])
        self.opt_grf.load_state_dict(state["opt_grf"])
        self.rng.bit_generator.state = state["rng"]
        self.step, self.wall_s, self.history = state["step"], state["wall_s"], list(state["history"])
        self.commands = list(state["commands"])
        self.stream_pair, self.stream_frame = state["stream_pair"].copy(), state["stream_frame"].copy()
        self.q, self.qd = state["q"].clone(), state["qd"].clone()

    def save(self, out: Path) -> None:
        """Checkpoint, weights and sidecar into ``out``."""
        with atomic_write(out / CHECKPOINT_FILE) as tmp:
            torch.save(self.state(), tmp)
        save_cycle(self.cycle, out / WEIGHTS_FILE)
        write_json(out / SIDECAR_FILE, self.sidecar())

    def sidecar(self) -> dict:
        def mean(rows: list[dict], key: str) -> float | None:
            return float(np.mean([r[key] for r in rows])) if rows else None
        n = min(20, len(self.history))
        first, last = self.history[:n], self.history[-n:]
        keys = ("l_dyn", "pose", "tau", "l_grf", "force", "smooth", "cone", "s_g", "stray_m")
        return {"format": SIDECAR_FORMAT, "commands": self.commands, "seed": self.config.seed, "steps": self.step,
                "wall_s": round(self.wall_s, 1), "frames_trained": self.step * self.config.batch * self.config.window,
                "clips": len({p.name.split(" (imu")[0] for p in self.pairs}), "pairs": len(self.pairs),
                "train_config": self.config.as_dict(), "cycle_config": config_to_dict(self.cycle.config),
                "parameters": {name: sum(p.numel() for p in net.parameters())
                               for name, net in (("dynet", self.cycle.dynet), ("grfnet", self.cycle.grfnet)) if net},
                "metrics": {f"{when}_{k}": mean(rows, k) for when, rows in (("first20", first), ("last20", last))
                            for k in keys}}


def train(config: TrainConfig, out: Path, minutes: float | None = None, steps: int | None = None,
          resume: bool = False, command: str | None = None, progress: bool = True) -> Trainer:
    """Train into ``out`` until ``steps`` total steps or ``minutes`` of this call's wall time
    (whichever first; at least one must be given); with ``resume``, continue the run in ``out``
    (its stored :class:`TrainConfig` is used). Returns the trainer."""
    if minutes is None and steps is None:
        raise ValueError("give a budget: --minutes and/or --steps")
    out = Path(out)
    state = None
    if not resume and ((out / CHECKPOINT_FILE).exists() or (out / WEIGHTS_FILE).exists()):
        raise ValueError(f"{out}: already holds a diff-PD model; pass --resume to continue it or pick a new --out")
    if resume:
        file = out / CHECKPOINT_FILE
        if not file.exists():
            raise FileNotFoundError(f"{file}: no checkpoint to resume")
        try:
            state = torch.load(file, map_location="cpu", weights_only=False)
        except Exception as err:  # torch raises many kinds on a damaged file
            raise ValueError(f"{file}: cannot read the checkpoint ({type(err).__name__}: {err})") from None
        if not isinstance(state, dict) or state.get("format") != CHECKPOINT_FORMAT:
            raise ValueError(f"{file}: not a diff-PD training checkpoint")
        stored = TrainConfig.from_dict(state["config"])
        ignored = [f.name for f in dataclasses.fields(TrainConfig)
                   if getattr(stored, f.name) != getattr(config, f.name)]
        if ignored:
            print(f"resuming {out} with its stored settings; ignoring the given {', '.join(ignored)}")
        config = stored
    trainer = Trainer(config, load_pairs(config))
    if state is not None:
        try:
            trainer.load_state(state)
        except (KeyError, RuntimeError, ValueError) as err:  # missing entries, weights of other shapes
            raise ValueError(f"{out / CHECKPOINT_FILE}: the checkpoint does not fit this trainer "
                             f"({type(err).__name__}: {str(err).splitlines()[0]})") from None
    if command:
        trainer.commands.append(command)
    start, start_step = time.perf_counter(), trainer.step
    budget_s = math.inf if minutes is None else 60.0 * minutes
    goal = math.inf if steps is None else steps
    bar = None
    if progress and tqdm is not None:
        bar = tqdm(total=None if steps is None else max(0, steps - trainer.step), desc="diff-PD training", unit="step")
    last_wall = start
    try:
        while trainer.step < goal and time.perf_counter() - start < budget_s:
            row = trainer.train_step()
            now = time.perf_counter()
            trainer.wall_s += now - last_wall
            last_wall = now
            if bar is not None:
                bar.update(1)
                bar.set_postfix(pose=f"{row['pose']:.4f}", force=f"{row['force']:.3f}", s_g=f"{row['s_g']:.2f}")
            if trainer.step % config.checkpoint_every == 0:
                trainer.save(out)
    finally:
        if bar is not None:
            bar.close()
        if trainer.step > start_step or not (out / WEIGHTS_FILE).exists():
            trainer.save(out)
    return trainer


def build_parser(prog: str | None = None) -> CliParser:
    d = TrainConfig()
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0],
                  formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--clips", nargs="+", default=list(d.clips), help="training SOURCE strings or clip sets")
    p.add_argument("--out", type=output_dir, default=Path("runs/diffpd"),
                   help="model directory (the shipped one is models/diffpd; an existing one needs --resume)")
    p.add_argument("--model", choices=("humanoid_1seg", "humanoid_2seg"), default=d.model)
    p.add_argument("--minutes", type=positive_float, default=None, help="wall-time budget of this call")
    p.add_argument("--steps", type=positive_int, default=None, help="stop at this many steps in total")
    p.add_argument("--resume", action="store_true", help="continue the run in --out (its stored settings)")
    p.add_argument("--seed", type=int, default=d.seed)
    p.add_argument("--window", type=positive_int, default=d.window, help="frames per BPTT window")
    p.add_argument("--batch", type=positive_int, default=d.batch, help="streams per step")
    p.add_argument("--lr", type=positive_float, default=d.lr)
    p.add_argument("--corrupted-fraction", type=fraction, default=d.corrupted_fraction)
    p.add_argument("--strength", type=non_negative_float, default=d.strength, help="IMU artefact strength")
    p.add_argument("--variants", type=positive_int, default=d.variants, help="corrupted copies per clip")
    p.add_argument("--dynet-hidden", type=positive_int, nargs=2, default=list(d.dynet_hidden))
    p.add_argument("--grfnet-hidden", type=positive_int, nargs=3, default=list(d.grfnet_hidden))
    p.add_argument("--contacts", choices=sorted(CONTACTS), default="corners",
                   help="contact points: the 8 sole corners or the 4 centre-line foot points")
    p.add_argument("--residual-bound", type=float, nargs=2, default=list(d.residual_bound), metavar=("N", "NM"),
                   help="bound of the root residual force: linear (N) and angular (N·m); inf: unbounded")
    p.add_argument("--no-slip-height", type=non_negative_float, default=d.no_slip_height,
                   help="contact points at most this high (m) stick (0: the paper's frictionless projection)")
    p.add_argument("--fixed-gains", action="store_true", help="train the baseline: no DyNet (s_g = 1/2, s_f = 0)")
    p.add_argument("--checkpoint-every", type=positive_int, default=d.checkpoint_every)
    p.add_argument("--threads", type=positive_int, default=1, help="torch threads")
    p.add_argument("--no-progress", action="store_true")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> dict:
    """Run the command line ``argv``; returns the sidecar."""
    argv = sys.argv[1:] if argv is None else argv
    args = build_parser(prog).parse_args(argv)
    torch.set_num_threads(args.threads)
    config = TrainConfig(clips=tuple(args.clips), model=args.model, window=args.window, batch=args.batch,
                         corrupted_fraction=args.corrupted_fraction, strength=args.strength, variants=args.variants,
                         lr=args.lr, dynet_hidden=tuple(args.dynet_hidden), grfnet_hidden=tuple(args.grfnet_hidden),
                         residual_bound=tuple(args.residual_bound), no_slip_height=args.no_slip_height,
                         contact_sites=CONTACTS[args.contacts], fixed_gains=args.fixed_gains, seed=args.seed,
                         checkpoint_every=args.checkpoint_every)
    command = "python agents/train_diffpd.py " + shlex.join(argv)
    trainer = train(config, args.out, args.minutes, args.steps, args.resume, command, not args.no_progress)
    sidecar = trainer.sidecar()
    m = sidecar["metrics"]
    print(f"wrote {args.out}: {trainer.step} steps, {trainer.wall_s:.0f} s; L_pose {m['first20_pose']:.4f} -> "
          f"{m['last20_pose']:.4f}, L_force {m['first20_force']:.4f} -> {m['last20_force']:.4f}")
    return sidecar


if __name__ == "__main__":
    main()
