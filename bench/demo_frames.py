"""The README's frames of the demo's video: a few instants of ``make demo``'s side-by-side video.

Usage: ``python bench/demo_frames.py [--video out/turn_left1_imu_vs_cleaned.mp4] [--times 1 3 5 7 9]
[--out bench/results/demo_frames.png]`` (after ``make demo``).
"""

from __future__ import annotations

import argparse

import imageio.v3 as iio
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--video", default="out/turn_left1_imu_vs_cleaned.mp4")
    p.add_argument("--times", nargs="+", type=float, default=[1, 3, 5, 7, 9], help="seconds into the video")
    p.add_argument("--out", default="bench/results/demo_frames.png")
    args = p.parse_args()
    frames = iio.imread(args.video)
    fps = float(iio.immeta(args.video).get("fps", 30.0))
    fig, axes = plt.subplots(len(args.times), 1, figsize=(8, 3.1 * len(args.times)), squeeze=False)
    for ax, t in zip(axes[:, 0], args.times):
        ax.imshow(frames[min(int(round(t * fps)), len(frames) - 1)])
        ax.set_title(f"t = {t:g} s: IMU-corrupted input (left) | cleaned by physics (right; red frame: re-anchored)",
                     fontsize=9)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
