"""What an asymmetric critic sees and the policy does not: the episode's hidden corruption and body.

Under the IMU suit's artefacts a corrupted episode's return depends on what the policy cannot
observe: how far the hinge angles it is shown are from those it is judged against (drift, bias,
noise, what the denoiser leaves), where the take's path slides and drifts away from the clean
clip's (the stance skate, root and heading drift), and the randomised body it drives
(:class:`envs.physics.PhysicsDraw`). A critic that values only the policy's observation averages
over all of these, so its advantages carry their noise. These features are appended to the
critic's input alone during training (``agents/privileged_critic.py``; Pinto et al. 2018,
"Asymmetric actor critic for image-based robot learning"); the policy never reads them, and
nothing at evaluation computes them.

Layout (``nu`` actuators, ``nb`` bodies of the model including the world body, ``K`` path steps):

==============  =====  ==================================================================
name            size   content
==============  =====  ==================================================================
hinge_error     nu     tracked reference's hinge angles − the judged reference's, now (rad)
path_offset     3K     the clean clip's CoM − the tracked reference's CoM at each of
                       :data:`PATH_STEPS` control steps from now, in the tracked
                       reference's heading frame now (m)
path_velocity   3      the clean clip's CoM velocity − the tracked reference's, now (m/s, same axes)
mass            nb     the episode's mass factor on each body − 1 (the world body's, which has
                       no mass, 0)
friction        1      its friction factor − 1
strength        nu     its PD gain factor on each actuator − 1
pd_offset       nu     its PD-target offset on each actuator (rad; 0 without one)
==============  =====  ==================================================================

A clean episode on the nominal body gives zeros throughout when it is judged against the reference it
tracks (``ArtefactMix.judge`` ``"corrupted"``, ``"clean_pose"`` or ``"unslid_pose"``; ``"clean"`` and
``"given"`` judge against the take as made, before it was prepared).
"""

from __future__ import annotations

import numpy as np

from envs.physics import PhysicsDraw
from envs.reference import ReferenceTrack

PATH_STEPS = (0, 2, 4, 8, 16)
"""Control steps from now at which :func:`privileged_features` compares the clean clip's path with the
tracked reference's (up to about half a second ahead at 30 Hz control: a stance skate's slide out and back)."""


def privileged_size(n_actuators: int, n_bodies: int) -> int:
    """Length of :func:`privileged_features` for a model of ``n_actuators`` actuators and ``n_bodies``
    bodies (the world body included)."""
    return 3 * n_actuators + n_bodies + 1 + 3 * len(PATH_STEPS) + 3


def privileged_features(tracked: ReferenceTrack, judged: ReferenceTrack, clean: ReferenceTrack, frame: int,
                        frames_per_control: int, body: PhysicsDraw) -> np.ndarray:
    """The critic's extra input ``(privileged_size(nu, nb),)`` float32 at reference frame ``frame`` (module
    docstring).

    Args:
        tracked: the reference the policy observes and tracks (a corrupted variant, prepared).
        judged: the reference its reward and terminations compare with.
        clean: the clip (variant -1), prepared as the tracked reference is, whose path the tracked
            reference's slides and drifts away from.
        frame: the current reference frame; the path steps are clamped to the tracks' last frame.
        frames_per_control: reference frames per control step.
        body: the episode's draw of the randomised physics.
    """
    for name, track in (("judged", judged), ("clean", clean)):
        if track.n_frames != tracked.n_frames:
            raise ValueError(f"privileged_features: the {name} track has {track.n_frames} frames, the tracked one "
                             f"{tracked.n_frames}; they must be one clip and its variants")
    ahead = np.minimum(frame + frames_per_control * np.asarray(PATH_STEPS), tracked.n_frames - 1)
    heading = tracked.to_heading[frame]
    path = (clean.com[ahead] - tracked.com[ahead]) @ heading.T
    velocity = heading @ (clean.com_vel[frame] - tracked.com_vel[frame])
    offset = np.zeros(len(body.strength)) if body.offset is None else body.offset
    mass = np.concatenate([[0.0], body.mass[1:] - 1.0])
    return np.concatenate([tracked.ctrl[frame] - judged.ctrl[frame], path.ravel(), velocity, mass,
                           [body.friction - 1.0], body.strength - 1.0, offset]).astype(np.float32)
