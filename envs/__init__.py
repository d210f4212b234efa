"""Gymnasium environments of physmimic, registered on ``import envs``.

=====================  =====================================================================
id                     configuration
=====================  =====================================================================
``MimicIMU-v0``        ADAPT (adapt §3.2, Table 4): full state (273-D), 8 key joints driven
                       (20-D), trained on a mix of clean and IMU-corrupted references
                       (:class:`ArtefactMix`)
``MimicDReCon-v0``     DReCon ablation: the same terms over 6 key bodies only
``MimicFullAction-v0`` full-action ablation: every actuated hinge driven (43-D)
``MimicGait-v0``       ContactVision reconstruction (contactvision §6.4, App. C) on
                       ``humanoid_2seg``: contact targets from perception, toe targets from
                       the ToeRefEstimator, key joints and toes driven (22-D), reward
                       R = Σ w_k r_k with the contact-xor term (:class:`GaitConfig`)
=====================  =====================================================================

The first three take the keyword arguments of :class:`envs.mimic.MimicEnv`; ``MimicGait-v0``
those of :class:`envs.gait.MimicGaitEnv`. Importing ``envs`` imports neither torch nor
``perception``: the gait env loads its contact networks when it first needs them.
"""

from gymnasium.envs.registration import register

from envs.config import ArtefactMix, GaitConfig, MimicConfig
from envs.gait import MimicGaitEnv
from envs.mimic import MimicEnv

__all__ = ["ArtefactMix", "GaitConfig", "MimicConfig", "MimicEnv", "MimicGaitEnv", "ENV_IDS"]

ENV_IDS = ("MimicIMU-v0", "MimicDReCon-v0", "MimicFullAction-v0", "MimicGait-v0")

register(id="MimicIMU-v0", entry_point="envs.mimic:MimicEnv", kwargs={"artefacts": ArtefactMix()})
register(id="MimicDReCon-v0", entry_point="envs.mimic:MimicEnv",
         kwargs={"artefacts": ArtefactMix(), "obs_mode": "drecon"})
register(id="MimicFullAction-v0", entry_point="envs.mimic:MimicEnv",
         kwargs={"artefacts": ArtefactMix(), "action_mode": "full"})
register(id="MimicGait-v0", entry_point="envs.gait:MimicGaitEnv")
