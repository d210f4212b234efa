"""Reconstruct a walk under physics with the two-segment foot: ContactVision's pipeline end to end.

Usage::

    python agents/reconstruct_gait.py library:data/library#dataset-1_walk_old_001 \\
        --policy models/mimic_gait --out out/walk_old.npz [--bvh out/walk_old.bvh] \\
        [--video out/walk_old.mp4] [--json out/walk_old.json] [--no-adapt]

Contacts → toe targets → a policy adapted to the clip → the simulated motion (contactvision §6.4):
the contact targets ĉ of the clip come from the policy's perception source (its sidecar's
``contacts``: VGRFNet on the reference's joints, or the ContactTransformer on its keypoints), the
ToeRefEstimator turns them into toe targets, the ``MimicGait-v0`` policy is fine-tuned on the clip
(:mod:`agents.adaptation`, per sequence as :data:`GAIT_ADAPTATION` says unless the ``--adapt-*``
options say otherwise, cached; ``--no-adapt`` skips it) and re-performs it as
``agents/clean.py`` does (rewind-and-retry, re-anchoring only as a last resort). Printed and
written with ``--json``: the joint-angle RMSE against the gait reference, the F1 of the simulated
contacts against ĉ, the push-offs (peak toe dorsiflexion and its timing against the ToeRef
target), the forward displacement error, and the gait parameters (stance, swing, single and
double support) of the simulated contacts against those of ĉ. ``--video`` shows the gait
reference (toes bent by the targets) beside the simulation, over a timeline of ĉ and the
simulated contacts.
"""

from __future__ import annotations

import sys
from dataclasses import asdict
from pathlib import Path

if __package__ in (None, ""):  # `python agents/reconstruct_gait.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

import envs  # noqa: F401  (registers the ids)
from agents.adaptation import AdaptConfig
from agents.clean import (adapt_to_clip, build_parser as clean_parser, clean_config, clean_motion, load_clip,
                          performing_policy, print_performance, reanchor_marks)
from agents.gait_metrics import (PushOff, contact_f1, forward_displacement_error, joint_angle_rmse_deg,
                                 simulated_contacts, summarize_push_offs, toe_push_off)
from agents.policy import MimicPolicy, PolicyError, load_policy
from agents.sidecar import GAIT_ENV_ID
from envs.config import FOOT_MODELS, TOE_BODIES
from perception.gait import gait_parameters, gait_phases
from reference_motion.atomic import atomic_write, write_json
from reference_motion.bvh_export import write_bvh
from reference_motion.cli import CliParser, one_line_errors, output_file
from reference_motion.humanoid.model import CONTACT_CHANNELS, load_model
from reference_motion.motion import Motion
from reference_motion.render import render, render_frames

TIMELINE_HEIGHT_PX = 150
"""Height of the contact timeline under the video."""


GAIT_ADAPTATION = AdaptConfig(budget_s=1200.0, target_sr90=None, action_variance=0.03, keep="performance")
"""How a gait policy is adapted to the walk it reconstructs, unless the command line says otherwise:
ContactVision trains a policy per sequence, so the adaptation does not stop once the walk is
survived (``clean.py``'s default) but trains to a 1200-s budget (20 min of one core for a 10-s
walk; the six test walks reach joint RMSE 2.79° and contact F1 0.874 with it, 3.21° / 0.833 after
600 s), keeping the chunk whose performance of the whole walk re-anchors least, then recovers
least, then earns the highest reward (``keep="performance"``: ranked by evaluations from reference
states instead, a held-out walk kept the chunk after 82k of 695k steps, 4.22° where the last chunk
gave 3.23°; on both validation walks the two rules kept chunks as good, 3.37° / 2.55° against
3.31° / 2.49°, within the 0.4° two runs differ by), with exploration noise σ² 0.03 rad² (ADAPT's, as
in training) at the policy's own learning rate. σ² was chosen at 600 s on both validation walks
(walk_happy_001 / 002): σ² 0.03 reached joint RMSE 3.31° / 2.49° (a repeat on 001: 3.40°), σ² 0.01
3.81° / 2.95° (it led at 300 s: 3.75° against 3.92°). The rate was compared at σ² 0.01 only, on
walk_happy_001: 3e-4 unlearned (4.37°), 5e-5 learned more slowly (3.63°) than the policy's own
1e-4 (README, "Gait reconstruction")."""


def build_parser(prog: str | None = None) -> CliParser:
    """``agents/clean.py``'s options (adaptation defaults: :data:`GAIT_ADAPTATION`); ``--policy``
    must be a ``MimicGait-v0`` policy."""
    p = clean_parser(prog, method=False)
    p.description = __doc__.split("\n\n")[0]
    p.set_defaults(adapt_budget_s=GAIT_ADAPTATION.budget_s, adapt_target=GAIT_ADAPTATION.target_sr90,
                   adapt_variance=GAIT_ADAPTATION.action_variance, adapt_lr=GAIT_ADAPTATION.learning_rate,
                   adapt_keep=GAIT_ADAPTATION.keep)
    p.add_argument("--push-off-strip", type=output_file(".png"),
                   help="a close-up frame strip of the feet through the simulation's strongest push-off")
    return p


STRIP_FRAMES = 7
"""Frames in a push-off strip, spread from the toe target's rise to 4 frames after it ends."""


def push_off_strip(simulated: Motion, push_offs: list[PushOff], path: Path) -> Path:
    """Write a side-view close-up of the feet (``STRIP_FRAMES`` frames side by side) through the push-off of
    ``push_offs`` with the largest simulated toe angle, after the first 30 frames."""
    later = [p for p in push_offs if p.start >= 30] or push_offs
    if not later:
        raise ValueError(f"{simulated.name}: no push-off (the toe targets never rise): nothing to show in a strip")
    best = max(later, key=lambda p: p.peak_deg)
    frames = np.linspace(best.start, min(best.stop + 4, simulated.n_frames - 1), STRIP_FRAMES).round().astype(int)
    still = simulated.with_qpos(simulated.qpos[frames], loop=False)
    images = render_frames(still, width=320, height=240, fps=still.fps, distance=1.5, elevation=-5.0,
                           lookat_height=0.35)
    with atomic_write(path) as tmp:
        import imageio.v2 as imageio
        imageio.imwrite(tmp, np.concatenate(list(images), axis=1), format="png")
    return path


def gait_targets(policy: MimicPolicy, reference: Motion) -> tuple[np.ndarray, np.ndarray, Motion]:
    """``(ĉ (T, 4) bool, toe targets (T, 2) rad, gait reference)`` of ``reference`` as ``policy``'s
    task sees it: the contacts from its perception source, the ToeRefEstimator's toe angles, and
    the clip with its toes so bent."""
    env = policy.make_env([reference], artefacts=None)
    base = env.unwrapped
    out = base.contact_targets[0], base.toe_targets[0], base.clips[0]
    env.close()
    return out


def reconstruction_metrics(simulated: Motion, gait_reference: Motion, targets: np.ndarray,
                           toe_targets: np.ndarray) -> dict:
    """Everything the command reports about ``simulated`` against ``gait_reference`` (same frames),
    the contact targets ``targets`` (T, 4) and ``toe_targets`` (T, 2) rad (see the module docstring)."""
    contacts = simulated_contacts(simulated)
    joints = load_model(simulated.model).body_joints
    push_offs = []
    if all(b in joints for b in TOE_BODIES):  # humanoid_2seg: the toe hinges' angles
        push_offs = toe_push_off(simulated.qpos[:, [joints[b].qpos_index[0] for b in TOE_BODIES]], toe_targets)
    target_parameters = gait_parameters(gait_phases(targets)).as_dict()
    simulated_parameters = gait_parameters(gait_phases(contacts)).as_dict()
    return {
        "frames": simulated.n_frames,
        "joint_rmse_deg": joint_angle_rmse_deg(simulated.qpos[:, 7:], gait_reference.qpos[:, 7:]),
        "contact_f1": contact_f1(contacts, targets),
        "contact_f1_per_channel": {c: contact_f1(contacts[:, i:i + 1], targets[:, i:i + 1])
                                   for i, c in enumerate(CONTACT_CHANNELS)},
        "push_off": summarize_push_offs(push_offs, simulated.fps).as_dict(),
        "push_offs": [asdict(p) for p in push_offs],
        "forward_displacement_error": forward_displacement_error(simulated.qpos[:, :3], gait_reference.qpos[:, :3]),
        "gait_parameters": {"simulated": simulated_parameters, "targets": target_parameters},
        "contacts": {"simulated": contacts.astype(int).tolist(), "targets": np.asarray(targets).astype(int).tolist()},
    }


def contact_timeline(targets: np.ndarray, contacts: np.ndarray, width: int, height: int = TIMELINE_HEIGHT_PX) -> np.ndarray:
    """``(height, width, 3)`` uint8: one row pair per contact channel, the target ĉ (grey) above the
    simulated contact (blue), time from the left edge (first frame) to the right (last frame)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(width / 100, height / 100), dpi=100)
    ax = fig.add_axes((0, 0, 1, 1))
    n = len(targets)
    for i, name in enumerate(CONTACT_CHANNELS):
        y = 2 * (len(CONTACT_CHANNELS) - 1 - i)
        for row, values, colour in ((y + 1, targets[:, i], "0.55"), (y, contacts[:, i], "tab:blue")):
            on = np.flatnonzero(values)
            ax.bar(on, 0.8, width=1.0, bottom=row + 0.1, color=colour, align="edge", linewidth=0)
        ax.text(3, y + 1.05, f"{name.replace('_', ' ')}: target / simulated", fontsize=7, va="center",
                bbox={"facecolor": "white", "alpha": 0.75, "linewidth": 0, "pad": 1})
    ax.set_xlim(0, n)
    ax.set_ylim(0, 2 * len(CONTACT_CHANNELS))
    ax.axis("off")
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
    plt.close(fig)
    return image


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> dict:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the report."""
    args = build_parser(prog).parse_args(argv)
    policy = load_policy(args.policy)
    if policy.env_id != GAIT_ENV_ID:
        raise PolicyError(f"{args.policy}: a {policy.env_id} policy; gait reconstruction needs a {GAIT_ENV_ID} "
                          f"policy (agents/train_ppo.py --env-id {GAIT_ENV_ID})")
    policy = performing_policy(policy, args)
    reference = load_clip(FOOT_MODELS[policy.foot], args)
    config = clean_config(policy, reference, args)
    targets, toe_targets, gait_reference = gait_targets(policy, reference)
    adaptation = adapt_to_clip(policy, reference, args)
    simulated = clean_motion(adaptation.policy if adaptation else policy, reference, config)
    simulated.save(args.out)
    print_performance(simulated, args.out)
    metrics = reconstruction_metrics(simulated, gait_reference, targets, toe_targets)
    push, params = metrics["push_off"], metrics["gait_parameters"]
    print(f"joint-angle RMSE {metrics['joint_rmse_deg']:.2f} deg; contact F1 {metrics['contact_f1']:.3f}; "
          f"forward displacement error {metrics['forward_displacement_error']:.1%}")
    print(f"push-offs: {push['count']}, peak toe angle {push['peak_deg']:.1f} deg (target {push['target_peak_deg']:.1f}), "
          f"peak {push['timing_ms']:+.0f} ms from the target's")
    print(f"{'gait parameter':<16}{'simulated':>10}{'targets':>10}")
    for k in ("stance", "swing", "single_support", "double_support"):
        print(f"{k:<16}{params['simulated'][k]:>10.3f}{params['targets'][k]:>10.3f}")
    if args.bvh:
        print(f"wrote {write_bvh(simulated, args.bvh)}")
    if args.push_off_strip:
        print(f"wrote {push_off_strip(simulated, [PushOff(**p) for p in metrics['push_offs']], args.push_off_strip)}")
    if args.video:
        width = 480
        footer = contact_timeline(targets, np.array(metrics["contacts"]["simulated"], bool), 2 * width)
        marked = [None, reanchor_marks(simulated)]
        print(f"wrote {render([gait_reference, simulated], args.video, width=width, marked=marked, progress=True, footer=footer)}")
    result = {"source": args.source, "policy": str(args.policy), "contacts_from": policy.record.env.contacts,
              "simulated_fraction": simulated.source["simulated_fraction"],
              "reanchors": simulated.source["reanchors"], "recoveries": simulated.source["recoveries"],
              "adaptation": adaptation.as_dict() if adaptation else None, **metrics}
    if args.json:
        write_json(args.json, result)
    return result


if __name__ == "__main__":
    main()
