"""Clean a clip with a trained mimic policy: the physically simulated re-performance of it.

Usage::

    python agents/clean.py --policy models/mimic_imu deepmimic:walker/turn_left1 --out out/clean.npz \\
        [--corrupt imu --strength 1 --seed 7] [--bvh out/clean.bvh] [--video out/clean.mp4]

The clip (any length) is simulated segment by segment (episodes of the policy's length); each
segment continues from the simulated state where the previous one ended, so the result is one
continuous motion. If the character falls or lags behind, the rest of that segment is copied
from the reference and the next segment restarts from the reference state; those frames are
listed in the output's ``source["kinematic_frames"]``. Before/after artefact metrics are printed,
and the video shows the reference (left) and the result (right).
"""

from __future__ import annotations

import sys
from pathlib import Path

if __package__ in (None, ""):  # `python agents/clean.py`: make the repository importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gymnasium as gym
import numpy as np
from tqdm import tqdm

import envs  # noqa: F401  (registers the ids)
from agents.policy import MimicPolicy, load_policy
from agents.reporting import write_json
from envs.config import FOOT_MODELS
from reference_motion.artefacts import ARTEFACT_KINDS, ArtefactRecipe, corrupt
from reference_motion.bvh_export import write_bvh
from reference_motion.cli import (CliParser, add_mocap_options, mocap_options, non_negative_float, non_negative_int,
                                  one_line_errors, output_file, require_frames)
from reference_motion.library import load_motion
from reference_motion.motion import Motion
from reference_motion.quality import ARTEFACT_METRICS, motion_quality
from reference_motion.render import SUPPORTED as VIDEO_SUFFIXES, render

MIN_FRAMES = 3
"""Frames a clip needs to be cleaned (a first frame to start from and two to simulate)."""


def clean_motion(policy: MimicPolicy, reference: Motion, episode_frames: int = 300, progress: bool = True) -> Motion:
    """The simulated re-performance of ``reference`` (60 Hz, same length, at least
    :data:`MIN_FRAMES`) by ``policy``."""
    require_frames(reference, MIN_FRAMES, reference.name, "cleaning")
    last = reference.n_frames - 1
    # hold the last frame for one more episode so every segment can start where the previous ended
    hold = np.repeat(reference.qpos[-1:], episode_frames + 2, axis=0)
    padded = reference.with_qpos(np.concatenate([reference.qpos, hold]), loop=False)
    env = gym.make(policy.env_id, clips=[padded], artefacts=None, foot=policy.foot, episode_frames=episode_frames)
    policy.check_env(env)
    base = env.unwrapped
    out = reference.qpos.copy()
    kinematic: list[list[int]] = []
    done, state = 0, None  # last frame written; simulated (qpos, qvel) at it, or None after a fall
    bar = tqdm(total=last, desc=f"cleaning {reference.name}", unit="frame", disable=not progress)
    while done < last:
        options = {"start_frame": done} if state is None else {"start_frame": done, "state": state}
        obs, _ = env.reset(seed=0, options=options)
        log: list[np.ndarray] = []
        base.frame_hook = lambda d: log.append(d.qpos.copy())
        term = trunc = False
        while not (term or trunc) and done + len(log) < last:
            obs, _, term, trunc, _ = env.step(policy(obs))
        frames = np.array(log)[: last - done]
        base.frame_hook = None
        end = done + len(frames)
        out[done + 1:end + 1] = frames
        if term and end < last:  # fell or lagged: the rest of the segment kinematically, then restart
            seg_end = min(done + episode_frames, last)
            kinematic.append([end + 1, seg_end])
            state, end = None, seg_end
        else:
            state = (base.data.qpos.copy(), base.data.qvel.copy())
        bar.update(end - done)
        done = end
    bar.close()
    env.close()
    source = {**reference.source, "cleaned_by": str(policy.path), "kinematic_frames": kinematic}
    return reference.with_qpos(out, name=f"{reference.name} (cleaned)", loop=False, source=source)


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> dict:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``); returns the before/after metrics."""
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0])
    p.add_argument("source", help="deepmimic:NAME, library:DIR#TAKE, or a .npz / .bvh / .amc / .txt file")
    add_mocap_options(p)
    p.add_argument("--policy", required=True, help="policy directory (model.zip, model_vecnormalize.pkl, sidecar.json)")
    p.add_argument("--out", type=output_file(".npz"), required=True, help="cleaned motion (.npz)")
    p.add_argument("--bvh", type=output_file(".bvh"), help="also write the cleaned motion as BVH")
    p.add_argument("--video", type=output_file(*VIDEO_SUFFIXES),
                   help="side-by-side video (.mp4/.gif; .png: first frame): reference | cleaned")
    p.add_argument("--min-frames", type=non_negative_int, help="loop a cyclic clip to at least this many 60 Hz frames")
    p.add_argument("--corrupt", choices=("imu",) + ARTEFACT_KINDS, help="corrupt the clip with IMU artefacts first")
    p.add_argument("--strength", type=non_negative_float, default=1.0)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", type=output_file(".json"), help="write the before/after metrics as JSON")
    args = p.parse_args(argv)
    policy = load_policy(args.policy)
    reference = require_frames(load_motion(args.source, FOOT_MODELS[policy.foot], min_frames=args.min_frames,
                                           mocap=mocap_options(args)),
                               MIN_FRAMES, args.source, "cleaning")
    if args.corrupt:
        reference = corrupt(reference, ArtefactRecipe.named(args.corrupt, args.strength), args.seed)
    cleaned = clean_motion(policy, reference)
    cleaned.save(args.out)
    before, after = motion_quality(reference).as_dict(), motion_quality(cleaned).as_dict()
    print(f"{'metric':<24}{'input':>12}{'cleaned':>12}")
    for k in ARTEFACT_METRICS:
        print(f"{k:<24}{before[k]:>12.4f}{after[k]:>12.4f}")
    kinematic = sum(b - a + 1 for a, b in cleaned.source["kinematic_frames"])
    print(f"wrote {args.out} ({cleaned.n_frames} frames; {kinematic} copied from the reference after a fall)")
    if args.bvh:
        print(f"wrote {write_bvh(cleaned, args.bvh)}")
    if args.video:
        print(f"wrote {render([reference, cleaned], args.video)}")
    result = {"source": args.source, "policy": str(args.policy), "input": before, "cleaned": after,
              "kinematic_frames": cleaned.source["kinematic_frames"]}
    if args.json:
        write_json(args.json, result)
    return result


if __name__ == "__main__":
    main()
