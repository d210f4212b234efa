"""Inference speed of the ContactTransformer on one CPU core.

Usage: ``python bench/keypoint_speed.py [--net models/contact_transformer] [--minutes 10] [--json [OUT]]``

``--minutes`` of walking at 60 Hz (DeepMimic walk looped) are filmed from a held-out view and read
whole by :func:`~perception.contact_transformer.contact_probabilities` (features, half-overlapping
128-frame windows, so each frame is read twice) with one torch thread; the network alone is also
timed on non-overlapping windows. Reported: frames/s of each, best of 3.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from vgrf_speed import best_of
from perception.contact_transformer import contact_probabilities, keypoint_features
from perception.keypoint_data import film, held_out_views
from perception.keypoints import FULL_BODY_KEYPOINTS, motion_keypoints
from perception.weights import load_network
from reference_motion.library import load_motion


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--net", type=Path, default=Path("models/contact_transformer"))
    p.add_argument("--minutes", type=float, default=10.0)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    torch.set_num_threads(1)
    frames = int(args.minutes * 60 * 60)
    points = motion_keypoints(load_motion("deepmimic:walk", min_frames=frames), FULL_BODY_KEYPOINTS)[:frames]
    keypoints = film(points, held_out_views()[0], np.random.default_rng(0), 60.0, test=True)
    net = load_network(args.net, "keypoints")
    contact_probabilities(net, keypoints[:600], 60.0)  # warm-up
    t_all = best_of(lambda: contact_probabilities(net, keypoints, 60.0))
    n = frames // net.window
    windows = torch.from_numpy(keypoint_features(keypoints)[:n * net.window].reshape(n, net.window, -1))

    @torch.no_grad()
    def network_only():
        for batch in windows.split(64):
            net(batch)

    t_net = best_of(network_only)
    result = {"frames": frames, "torch_threads": 1, "end_to_end_fps": frames / t_all,
              "network_fps": n * net.window / t_net}
    print(f"{frames} frames ({args.minutes:g} min at 60 Hz), one core:")
    print(f"  contact_probabilities (overlapping windows) {result['end_to_end_fps']:>10,.0f} frames/s")
    print(f"  network alone (disjoint windows of {net.window})   {result['network_fps']:>10,.0f} frames/s")
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
