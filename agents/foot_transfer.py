"""Carry a policy to a humanoid with fewer bodies and joints: a ``humanoid_2seg`` policy onto
``humanoid_1seg`` (ContactVision Fig. 12's one-segment-foot ablation, adapted per sequence from
the same weights as the other ablations).

Usage::

    python agents/foot_transfer.py --policy models/mimic_gait_ff --foot one --out runs/gait_ff_one

The two observations hold the same quantities for the bodies and driven joints both models share
(:mod:`envs.observations`), in the same order; the one-segment model lacks the toe bodies (their
``p``, ``v``, ``dp``, ``dv`` entries) and the toe hinges (their ``prev_action`` entries and action
outputs). The transferred network keeps, for every input it still gets, the source's first-layer
weights and observation statistics, and for every action it still outputs, the source's output
weights and log-std: it is the source network with the toe inputs and outputs cut out. What it
does on the new body is not the source's behaviour (the foot's mass, inertia and contacts
changed); it is a start for per-sequence adaptation (:mod:`agents.adaptation`) or
``train_ppo.py --init-from``.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv

if __package__ in (None, ""):  # `python agents/foot_transfer.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents.policy import MODEL_FILE, SIDECAR_FILE, STATS_FILE, MimicPolicy, PolicyError, load_policy
from agents.warm_start import FIRST_LAYERS, observation_normalizer
from envs.config import FOOT_MODELS
from envs.mimic import MimicEnv
from reference_motion.cli import CliParser, one_line_errors, output_dir

BODY_BLOCKS = ("p", "v", "dp", "dv")
"""Observation slices holding 3 entries per observed body, body by body (:mod:`envs.observations`)."""

ACTION_ROWS = ("action_net.weight", "action_net.bias", "log_std")
"""Parameters of SB3's ``MlpPolicy`` with one row (entry) per action component."""

SOURCE_ONLY = ("name", "evaluation", "evaluate_command", "training_wall_s_total", "training_steps_total")
"""Sidecar entries ``agents/ship.py`` adds that describe the source as shipped, not the transferred policy."""


def driven_joint_names(env: MimicEnv) -> list[str]:
    """The actuator name of each action component of ``env`` (its ``driven`` actuators)."""
    return [mujoco.mj_id2name(env.model, mujoco.mjtObj.mjOBJ_ACTUATOR, int(a)) for a in env.driven]


def observed_body_names(env: MimicEnv) -> list[str]:
    """The name of each body in ``env``'s observation, in order."""
    return [str(n) for n in np.asarray(env.humanoid.body_names)[env.observed]]


def _name_index(source: list[str], target: list[str], what: str) -> np.ndarray:
    missing = [n for n in target if n not in source]
    if missing:
        raise PolicyError(f"foot transfer: the target has {what} the source lacks ({missing}); only dropping is possible")
    return np.array([source.index(n) for n in target], dtype=int)


def shared_inputs(source: MimicEnv, target: MimicEnv) -> np.ndarray:
    """Index into ``source``'s observation of each entry of ``target``'s observation ``(D_target,)``:
    per-body blocks matched by body name, ``prev_action`` by joint name, every other slice as it
    is. Raises :class:`PolicyError` when the layouts name different slices, a slice other than
    those differs in size, or ``target`` observes a body or joint ``source`` does not."""
    src, tgt = source.obs_slices, target.obs_slices
    if list(src) != list(tgt):
        raise PolicyError(f"foot transfer: the observations differ in layout ({list(src)} vs {list(tgt)})")
    bodies = _name_index(observed_body_names(source), observed_body_names(target), "bodies")
    joints = _name_index(driven_joint_names(source), driven_joint_names(target), "driven joints")
    index = []
    for name, s in src.items():
        if name in BODY_BLOCKS:
            index.append(s.start + (3 * bodies[:, None] + np.arange(3)).ravel())
        elif name == "prev_action":
            index.append(s.start + joints)
        elif s.stop - s.start != tgt[name].stop - tgt[name].start:
            raise PolicyError(f"foot transfer: observation slice {name!r} has {s.stop - s.start} entries in the source "
                              f"and {tgt[name].stop - tgt[name].start} in the target")
        else:
            index.append(np.arange(s.start, s.stop))
    return np.concatenate(index)


def cut_network(state_dict: dict[str, torch.Tensor], inputs: np.ndarray, actions: np.ndarray) -> dict[str, torch.Tensor]:
    """A copy of an SB3 ``MlpPolicy`` ``state_dict`` that reads only observation entries ``inputs``
    (columns of :data:`FIRST_LAYERS`) and outputs only action components ``actions`` (rows of
    :data:`ACTION_ROWS`); every other parameter as it is."""
    out = dict(state_dict)
    for name in (*FIRST_LAYERS, *ACTION_ROWS):
        if name not in state_dict:
            raise PolicyError(f"foot transfer: the source policy has no {name!r}; not an SB3 MlpPolicy")
    for name in FIRST_LAYERS:
        out[name] = state_dict[name][:, torch.as_tensor(inputs)].clone()
    for name in ACTION_ROWS:
        out[name] = state_dict[name][torch.as_tensor(actions)].clone()
    return out


def transfer(source: MimicPolicy, foot: str) -> MimicPolicy:
    """``source`` carried to the ``foot`` humanoid (module docstring): a policy in memory whose
    model has the target's spaces and the source's hyperparameters, the source's observation
    statistics for the inputs kept, and a sidecar naming the new foot and where it came from
    (``transferred_from``); its ``path`` is still the source's until :func:`save` writes it."""
    if foot not in FOOT_MODELS:
        raise PolicyError(f"foot transfer: unknown foot {foot!r}; expected one of {tuple(FOOT_MODELS)}")
    if foot == source.foot:
        raise PolicyError(f"{source.path}: already a foot={foot!r} policy")
    clip = source.record.training.clips[:1] or ["deepmimic:walk"]
    task = replace(source.record.env, foot=foot)
    source_env, target_env = source.make_env(clip).unwrapped, task.make(clip)
    inputs = shared_inputs(source_env, target_env.unwrapped)
    actions = _name_index(driven_joint_names(source_env), driven_joint_names(target_env.unwrapped), "driven joints")
    old = source.model
    model = PPO("MlpPolicy", DummyVecEnv([lambda: target_env]), learning_rate=old.learning_rate, n_steps=old.n_steps,
                batch_size=old.batch_size, n_epochs=old.n_epochs, gamma=old.gamma, gae_lambda=old.gae_lambda,
                clip_range=old.clip_range, ent_coef=old.ent_coef, vf_coef=old.vf_coef, max_grad_norm=old.max_grad_norm,
                target_kl=old.target_kl, policy_kwargs=old.policy_kwargs, device="cpu", verbose=0)
    model.policy.load_state_dict(cut_network(old.policy.state_dict(), inputs, actions))
    normalizer = observation_normalizer(model.get_env(), old.gamma)
    rms = source.normalizer.obs_rms.copy()
    rms.mean, rms.var = rms.mean[inputs], rms.var[inputs]
    normalizer.obs_rms = rms
    record = source.record
    kept = {k: v for k, v in record.extra.items() if k not in SOURCE_ONLY}
    sidecar = replace(record, env=task, metrics={}, score=None,
                      extra={**kept, "transferred_from": str(source.path), "transferred_to_foot": foot})
    source_env.close()
    return MimicPolicy(source.path, model, normalizer, sidecar.to_dict())


def save(policy: MimicPolicy, out: Path) -> Path:
    """Write ``policy`` as a policy directory ``out`` (model, statistics, sidecar)."""
    out.mkdir(parents=True, exist_ok=True)
    policy.model.save(out / MODEL_FILE)
    policy.normalizer.save(str(out / STATS_FILE))
    policy.record.save(out / SIDECAR_FILE)
    return out


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the written directory."""
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", type=Path, required=True, help="the source policy directory")
    p.add_argument("--foot", choices=tuple(FOOT_MODELS), default="one", help="the humanoid to carry it to")
    p.add_argument("--out", type=output_dir, required=True, help="the policy directory to write")
    args = p.parse_args(argv)
    policy = transfer(load_policy(args.policy), args.foot)
    policy.sidecar["transfer_command"] = " ".join(["python agents/foot_transfer.py", *(sys.argv[1:] if argv is None else argv)])
    out = save(policy, args.out)
    print(f"wrote {out}: {args.policy} on foot={args.foot!r}")
    return out


if __name__ == "__main__":
    main()
