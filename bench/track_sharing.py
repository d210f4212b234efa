"""Cold start of a training process: reference tracks built per environment vs shared.

Usage: ``python bench/track_sharing.py [--clips SOURCE ...] [--envs 8] [--variants 2] [--json [OUT]]``

A PPO run steps ``--envs`` environments in one process (``agents/train_ppo.py``'s DummyVecEnv).
Each environment needs the reference track (:class:`envs.reference.ReferenceTrack`) of every clip
and of every corrupted variant it meets: a corruption plus a precomputation per track. With each
environment drawing its own variants (``ArtefactMix(seed=None)``, the reset seed decides) every
environment builds and holds its own corrupted tracks (the clean ones are shared either way, so
the code before sharing, which also built each clean track per environment, was slower still); with a fixed variant seed (``ArtefactMix(seed=0)``, what
``train_ppo`` now sets) the environments make the same variants and share one copy
(``envs.track_cache.TRACKS``). Measured side by side in one run: wall time to give every
environment every track, and the bytes of distinct tracks held.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import envs  # noqa: F401  (registers the ids)
from envs import ArtefactMix
from envs.track_cache import REFERENCES, TRACKS
from json_report import emit_json  # bench/json_report.py: the scripts run from bench/
from reference_motion.library import expand_clips, load_motion

CLIPS = ("deepmimic:walk", "deepmimic:run", "deepmimic:walker/turn_left0", "deepmimic:walker/turn_right0")


def track_bytes(track) -> int:
    """Bytes of a track's arrays."""
    return sum(v.nbytes for v in vars(track).values() if isinstance(v, np.ndarray))


def cold_start(clips: list, n_envs: int, variants: int, seed: int | None) -> dict:
    """Build every track in ``n_envs`` environments; wall time and distinct bytes."""
    TRACKS.clear()  # as in a new process: nothing kept from the other measurement
    REFERENCES.clear()
    mix = ArtefactMix(fraction=0.5, variants_per_clip=variants, seed=seed)
    made = [gym.make("MimicIMU-v0", clips=clips, artefacts=mix).unwrapped for _ in range(n_envs)]
    for i, env in enumerate(made):
        env.reset(seed=i)
    start = time.perf_counter()
    held = {}
    for env in made:
        for c in range(len(clips)):
            for v in range(-1, variants):
                track = env.track(c, v)
                held[id(track)] = track
    wall = time.perf_counter() - start
    return {"wall_s": wall, "tracks_held": len(held), "bytes": sum(track_bytes(t) for t in held.values())}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--clips", nargs="+", default=list(CLIPS))
    p.add_argument("--envs", type=int, default=8)
    p.add_argument("--variants", type=int, default=2)
    p.add_argument("--json", nargs="?", const="-", default=None)
    args = p.parse_args()
    clips = [load_motion(c, "humanoid_1seg", min_frames=602) for c in expand_clips(args.clips)]
    own = cold_start(clips, args.envs, args.variants, seed=None)
    shared = cold_start(clips, args.envs, args.variants, seed=0)
    frames = sum(c.n_frames for c in clips)
    print(f"{len(clips)} clips ({frames} frames), {args.envs} envs, {args.variants} corrupted variants per clip")
    print(f"{'':<22}{'wall s':>9}{'tracks':>8}{'MB held':>9}")
    for name, r in (("per-env variants", own), ("shared (seed fixed)", shared)):
        print(f"{name:<22}{r['wall_s']:>9.2f}{r['tracks_held']:>8}{r['bytes'] / 1e6:>9.1f}")
    ratio = own["wall_s"] / shared["wall_s"]
    print(f"sharing: {ratio:.1f}x faster cold start, {own['bytes'] / shared['bytes']:.1f}x less memory")
    emit_json({"clips": len(clips), "frames": frames, "envs": args.envs, "variants": args.variants,
               "per_env": own, "shared": shared, "speedup": ratio}, args.json)


if __name__ == "__main__":
    main()
