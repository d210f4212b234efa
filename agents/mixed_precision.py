"""PPO whose updates run the networks' matrix products in bfloat16 (``train_ppo.py --update-precision bf16``).

On the project's 2-core machines a PPO update of the [256, 256] actor and critic is compute-bound:
about 9 ms of fp32 matrix products per minibatch of 512, a third of a training step's wall time
(``bench/ppo_throughput.py``). CPUs with AVX-512 BF16 (these have it) multiply bfloat16 matrices at
about twice the fp32 rate. :class:`BF16UpdatePPO` runs :meth:`PPO.train` under ``torch.autocast``:
linear layers take bfloat16 inputs and weights and accumulate in fp32, while the weights, Adam's
state, the losses and the log-probabilities stay fp32. Rollouts (the policy's actions while
collecting) are not affected.
"""

from __future__ import annotations

import torch
from stable_baselines3 import PPO

UPDATE_PRECISIONS = ("fp32", "bf16")
"""``train_ppo.py --update-precision`` choices."""


class BF16UpdatePPO(PPO):
    """:class:`stable_baselines3.PPO` with its updates under ``torch.autocast(dtype=torch.bfloat16)``
    on the model's device; everything else, saving and loading included, as PPO (a checkpoint of
    either loads into the other)."""

    def train(self) -> None:
        with torch.autocast(self.device.type, dtype=torch.bfloat16):
            super().train()


def ppo_class(precision: str) -> type[PPO]:
    """The PPO class of ``--update-precision`` ``precision`` (``"fp32"`` or ``"bf16"``)."""
    if precision not in UPDATE_PRECISIONS:
        raise ValueError(f"update precision must be one of {', '.join(UPDATE_PRECISIONS)}, got {precision!r}")
    return BF16UpdatePPO if precision == "bf16" else PPO
