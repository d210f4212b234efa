"""Offscreen frames of a simulated character with its reference drawn translucent beside it.

The camera looks obliquely from the character's left-front, so the two bodies stand side by side.
"""

from __future__ import annotations

import mujoco
import numpy as np

GHOST_OFFSET_M = np.array([0.0, 1.0, 0.0])
"""Where the reference is drawn relative to its true place (1 m to the world left)."""

GHOST_RGBA = (1.0, 0.55, 0.3, 0.35)
"""Colour and opacity of the reference character."""


class GhostRenderer:
    """Renders ``data``'s character plus a translucent copy posed at a reference ``qpos``.

    Args:
        model: the compiled model.
        width, height: image size in pixels (at most the model's offscreen buffer, 1280×720).
    """

    def __init__(self, model: mujoco.MjModel, width: int = 480, height: int = 360):
        self.model = model
        self.renderer = mujoco.Renderer(model, height=height, width=width)
        self.ghost = mujoco.MjData(model)
        self.option = mujoco.MjvOption()
        self.perturb = mujoco.MjvPerturb()
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.azimuth, self.camera.elevation, self.camera.distance = 125.0, -15.0, 4.5

    def render(self, data: mujoco.MjData, ref_qpos: np.ndarray) -> np.ndarray:
        """RGB image ``(height, width, 3)`` uint8; the camera looks at the midpoint of the two."""
        self.ghost.qpos[:] = ref_qpos
        self.ghost.qpos[:3] += GHOST_OFFSET_M
        mujoco.mj_kinematics(self.model, self.ghost)
        mid = 0.5 * (data.qpos[:3] + self.ghost.qpos[:3])
        self.camera.lookat[:] = [mid[0], mid[1], 0.9]
        self.renderer.update_scene(data, camera=self.camera)
        scene = self.renderer.scene
        first = scene.ngeom
        mujoco.mjv_addGeoms(self.model, self.ghost, self.option, self.perturb, mujoco.mjtCatBit.mjCAT_DYNAMIC, scene)
        for g in range(first, scene.ngeom):
            scene.geoms[g].rgba[:] = GHOST_RGBA
        return self.renderer.render()

    def close(self) -> None:
        self.renderer.close()
