"""Training on more references than a process keeps tracks of: dropped tracks rebuilt from kept references.

Usage: ``python bench/track_rebuild.py [--clips SOURCE ...] [--resets 300] [--track-cache 8] [--json [OUT]]``

A run on many references (every training take mirrored, time-warped, reposed, each with six corrupted
variants, each judged against another track) cannot keep every reference track in memory (~3 MB each),
so an environment often rebuilds the tracks of the episode it starts. A process also keeps the prepared
references the tracks were built from (``MimicConfig.reference_cache_size``; ~12x smaller), so a rebuild
skips corrupting, denoising and preparing (:mod:`envs.track_cache`). Measured side by side in one run,
with a training run's references (``train_ppo.py``'s ``--corrupted-fraction 0.75 --variants-per-clip 6
--denoise --denoise-slow 0.5 --even-legs --part-legs --ground --swing-lift --judge unslid_pose``) and
``--track-cache`` tracks: the wall time of an episode's reset once every reference has been met, without
kept references (``--reference-cache 0``) and with them.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym

import envs  # noqa: F401  (registers the ids)
from agents.train_ppo import build_parser, env_kwargs
from envs.track_cache import REFERENCES, TRACKS
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from perception.imu_denoiser import DEFAULT_DENOISER
from reference_motion.cli import positive_int

CLIPS = ("deepmimic:walk", "deepmimic:run", "deepmimic:walker/turn_left0", "deepmimic:walker/turn_right0")
TRAINING = ("--corrupted-fraction", "0.75", "--variants-per-clip", "6", "--denoise-slow", "0.5", "--even-legs",
            "--part-legs", "--ground", "--swing-lift", "--judge", "unslid_pose")


def reset_wall(clips: list[str], resets: int, track_cache: int, reference_cache: int) -> dict:
    """Milliseconds per reset over ``resets`` resets that follow ``resets`` warming ones, in a process
    whose caches start empty and keep ``track_cache`` tracks and ``reference_cache`` references."""
    for cache in (TRACKS, REFERENCES):
        cache.clear(release=True)  # as in a new process: empty, nothing reserved
    args = build_parser().parse_args(["--clips", *clips, *TRAINING, "--denoise", str(DEFAULT_DENOISER),
                                      "--track-cache", str(track_cache), "--reference-cache", str(reference_cache),
                                      "--run-dir", "unused"])  # env settings only: nothing is trained
    env = gym.make("MimicIMU-v0", **env_kwargs(args, clips, args.corrupted_fraction)).unwrapped
    env.reset(seed=0)
    for _ in range(resets):
        env.reset()
    start = time.perf_counter()
    for _ in range(resets):
        env.reset()
    wall = time.perf_counter() - start
    return {"reset_ms": 1e3 * wall / resets, "references_kept": len(REFERENCES), "tracks_kept": len(TRACKS)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", default=list(CLIPS))
    p.add_argument("--resets", type=positive_int, default=300, help="resets timed (after as many warming ones)")
    p.add_argument("--track-cache", type=positive_int, default=8, help="tracks the process keeps")
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    scratch = reset_wall(args.clips, args.resets, args.track_cache, 0)
    rebuilt = reset_wall(args.clips, args.resets, args.track_cache, 100_000)
    print(f"{len(args.clips)} clips, 7 references each (the clip, 6 variants) and their judged tracks; "
          f"{args.track_cache} tracks kept; {args.resets} resets timed")
    print(f"{'':<34}{'ms/reset':>9}{'refs kept':>10}")
    for name, r in (("made from scratch (refs 0)", scratch), ("rebuilt from kept references", rebuilt)):
        print(f"{name:<34}{r['reset_ms']:>9.1f}{r['references_kept']:>10}")
    ratio = scratch["reset_ms"] / rebuilt["reset_ms"]
    print(f"kept references: resets {ratio:.1f}x faster")
    emit_json({"clips": args.clips, "resets": args.resets, "track_cache": args.track_cache,
               "from_scratch": scratch, "from_kept_references": rebuilt, "speedup": ratio}, args.json)


if __name__ == "__main__":
    main()
