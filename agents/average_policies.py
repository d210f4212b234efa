"""Average the weights of several checkpoints of one training run into a policy (stochastic
weight averaging, Izmailov et al. 2018: an average of late iterates lies in a flatter region of
the loss than any one of them).

Usage::

    python agents/average_policies.py runs/stance_ppo/checkpoints/step_{4000000,4500000,5000000}.zip --out DIR

Every input is a policy directory or a run checkpoint (:func:`agents.policy.load_policy`) of the
same network. The output's weights are the element-wise mean of the inputs' (actor, critic and
exploration noise alike); its observation statistics pool the inputs' running means and variances
(:func:`pooled_statistics`), since each network was trained on observations normalised by its own.
Its sidecar is the last input's, with ``averaged_from`` naming the inputs.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecNormalize

if __package__ in (None, ""):  # `python agents/average_policies.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents.policy import MimicPolicy, PolicyError, load_policy, save_loaded_policy
from agents.sidecar import PolicySidecar
from reference_motion.cli import CliParser, one_line_errors, output_dir


def averaged_weights(states: list[dict[str, torch.Tensor]], names: list[str]) -> dict[str, torch.Tensor]:
    """The element-wise mean of the ``states`` (``torch`` state dicts of one architecture);
    ``names`` label them in the error raised when their parameters differ in name or shape."""
    first = states[0]
    expected = {k: tuple(v.shape) for k, v in first.items()}
    for state, name in zip(states[1:], names[1:]):
        shapes = {k: tuple(v.shape) for k, v in state.items()}
        if shapes != expected:
            differing = sorted(k for k in set(shapes) | set(expected) if shapes.get(k) != expected.get(k))
            raise PolicyError(f"{name}: a different network from {names[0]} (parameters {differing[:4]} differ); "
                              f"only checkpoints of one architecture can be averaged")
    return {k: torch.stack([s[k].float() for s in states]).mean(0).to(first[k].dtype) for k in first}


def pooled_statistics(means: np.ndarray, variances: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mean ``(D,)`` and variance ``(D,)`` of an equal mixture of distributions with the
    given ``means`` and ``variances`` ``(K, D)``: E[x] and E[x²] − E[x]²."""
    mean = means.mean(0)
    return mean, (variances + means ** 2).mean(0) - mean ** 2


def average_policies(policies: list[MimicPolicy]) -> tuple[PPO, VecNormalize]:
    """The averaged PPO model and the pooled observation statistics: the last policy's model and
    ``VecNormalize`` objects, their weights and statistics replaced in place."""
    if len(policies) < 2:
        raise PolicyError(f"averaging needs at least two policies, got {len(policies)}")
    names = [str(p.path) for p in policies]
    if len({p.model.observation_space.shape for p in policies}) > 1:
        raise PolicyError(f"the policies observe different spaces: {[p.model.observation_space.shape for p in policies]}")
    envs = [PolicySidecar.from_dict(p.sidecar).env for p in policies]
    for env, name in zip(envs[1:], names[1:]):
        if env != envs[0]:
            raise PolicyError(f"{name}: trained in another environment than {names[0]} ({env} against {envs[0]}); "
                              f"average checkpoints of one run")
    symmetric = [name for p, name in zip(policies, names) if p.symmetric_network]
    if 0 < len(symmetric) < len(policies):
        raise PolicyError(f"{', '.join(symmetric)}: trained as the symmetric actor (train_ppo.py --symmetric), the "
                          f"others not; average checkpoints of one run")
    model = policies[-1].model
    model.policy.load_state_dict(averaged_weights([p.model.policy.state_dict() for p in policies], names))
    stats = policies[-1].normalizer
    for attr in ("obs_rms", "ret_rms"):
        rms = getattr(stats, attr)
        rms.mean, rms.var = pooled_statistics(np.stack([getattr(p.normalizer, attr).mean for p in policies]),
                                              np.stack([getattr(p.normalizer, attr).var for p in policies]))
    return model, stats


def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("policies", nargs="+", help="policy directories or run checkpoints (RUN/checkpoints/step_N.zip)")
    p.add_argument("--out", type=output_dir, required=True, help="the averaged policy's directory")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the policy's directory."""
    args = build_parser(prog).parse_args(sys.argv[1:] if argv is None else argv)
    policies = [load_policy(path) for path in args.policies]
    model, stats = average_policies(policies)
    sidecar = PolicySidecar.from_dict(policies[-1].sidecar)
    sidecar = replace(sidecar, metrics={}, score=None,
                      extra={**sidecar.extra, "averaged_from": list(args.policies),
                             "lineage_note": f"weights averaged over {len(args.policies)} checkpoints "
                                             f"(agents/average_policies.py); steps and wall time are the last one's"})
    save_loaded_policy(args.out, model, stats, sidecar)
    print(f"{args.out}: the average of {len(policies)} policies")
    return args.out


if __name__ == "__main__":
    main()
