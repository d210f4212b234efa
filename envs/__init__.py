"""Gymnasium environments of physmimic, registered on ``import envs``.

=====================  =====================================================================
id                     configuration (adapt §3.2, Table 4)
=====================  =====================================================================
``MimicIMU-v0``        ADAPT: full state (273-D), 8 key joints driven (20-D), trained on a
                       mix of clean and IMU-corrupted references (:class:`ArtefactMix`)
``MimicDReCon-v0``     DReCon ablation: the same terms over 6 key bodies only
``MimicFullAction-v0`` full-action ablation: every actuated hinge driven (43-D)
=====================  =====================================================================

All take the keyword arguments of :class:`envs.mimic.MimicEnv`.
"""

from gymnasium.envs.registration import register

from envs.config import ArtefactMix, MimicConfig
from envs.mimic import MimicEnv

__all__ = ["ArtefactMix", "MimicConfig", "MimicEnv", "ENV_IDS"]

ENV_IDS = ("MimicIMU-v0", "MimicDReCon-v0", "MimicFullAction-v0")

register(id="MimicIMU-v0", entry_point="envs.mimic:MimicEnv", kwargs={"artefacts": ArtefactMix()})
register(id="MimicDReCon-v0", entry_point="envs.mimic:MimicEnv",
         kwargs={"artefacts": ArtefactMix(), "obs_mode": "drecon"})
register(id="MimicFullAction-v0", entry_point="envs.mimic:MimicEnv",
         kwargs={"artefacts": ArtefactMix(), "action_mode": "full"})
