"""Write a policy's mirror image: a network that acts on every observation as the source policy acts
on its mirror image, mapped back.

Usage::

    python agents/mirror_policy.py models/mimic_general_dashes --out runs/dashes_mirrored

Why: a policy trained on a clip and its mirror image may perform one side and not the other. On
DeepMimic's ``walker/turn_right0`` the plain actors of ``mimic_general_robust``, ``_480`` and
``_dashes`` perform the right turn (ELR 0.94–1.00) and none its mirror image, the left turn
(0.35–0.42), so their symmetric actors, which average the two, lose the take (0.50–0.63). The
mirror image of a policy that performs the right turn performs the left one exactly as well (the
environment is mirror symmetric, ``tests/test_mirror.py``): a teacher for the side no policy
learned (``agents/distill.py`` with a policy set routing ``"*(mirrored)*"`` copies to it).

The mirrored policy ``π'(o) = M_a π(M_o o)``, ``V'(o) = V(M_o o)`` (``M_o``, ``M_a``: the
observation's and the action's left/right maps, :class:`agents.mirror.MirrorMaps`, each a signed
permutation ``x[perm] * sign`` and its own inverse) is the same network with its weights moved, no
training: the observation statistics are permuted and the sign-flipped components' means negated
(the normalised mirrored observation is then the mirrored normalised observation, the clip range
being symmetric), the first layer's input columns of actor and critic permuted and signed alike,
and the actor's output rows and exploration ``log_std`` by the action map; the deeper layers stay.
Adam's moments are not carried (a fresh optimizer, as :mod:`agents.foot_transfer` does), so
fine-tuning the mirror image starts clean. Its sidecar is the source's with ``mirrored_from`` naming
the source, a ``lineage_note``, and no metrics or score (they were the source's).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

if __package__ in (None, ""):  # `python agents/mirror_policy.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from stable_baselines3.common.torch_layers import FlattenExtractor

from agents.foot_transfer import LAYOUT_CLIP
from agents.mirror import MirrorMaps
from agents.policy import MimicPolicy, PolicyError, load_policy, save_loaded_policy
from agents.sidecar import PolicySidecar
from agents.warm_start import FIRST_LAYERS
from reference_motion.cli import CliParser, one_line_errors, output_dir

ACTION_ROWS = ("action_net.weight", "action_net.bias", "log_std")
"""The parameters with one row per action component."""


def mirrored_weights(state: dict[str, torch.Tensor], maps: MirrorMaps) -> dict[str, torch.Tensor]:
    """The state dict of the mirrored network (the module's equation) from ``state``, an SB3
    ``MlpPolicy``'s with separate actor and critic (first layers :data:`~agents.warm_start.FIRST_LAYERS`
    ``(H, D)``, ``action_net`` ``(A, H)`` and ``(A,)``, ``log_std`` ``(A,)``), reading normalised
    observations mirrored as ``maps`` says (each map its own inverse, which :class:`MirrorMaps` checks)."""
    missing = [k for k in (*FIRST_LAYERS, *ACTION_ROWS) if k not in state]
    if missing:
        raise PolicyError(f"not an MLP actor-critic with separate actor and critic: no {', '.join(missing)}")
    out = dict(state)
    obs_perm, obs_sign = torch.as_tensor(maps.obs_perm), torch.as_tensor(maps.obs_sign)
    act_perm, act_sign = torch.as_tensor(maps.action_perm), torch.as_tensor(maps.action_sign)
    for key in FIRST_LAYERS:
        w = state[key]
        if w.shape[1] != len(obs_perm):
            raise PolicyError(f"{key} reads {w.shape[1]} inputs; the mirror maps an observation of {len(obs_perm)}")
        out[key] = (w * obs_sign.to(w.dtype))[:, obs_perm]
    for key in ACTION_ROWS:
        w = state[key]
        if w.shape[0] != len(act_perm):
            raise PolicyError(f"{key} has {w.shape[0]} rows; the mirror maps an action of {len(act_perm)}")
        sign = act_sign.to(w.dtype).reshape(-1, *([1] * (w.dim() - 1)))
        out[key] = w[act_perm] if key == "log_std" else w[act_perm] * sign
    return out


def mirrored_statistics(mean: np.ndarray, var: np.ndarray, maps: MirrorMaps) -> tuple[np.ndarray, np.ndarray]:
    """The observation statistics ``(D,)`` mean and variance under which the mirrored raw
    observation normalises to the mirror image of the normalised one."""
    return maps.observation(mean), var[maps.obs_perm]


def mirror_policy(policy: MimicPolicy, source: str) -> MimicPolicy:
    """``policy``'s mirror image (the module's equation), ``source`` naming it (a directory or
    checkpoint) in the sidecar and errors. **In place:** ``policy``'s model and statistics objects
    are the returned policy's, their weights and statistics moved, with a fresh optimizer."""
    if policy.symmetric_network:
        raise PolicyError(f"{source}: trained as the symmetric actor (train_ppo.py --symmetric), which is its own "
                          f"mirror image")
    extractor = policy.model.policy.features_extractor
    if not isinstance(extractor, FlattenExtractor) or not policy.model.policy.share_features_extractor:
        raise PolicyError(f"{source}: its network reads the observation through a {type(extractor).__name__}; only "
                          f"an MLP actor-critic on the flat observation can be mirrored")
    try:
        maps = policy.mirror_averaged_on(LAYOUT_CLIP[0]).mirror  # the maps depend on the task, not the clip
        state = mirrored_weights(policy.model.policy.state_dict(), maps)
    except ValueError as err:  # PolicyError, or MirrorMaps refusing an observation layout or a map
        raise PolicyError(f"{source}: cannot be mirrored: {err}") from err
    net = policy.model.policy
    net.load_state_dict(state)
    net.optimizer = net.optimizer_class(net.parameters(), lr=net.optimizer.param_groups[0]["lr"],
                                        **net.optimizer_kwargs)
    rms = policy.normalizer.obs_rms
    rms.mean, rms.var = mirrored_statistics(rms.mean, rms.var, maps)
    sidecar = PolicySidecar.from_dict(policy.sidecar)
    sidecar = replace(sidecar, metrics={}, score=None,
                      extra={**sidecar.extra, "mirrored_from": source,
                             "lineage_note": "the mirror image of the policy in mirrored_from "
                                             "(agents/mirror_policy.py); no training"})
    return replace(policy, sidecar=sidecar.to_dict())


def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("policy", help="a policy directory or a run checkpoint (RUN/checkpoints/step_N.zip)")
    p.add_argument("--out", type=output_dir, required=True, help="the mirrored policy's directory")
    return p


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> Path:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the policy's directory."""
    args = build_parser(prog).parse_args(sys.argv[1:] if argv is None else argv)
    mirrored = mirror_policy(load_policy(args.policy), str(args.policy))
    save_loaded_policy(args.out, mirrored.model, mirrored.normalizer, mirrored.record)
    print(f"{args.out}: the mirror image of {args.policy}")
    return args.out


if __name__ == "__main__":
    main()
