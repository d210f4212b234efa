"""The video path end to end on rendered MuJoCo rollouts: contacts from MediaPipe keypoints and the
ContactTransformer against the simulator's (``video`` extra).

Usage: ``python bench/video_contacts.py --dataset data/physics [--net models/contact_transformer] [--episodes 2] [--json [OUT]]``

The ``--episodes`` longest test-split episodes of each held-out clip (performed by ``mimic_imu``
in MuJoCo) are rendered dressed at 30 fps, 640×480, from MuJoCo camera azimuths 90° (side), 135°
(front-oblique) and 180° (front), 3.5 m away; each video goes through
:func:`~perception.video.video_keypoints` and the network, and its contacts are scored against
Γ of the simulated insole forces at the video's frames. Reported: detection rate, precision,
recall and F1 per azimuth. The first episode's gait timelines (from the 135° video, and from the
simulator) go to ``bench/results/gait_video_{predicted,simulator}.png``.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import imageio.v2 as imageio
import numpy as np

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.contact_transformer import detect_contacts
from perception.contacts import ContactFunction, detection_scores
from perception.plots import plot_gait
from perception.dataset import load_split
from perception.video import video_keypoints
from perception.weights import load_network
from reference_motion.motion import Motion
from reference_motion.render import render_frames

AZIMUTHS = (90.0, 135.0, 180.0)
VIDEO_FPS = 30.0
RESULTS = Path(__file__).resolve().parent / "results"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dataset", type=Path, required=True)
    p.add_argument("--net", type=Path, default=Path("models/contact_transformer"))
    p.add_argument("--episodes", type=int, default=2, help="per test clip")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    net = load_network(args.net, "keypoints")
    test = load_split(args.dataset, "test")
    episodes = [s for clip in sorted({s.clip for s in test})
                for s in sorted((s for s in test if s.clip == clip), key=lambda s: -len(s.qpos))[:args.episodes]]
    result = {"episodes": [f"{s.clip} ({len(s.qpos)} frames)" for s in episodes], "video_fps": VIDEO_FPS,
              "azimuths": {}}
    gamma = ContactFunction()
    labels_of = [gamma(s.forces, s.fps) for s in episodes]
    with tempfile.TemporaryDirectory() as tmp:
        for azimuth in AZIMUTHS:
            predicted, truth, detected = [], [], []
            for k, s in enumerate(episodes):
                frames = render_frames(Motion(s.clip, s.fps, s.qpos, s.model), 640, 480, fps=VIDEO_FPS,
                                       azimuth=azimuth, elevation=-8, distance=3.5, clothed=True)
                video = Path(tmp) / f"{k}.mp4"
                imageio.mimsave(video, frames, fps=VIDEO_FPS, macro_block_size=1)
                keypoints, fps = video_keypoints(video)
                labels = labels_of[k]
                at = np.minimum(np.round(np.arange(len(keypoints)) * s.fps / fps).astype(int), len(labels) - 1)
                predicted.append(detect_contacts(net, keypoints, fps))
                truth.append(labels[at])
                detected.append((keypoints[:, 0, 2] > 0).mean())
                if k == 0 and azimuth == 135.0:
                    for name, contacts in (("predicted", predicted[-1]), ("simulator", truth[-1])):
                        plot_gait(RESULTS / f"gait_video_{name}.png", contacts, fps,
                                  f"{s.clip} rollout: " + ("from the video (MediaPipe + ContactTransformer)"
                                                           if name == "predicted" else "simulator (Γ of insole forces)"))
            scores = detection_scores(np.concatenate(predicted), np.concatenate(truth))
            by_clip = {clip: detection_scores(np.concatenate([p for p, s in zip(predicted, episodes) if s.clip == clip]),
                                              np.concatenate([t for t, s in zip(truth, episodes) if s.clip == clip]))
                       ["overall"]["f1"] for clip in dict.fromkeys(s.clip for s in episodes)}
            result["azimuths"][f"{azimuth:g}"] = {"detected": float(np.mean(detected)), **scores["overall"],
                                                  "f1_by_channel": {c: v["f1"] for c, v in scores.items()},
                                                  "f1_by_clip": by_clip}
            r = result["azimuths"][f"{azimuth:g}"]
            print(f"azimuth {azimuth:>5g}°: person found in {r['detected']:.0%} of frames; precision "
                  f"{r['precision']:.3f}, recall {r['recall']:.3f}, F1 {r['f1']:.3f} ("
                  + ", ".join(f"{c.split(':')[-1]} {f:.3f}" for c, f in by_clip.items()) + ")", flush=True)
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
