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
weights and log-std: it is the source network with the toe inputs and outputs cut out, acting as
the source would with the cut inputs at their running mean. The ``MimicGait-v0`` toe targets stay
in the observation and read 0 on the one-segment foot (no toe hinge to bend), as in the
``no_toeref`` ablation, with the source's statistics: the carried policy starts as the source
would with straight-toe targets. What it does on the new body is not the source's behaviour (the
foot's mass, inertia and contacts changed); it is a start for per-sequence adaptation
(:mod:`agents.adaptation`) or ``train_ppo.py --init-from``.
"""

from __future__ import annotations

import shlex
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

from agents.policy import MimicPolicy, PolicyError, load_policy, save_policy
from agents.warm_start import FIRST_LAYERS, observation_normalizer
from envs.config import FOOT_MODELS
from envs.mimic import MimicEnv
from reference_motion.cli import CliParser, one_line_errors, output_dir

BODY_BLOCKS = ("p", "v", "dp", "dv")
"""Observation slices holding 3 entries per observed body, body by body (:mod:`envs.observations`)."""

ACTION_ROWS = ("action_net.weight", "action_net.bias", "log_std")
"""Parameters of SB3's ``MlpPolicy`` with one row (entry) per action component."""

KEPT_HYPERPARAMETERS = ("learning_rate", "n_steps", "batch_size", "n_epochs", "gamma", "gae_lambda", "clip_range",
                        "clip_range_vf", "normalize_advantage", "ent_coef", "vf_coef", "max_grad_norm", "use_sde",
                        "sde_sample_freq", "target_kl", "policy_kwargs", "seed")
"""The source PPO's settings the carried model is built with."""

LAYOUT_CLIP = ["deepmimic:walk"]
"""The clip the two environments are built on to read their layouts (which do not depend on it)."""


def driven_joint_names(env: MimicEnv) -> list[str]:
    """The actuator name of each action component of ``env`` (its ``driven`` actuators)."""
    return [mujoco.mj_id2name(env.model, mujoco.mjtObj.mjOBJ_ACTUATOR, int(a)) for a in env.driven]


def observed_body_names(env: MimicEnv) -> list[str]:
    """The name of each body in ``env``'s observation, in order."""
    return [str(n) for n in np.asarray(env.humanoid.body_names)[env.observed]]


def _name_index(source: list[str], target: list[str], what: str) -> np.ndarray:
    """Index into ``source`` of each name of ``target`` ``(len(target),)``; :class:`PolicyError`
    naming the ``what`` (bodies, joints) that ``target`` has and ``source`` lacks."""
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
    index = np.concatenate(index)
    if len(index) != target.observation_space.shape[0]:
        raise PolicyError(f"foot transfer: matched {len(index)} observation entries, the target observes "
                          f"{target.observation_space.shape[0]}")
    return index


def cut_network(state_dict: dict[str, torch.Tensor], inputs: np.ndarray, actions: np.ndarray) -> dict[str, torch.Tensor]:
    """A copy of an SB3 ``MlpPolicy`` ``state_dict`` that reads only observation entries ``inputs``
    ``(D_target,)`` int (columns of :data:`FIRST_LAYERS`) and outputs only action components
    ``actions`` ``(A_target,)`` int (rows of :data:`ACTION_ROWS`); every other parameter as it is."""
    out = dict(state_dict)
    for name in (*FIRST_LAYERS, *ACTION_ROWS):
        if name not in state_dict:
            raise PolicyError(f"foot transfer: the source policy has no {name!r}; not an SB3 MlpPolicy")
    for name in FIRST_LAYERS:
        out[name] = state_dict[name][:, torch.as_tensor(inputs)].clone()
    for name in ACTION_ROWS:
        out[name] = state_dict[name][torch.as_tensor(actions)].clone()
    return out


def transfer(source: MimicPolicy, foot: str, out: Path, command: str = "") -> MimicPolicy:
    """Write ``source`` carried to the ``foot`` humanoid (module docstring) as the policy directory
    ``out`` and return it loaded: a model with the target's spaces, the source's cut weights and
    PPO settings (:data:`KEPT_HYPERPARAMETERS`; a fresh optimizer: Adam's moments are not carried),
    the source's observation statistics for the inputs kept, and a sidecar of the target's task
    whose training record continues the source's (``init_from`` the source, ``command`` appended)."""
    if not source.sidecar:
        raise PolicyError(f"{source.name}: no sidecar.json, so its environment and foot are unknown; cannot carry it")
    if foot not in FOOT_MODELS:
        raise PolicyError(f"foot transfer: unknown foot {foot!r}; expected one of {tuple(FOOT_MODELS)}")
    if foot == source.foot:
        raise PolicyError(f"{source.name}: already a foot={foot!r} policy")
    if Path(out).resolve() == Path(source.path).resolve():
        raise PolicyError(f"{out}: is the source policy; write the carried policy elsewhere")
    task = replace(source.record.env, foot=foot)
    source_env, target_env = source.make_env(LAYOUT_CLIP), task.make(LAYOUT_CLIP)
    try:
        inputs = shared_inputs(source_env.unwrapped, target_env.unwrapped)
        actions = _name_index(driven_joint_names(source_env.unwrapped), driven_joint_names(target_env.unwrapped),
                              "driven joints")
        old = source.model
        if source.symmetric_network:
            raise PolicyError(f"{source.name}: a network trained as the symmetric actor; its mirror maps are those of "
                              f"the {source.foot}-foot task, so it cannot be carried to another foot")
        model = PPO(old.policy_class, DummyVecEnv([lambda: target_env]), device="cpu", verbose=0,
                    **{name: getattr(old, name) for name in KEPT_HYPERPARAMETERS})
        try:
            model.policy.load_state_dict(cut_network(old.policy.state_dict(), inputs, actions))
        except RuntimeError as err:  # torch names the parameter whose shape differs
            raise PolicyError(f"{source.name}: its network does not fit the {foot}-foot task once cut: {err}") from err
        normalizer = observation_normalizer(model.get_env(), old.gamma)
        normalizer.obs_rms = source.normalizer.obs_rms.copy()
        normalizer.obs_rms.mean, normalizer.obs_rms.var = normalizer.obs_rms.mean[inputs], normalizer.obs_rms.var[inputs]
        record = source.record
        training = replace(record.training, init_from=source.name,
                           commands=[*record.training.commands, *([command] if command else [])])
        sidecar = replace(record, env=task, training=training, metrics={}, score=None,
                          extra={"transferred_from": source.name})
        save_policy(Path(out), model, normalizer, sidecar)
    finally:
        source_env.close()
        target_env.close()
    return load_policy(out)


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the written directory."""
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("--policy", type=Path, required=True, help="the source policy directory")
    p.add_argument("--foot", choices=tuple(FOOT_MODELS), default="one", help="the humanoid to carry it to")
    p.add_argument("--out", type=output_dir, required=True, help="the policy directory to write")
    args = p.parse_args(argv)
    command = shlex.join(["python", "agents/foot_transfer.py", *(sys.argv[1:] if argv is None else argv)])
    transfer(load_policy(args.policy), args.foot, args.out, command)
    print(f"wrote {args.out}: {args.policy} on foot={args.foot!r}")
    return args.out


if __name__ == "__main__":
    main()
