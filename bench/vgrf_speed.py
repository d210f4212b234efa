"""Inference speed of the contact pipeline on one CPU core for a long clip, side by side.

Usage: ``python bench/vgrf_speed.py [--vgrf models/vgrf] [--minutes 10] [--json [OUT]]``

A clip of ``--minutes`` of walking at 60 Hz (DeepMimic walk looped, 23 joints) goes through
VGRFNet in one call with one torch thread; Γ on its output and the OT baseline are timed on the
same clip. Reported: frames/s of each (best of 3) and VGRFNet against the 20,000 frames/s goal.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import torch

from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.contacts import ContactFunction, OptimalThresholds
from perception.skeleton import motion_joint_positions
from perception.vgrf import estimate
from perception.weights import load_network
from reference_motion.library import load_motion

GOAL_FPS = 20_000


def best_of(fn, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--vgrf", type=Path, default=Path("models/vgrf"))
    p.add_argument("--minutes", type=float, default=10.0)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    torch.set_num_threads(1)
    frames = int(args.minutes * 60 * 60)
    positions = motion_joint_positions(load_motion("deepmimic:walk", min_frames=frames))[:frames]
    net = load_network(args.vgrf, "vgrf")
    estimate(net, positions[:600])  # warm-up
    t_net = best_of(lambda: estimate(net, positions))
    forces = estimate(net, positions)
    t_gamma = best_of(lambda: ContactFunction()(forces, 60.0))
    t_ot = best_of(lambda: OptimalThresholds().predict(positions, 60.0))
    result = {"frames": frames, "torch_threads": 1, "vgrf_fps": frames / t_net, "gamma_fps": frames / t_gamma,
              "vgrf_plus_gamma_fps": frames / (t_net + t_gamma), "ot_fps": frames / t_ot,
              "vgrf_over_goal": frames / t_net / GOAL_FPS, "ot_over_vgrf": t_net / t_ot}
    print(f"{frames} frames ({args.minutes:g} min at 60 Hz), one core:")
    print(f"  VGRFNet        {result['vgrf_fps']:>12,.0f} frames/s  ({result['vgrf_over_goal']:.2f}x the 20,000 goal)")
    print(f"  Γ              {result['gamma_fps']:>12,.0f} frames/s")
    print(f"  VGRFNet + Γ    {result['vgrf_plus_gamma_fps']:>12,.0f} frames/s")
    print(f"  OT baseline    {result['ot_fps']:>12,.0f} frames/s  ({result['ot_over_vgrf']:.0f}x VGRFNet)")
    emit_json(result, args.json)


if __name__ == "__main__":
    main()
