"""Round 30: how much a privileged critic reads its privileged inputs: the mean (and largest) L2 norm of its value
network's first-layer weight columns on the observation's columns against the privileged ones
(``agents.privileged_critic.PrivilegedCriticPolicy``: the first ``policy_inputs`` columns are the actor's observation,
the rest the critic's own), for each checkpoint named.

Usage: python bench/rounds/r30/critic_norms.py [--json OUT] NAME=CHECKPOINT.zip ...
(round 30: PV=runs/r29/ppo_pv/checkpoints/step_3500000.zip PV10_0.5M=runs/r29/ppo_pv10/checkpoints/step_500000.zip
PV10=runs/r29/ppo_pv10/checkpoints/step_4002912.zip; the runs are this machine's, not the repository's)
"""

import argparse
import json
from pathlib import Path

from stable_baselines3 import PPO

from agents.privileged_critic import PrivilegedCriticPolicy


def column_norms(checkpoint: Path) -> dict[str, float]:
    """The value network's first-layer column norms of ``checkpoint``, split at the actor's inputs."""
    policy = PPO.load(checkpoint, device="cpu").policy
    if not isinstance(policy, PrivilegedCriticPolicy):
        raise SystemExit(f"{checkpoint}: not a privileged critic's checkpoint (train_ppo.py --privileged-critic)")
    norms = policy.mlp_extractor.value_net[0].weight.detach().norm(dim=0)
    seen, privileged = norms[:policy.policy_inputs], norms[policy.policy_inputs:]
    return {"observation_mean": float(seen.mean()), "privileged_mean": float(privileged.mean()),
            "privileged_max": float(privileged.max()), "privileged_columns": int(privileged.numel())}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("checkpoints", nargs="+", metavar="NAME=CHECKPOINT.zip")
    p.add_argument("--json", type=Path)
    args = p.parse_args()
    rows = {}
    for item in args.checkpoints:
        name, _, path = item.partition("=")
        rows[name] = {"checkpoint": path, **column_norms(Path(path))}
        r = rows[name]
        print(f"{name}: observation column {r['observation_mean']:.3f}, privileged column {r['privileged_mean']:.3f} "
              f"(largest {r['privileged_max']:.2f}, {r['privileged_columns']} columns)")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
