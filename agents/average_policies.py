"""Average several policies into one: the weights of checkpoints of one training run, or (``--actions``)
the actions of policies of one task.

Usage::

    python agents/average_policies.py runs/stance_ppo/checkpoints/step_{4000000,4500000,5000000}.zip --out DIR
    python agents/average_policies.py models/mimic_general_stance_avg models/mimic_general_privileged \
        --actions --out DIR

**Weights** (stochastic weight averaging, Izmailov et al. 2018: an average of late iterates lies in
a flatter region of the loss than any one of them).
Every input is a policy directory or a run checkpoint (:func:`agents.policy.load_policy`) of the
same network. The output's weights are the element-wise mean of the inputs' (actor, critic and
exploration noise alike); its observation statistics pool the inputs' running means and variances
(:func:`pooled_statistics`), since each network was trained on observations normalised by its own.
Its sidecar is the last input's, with ``averaged_from`` naming the inputs.

**Actions** (an ensemble as one policy). Every input is a plain (not symmetric) tanh MLP of one
depth, trained in the same environment and normalising the observation with the same statistics
(a DAgger student keeps its teacher's, ``agents/distill.py``). The output's hidden layers hold the
inputs' side by side, ``K·h`` units wide for ``K`` inputs of ``h``: the first layer's rows stacked,
every deeper layer block-diagonal, so no unit reads another input's units. Its action and value
layers are the inputs' placed side by side and divided by ``K``. So its mean action is the mean of
the inputs' mean actions, exactly, before clipping to the action space (each input alone clips its
own first; the two differ only where an input asks for more than the space allows), its value the
mean of their values, and its exploration noise's log σ the mean of theirs: one policy that every
command takes (``evaluate.py``, ``clean.py``, ``--mirror-average``), at ``K`` times the network's
cost per step. Its sidecar is the last input's, with ``merged_from`` naming the inputs and
``ppo.net`` the wider layers.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

if __package__ in (None, ""):  # `python agents/average_policies.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from agents.policy import MimicPolicy, PolicyError, load_policy, save_loaded_policy
from agents.sidecar import PolicySidecar
from agents.train_ppo import policy_kwargs
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


def check_one_environment(policies: list[MimicPolicy], advice: str) -> None:
    """Raise :class:`PolicyError` naming the first of ``policies`` trained in another environment
    (the sidecar's env spec) than the first, ending with ``advice``."""
    names = [p.name for p in policies]
    envs = [PolicySidecar.from_dict(p.sidecar).env for p in policies]
    for env, name in zip(envs[1:], names[1:]):
        if env != envs[0]:
            raise PolicyError(f"{name}: trained in another environment than {names[0]} ({env} against {envs[0]}); "
                              f"{advice}")


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
    names = [p.name for p in policies]
    if len({p.model.observation_space.shape for p in policies}) > 1:
        raise PolicyError(f"the policies observe different spaces: {[p.model.observation_space.shape for p in policies]}")
    check_one_environment(policies, "average checkpoints of one run")
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


PROBE_CLIP = "deepmimic:walk"
"""A clip the merged model's environment is built on (any clip of the task: the weights do not depend on it)."""


def linear_layers(state: dict[str, torch.Tensor], branch: str) -> list[str]:
    """Parameter name prefixes (``mlp_extractor.policy_net.0``, …) of the linear layers of an SB3
    ``MlpExtractor`` branch (``policy_net`` or ``value_net``) in ``state``, input first."""
    prefix = f"mlp_extractor.{branch}."
    indices = sorted({int(k[len(prefix):].split(".")[0]) for k in state if k.startswith(prefix)})
    return [f"{prefix}{i}" for i in indices]


def hidden_sizes(state: dict[str, torch.Tensor], branch: str) -> list[int]:
    """Hidden layer widths of an SB3 ``MlpExtractor`` branch (``policy_net`` or ``value_net``)."""
    return [state[f"{layer}.weight"].shape[0] for layer in linear_layers(state, branch)]


def merged_weights(states: list[dict[str, torch.Tensor]]) -> dict[str, torch.Tensor]:
    """The state dict of the merged network (module docstring) of ``states``, SB3 ``MlpPolicy``
    state dicts of one architecture."""
    k = len(states)
    merged: dict[str, torch.Tensor] = {}
    for branch, head in (("policy_net", "action_net"), ("value_net", "value_net")):
        for depth, layer in enumerate(linear_layers(states[0], branch)):
            weights = [s[f"{layer}.weight"] for s in states]
            merged[f"{layer}.weight"] = torch.cat(weights) if depth == 0 else torch.block_diag(*weights)
            merged[f"{layer}.bias"] = torch.cat([s[f"{layer}.bias"] for s in states])
        merged[f"{head}.weight"] = torch.cat([s[f"{head}.weight"] for s in states], dim=1) / k
        merged[f"{head}.bias"] = torch.stack([s[f"{head}.bias"] for s in states]).mean(0)
    merged["log_std"] = torch.stack([s["log_std"] for s in states]).mean(0)
    return merged


def merge_policies(policies: list[MimicPolicy]) -> PPO:
    """The merged PPO model of ``policies`` (module docstring); :class:`PolicyError` names an
    input that cannot join: a symmetric network, another environment, other observation
    statistics, another architecture."""
    if len(policies) < 2:
        raise PolicyError(f"merging needs at least two policies, got {len(policies)}")
    check_one_environment(policies, "merge policies of one task")
    names = [p.name for p in policies]
    first = policies[0]
    states = [p.model.policy.state_dict() for p in policies]
    for policy, name, state in zip(policies, names, states):
        if policy.symmetric_network:
            raise PolicyError(f"{name}: trained as the symmetric actor (train_ppo.py --symmetric); merge plain "
                              "networks and ask for their symmetric actor with --mirror-average")
        stats, ref = policy.normalizer.obs_rms, first.normalizer.obs_rms
        if not (np.allclose(stats.mean, ref.mean) and np.allclose(stats.var, ref.var)):
            raise PolicyError(f"{name}: normalises observations with other statistics than {names[0]}; the merged "
                              "network reads one normalised observation (merge a DAgger student with its teacher, "
                              "or policies of one run)")
        shape = {key: tuple(value.shape) for key, value in state.items()}
        if shape != {key: tuple(value.shape) for key, value in states[0].items()}:
            raise PolicyError(f"{name}: a different network from {names[0]}; merge networks of one architecture")
    sizes = [len(policies) * h for h in hidden_sizes(states[0], "policy_net")]
    if sizes != [len(policies) * h for h in hidden_sizes(states[0], "value_net")]:
        raise PolicyError(f"{names[0]}: actor and critic of other widths; the merged network needs them alike")
    variance = float(np.exp(2 * torch.stack([s["log_std"] for s in states]).mean(0).numpy()).mean())
    env = first.make_env([PROBE_CLIP], artefacts=None)
    try:
        model = PPO("MlpPolicy", DummyVecEnv([lambda: env]), device="cpu", verbose=0,
                    policy_kwargs=policy_kwargs(",".join(map(str, sizes)), variance))
        model.policy.load_state_dict(merged_weights(states))
    finally:
        env.close()
    return model


def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("policies", nargs="+", help="policy directories or run checkpoints (RUN/checkpoints/step_N.zip)")
    p.add_argument("--actions", action="store_true",
                   help="average the policies' actions (one network holding them side by side), not their weights")
    p.add_argument("--out", type=output_dir, required=True, help="the averaged policy's directory")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the policy's directory."""
    args = build_parser(prog).parse_args(sys.argv[1:] if argv is None else argv)
    policies = [load_policy(path) for path in args.policies]
    sidecar = PolicySidecar.from_dict(policies[-1].sidecar)
    if args.actions:
        model, stats = merge_policies(policies), policies[-1].normalizer
        net = ",".join(map(str, hidden_sizes(model.policy.state_dict(), "policy_net")))
        sidecar = replace(sidecar, ppo=replace(sidecar.ppo, net=net), metrics={}, score=None,
                          extra={**sidecar.extra, "merged_from": list(args.policies),
                                 "lineage_note": f"the mean action of {len(policies)} policies as one network "
                                                 "(agents/average_policies.py --actions); training record: the "
                                                 "last one's"})
        done = f"the mean action of {len(policies)} policies, hidden layers {net}"
    else:
        model, stats = average_policies(policies)
        sidecar = replace(sidecar, metrics={}, score=None,
                          extra={**sidecar.extra, "averaged_from": list(args.policies),
                                 "lineage_note": f"weights averaged over {len(args.policies)} checkpoints "
                                                 "(agents/average_policies.py); steps and wall time are the "
                                                 "last one's"})
        done = f"the average of {len(policies)} policies"
    save_loaded_policy(args.out, model, stats, sidecar)
    print(f"{args.out}: {done}")
    return args.out


if __name__ == "__main__":
    main()
