"""Reference motion: loading mocap, retargeting onto the MJCF humanoids, resampling, looping,
mirroring, IMU-artefact synthesis, quality metrics and rendering.

Set ``MUJOCO_GL`` before anything imports MuJoCo: EGL (headless, works in software) unless the user
chose otherwise.
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")
