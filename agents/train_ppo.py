"""Train a mimic policy with stable-baselines3 PPO (ADAPT Table 3 settings where they fit a CPU).

Usage::

    python agents/train_ppo.py --clips deepmimic:walk --total-steps 3000000 --run-dir runs/mimic_walk
    python agents/train_ppo.py --run-dir runs/mimic_walk --resume          # continue an interrupted run

A run directory holds ``args.json`` (the command's settings), ``checkpoints/`` (model,
observation statistics and sidecar every ``--checkpoint-every`` steps, each loadable as a policy:
``evaluate.py --policy RUN/checkpoints/step_N.zip``; ``--resume`` continues from the newest,
losing at most one interval), ``best/`` (the checkpoint with the best evaluation, as ADAPT keeps
the best epoch), ``evaluations.jsonl`` and TensorBoard logs in ``tb/``.

Policy: tanh MLP, the same size for actor and critic, fixed action variance σ² = 0.03 (the log-std
is not learned), observations normalised by running statistics (saved with every checkpoint).
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import math
import re
import shlex
import signal
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, fields
from pathlib import Path

if __package__ in (None, ""):  # `python agents/train_ppo.py` puts agents/ first on the path: use the repo root
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gymnasium as gym
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback, CallbackList
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecNormalize

import envs  # noqa: F401  (registers the ids)
from agents.evaluation import evaluate
from agents.kickstart import Kickstart, KickstartConfig, Teaching
from agents.lr_schedule import kl_following
from agents.policy import CHECKPOINTS_DIR, SIDECAR_FILE, MimicPolicy, load_policy, set_action_variance
from agents.sidecar import GAIT_ENV_ID, EnvSpec, PolicySidecar, PPOSettings, TrainingRecord, repository_relative
from agents.batched_vec_env import BatchedMimicVecEnv, BatchShard
from agents.vec_env import ShardedVecEnv, shard_count
from agents.mirror import MirrorMaps
from agents.symmetric_policy import SymmetricActorCriticPolicy, maps_as_kwargs, symmetrise_statistics
from agents.privileged_critic import PrivilegedCriticPolicy, PrivilegedObservation, actor_only
from agents.warm_start import observation_normalizer, renormalised_inputs, warm_start, warm_start_privileged
from envs import ENV_IDS, ArtefactMix
from envs.config import (CONTACT_MODES, FOOT_MODELS, GAIT_ABLATIONS, JUDGED_WITHOUT, JUDGES, Dynamics, GaitConfig,
                         MimicConfig, Pushes)
from envs.observations import OBS_FRAMES
from envs.preparation import preparation_of, preparation_record, prepares_any
from perception.imu_denoiser import add_denoise_option, add_slow_corrections_option, check_slowing
from perception.weights import shared_network
from reference_motion.atomic import atomic_write, write_json
from reference_motion.artefacts import ArtefactRecipe
from reference_motion.cli import (CliParser, add_mocap_options, fraction, mocap_options, non_negative_float,
                                  non_negative_int, one_line_errors, or_none, output_dir, positive_float,
                                  positive_int)
from reference_motion.grounding import add_grounding_option
from reference_motion.leg_gap import add_leg_gap_option
from reference_motion.leg_symmetry import add_leg_symmetry_option
from reference_motion.library import (STANCE_EXTRA_M, augmented, check_stance_extra, expand_clips, load_motion,
                                      posture_copies, stance_copies)
from reference_motion.motion import Motion
from reference_motion.rigs import MocapOptions
from reference_motion.swing_lift import add_swing_lift_options
from reference_motion.transforms import PostureRanges, reversed_in_time

CHECKPOINT = re.compile(r"step_(\d+)\.zip$")


def build_parser(prog: str | None = None) -> CliParser:
    p = CliParser(prog=prog, description=__doc__.split("\n\n")[0],
                  formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    g = p.add_argument_group("task")
    g.add_argument("--env-id", default="MimicIMU-v0", choices=ENV_IDS,
                   help="task: ADAPT (MimicIMU-v0), its two ablations, or ContactVision's gait reconstruction")
    g.add_argument("--clips", nargs="+", default=["deepmimic:walk"],
                   help="training clips: SOURCE strings, or one named set (locomotion, deepmimic)")
    g.add_argument("--exclude", nargs="*", default=[], help="clips to leave out of a named set (held out)")
    g.add_argument("--eval-clips", nargs="*", default=None, help="evaluation clips (default: the training clips)")
    add_mocap_options(p)
    g.add_argument("--foot", choices=["one", "two"], default=None,
                   help="humanoid: one- or two-segment feet (default: two for MimicGait-v0, else one)")
    g.add_argument("--corrupted-fraction", type=fraction, default=0.0,
                   help="share of episodes with an IMU-corrupted reference (ADAPT's mix: 0.5; 0 = clean only)")
    g.add_argument("--strength", type=non_negative_float, nargs=2, default=(0.5, 1.0), metavar=("LOW", "HIGH"),
                   help="IMU artefact strength range of corrupted references")
    g.add_argument("--judge", choices=JUDGES, default=ArtefactMix().judge,
                   help="what an episode is rewarded and terminated against: the reference the policy observes "
                        "(ADAPT), the clean clip a corrupted one was made from, the reference as made, before "
                        "--denoise, --even-legs, --part-legs, --ground and --swing-lift prepared it, as evaluate.py "
                        "judges a take, or (clean_pose) that reference as made with the clean clip's hinge angles: the "
                        "corrupted root path, a performable pose, or (unslid_pose) that without the root's stance skate "
                        "as well (envs.ArtefactMix.judge)")
    add_denoise_option(g, "every corrupted reference (training, and --eval-strength evaluation), before the "
                          "policy observes it, as clean.py --denoise does (envs.ArtefactMix.denoiser); the "
                          "--eval-strength evaluation then judges a rollout against the denoised reference it follows "
                          "(with --judge given against the reference as made, as evaluate.py --denoise judges the "
                          "take as given)")
    add_slow_corrections_option(g)
    add_leg_symmetry_option(g, "every training reference, clean or corrupted (envs.ArtefactMix.symmetry)")
    add_leg_gap_option(g, "every training reference, clean or corrupted, after --denoise and --even-legs "
                          "(envs.ArtefactMix.legs)")
    add_grounding_option(g, "every training reference, clean or corrupted, is set on the floor after --denoise "
                            "and --part-legs (envs.ArtefactMix.grounding)")
    add_swing_lift_options(g, "every training reference is lifted last (envs.ArtefactMix.lift)")
    g.add_argument("--variants-per-clip", type=positive_int, default=4,
                   help="distinct corrupted references made per training clip (the same in every "
                        "process and shared by its envs: that many in all; with --vec subproc that many per env)")
    g.add_argument("--track-cache", type=positive_int, default=MimicConfig().track_cache_size,
                   help="reference tracks the training process keeps in memory for all its envs (~5 kB a frame, "
                        "~3 MB for a 602-frame clip; at least 3 per env; more are rebuilt on use, which slows "
                        "training; before stop 76 this counted per env). Per clip: 1, and 1 per variant; each "
                        "doubles where the episode is judged against another track (--judge given with "
                        "--denoise, --even-legs, --part-legs, --ground or --swing-lift; --judge clean_pose or "
                        "unslid_pose)")
    g.add_argument("--reference-cache", type=non_negative_int, default=MimicConfig().reference_cache_size,
                   help="prepared references (corrupted, denoised, prepared; ~0.4 kB a frame, each ~12x smaller "
                        "than a track) the process keeps, so that a dropped track is rebuilt without corrupting "
                        "and denoising again")
    g.add_argument("--obs-frame", choices=OBS_FRAMES, default="world",
                   help="axes of the observation: world (ADAPT) or the character's heading frame with its CoM "
                        "offset from the reference (envs.observations)")
    g.add_argument("--com-offset", action="store_true",
                   help="the world-frame observation also carries the character's CoM offset from the reference's "
                        "(MimicConfig.com_offset; --init-from a policy without it widens its inputs)")
    g.add_argument("--velocity-feedforward", action="store_true",
                   help="PD controllers damp towards the reference's joint velocity, not towards rest, so the body "
                        "does not trail the reference (MimicConfig.velocity_feedforward)")
    g.add_argument("--lookahead", type=positive_int, nargs="+", default=[], metavar="STEPS",
                   help="the observation also shows the reference this many control steps ahead, each "
                        "(e.g. 1 4 10; MimicConfig.lookahead; --init-from a policy without it, or with fewer of these "
                        "steps, widens its inputs)")
    g.add_argument("--lookbehind", type=positive_int, nargs="+", default=[], metavar="STEPS",
                   help="the observation also shows the reference this many control steps back, each, after the "
                        "lookahead (e.g. 1 2 4 8; MimicConfig.lookbehind; --init-from a policy without a window, or "
                        "with fewer of these steps, widens its inputs)")
    g.add_argument("--steer-gain", type=non_negative_float, default=MimicConfig.steer_gain_hz, metavar="HZ",
                   help="the observed reference velocities pull the character back onto the reference's position "
                        "at this rate, 1/s (MimicConfig.steer_gain_hz; 0: ADAPT's observation, same layout)")
    g.add_argument("--action-limit", type=positive_float, default=MimicConfig.action_limit_rad, metavar="RAD",
                   help="the action space is [-RAD, RAD] rad of PD target offset per driven hinge "
                        "(MimicConfig.action_limit_rad; a policy warm-started with --init-from keeps its weights)")
    g.add_argument("--physics-rate-hz", type=positive_float, default=MimicConfig.physics_rate_hz, metavar="HZ",
                   help="physics steps per second, a multiple of 60 (MimicConfig.physics_rate_hz: above the model's "
                        "120, finer steps and stiffer contacts, so soles sink and slide less, for more physics time)")
    g.add_argument("--still-feet-weight", type=non_negative_float, default=MimicConfig.still_feet_weight,
                   metavar="W", help="weight of the still-feet term in the reward (MimicConfig.still_feet_weight: "
                                     "exp(-alpha * summed horizontal speed of the foot points on the floor); "
                                     "0: ADAPT's reward)")
    g.add_argument("--still-feet-alpha", type=positive_float, default=MimicConfig.still_feet_alpha, metavar="ALPHA",
                   help="its scale, per m/s (MimicConfig.still_feet_alpha)")
    g.add_argument("--com-velocity-weight", type=non_negative_float, default=MimicConfig.com_velocity_weight,
                   metavar="W", help="weight of the CoM-velocity term in the reward (MimicConfig.com_velocity_weight: "
                                     "exp(-alpha * |horizontal CoM velocity - the reference's, steered back onto it|); "
                                     "0: ADAPT's reward)")
    g.add_argument("--com-velocity-alpha", type=positive_float, default=MimicConfig.com_velocity_alpha,
                   metavar="ALPHA", help="its scale, per m/s (MimicConfig.com_velocity_alpha)")
    g.add_argument("--contacts", choices=CONTACT_MODES, default="vgrf",
                   help="MimicGait-v0: contact targets from VGRFNet on the reference's joints or from the "
                        "ContactTransformer on its 2D keypoints")
    g.add_argument("--gait-ablation", choices=GAIT_ABLATIONS, default=None,
                   help="MimicGait-v0: ContactVision Fig. 12's ablations: no_fc (no contact reward), no_toeref "
                        "(toe targets 0); the one-segment foot is --foot one")
    g.add_argument("--mirror", action="store_true", help="also train on every clip mirrored left/right")
    g.add_argument("--speeds", type=positive_float, nargs="+", default=[1.0],
                   help="time-warp speeds each training clip is played at (e.g. 0.8 1.0 1.2)")
    g.add_argument("--push-force", type=non_negative_float, nargs=2, default=None, metavar=("LOW", "HIGH"),
                   help="shove the pelvis during training episodes with a horizontal force drawn from LOW..HIGH N "
                        "(envs.config.Pushes: DeepMimic's perturbations, to learn recoveries; e.g. 40 120); "
                        "default: no pushes")
    g.add_argument("--push-rate", type=non_negative_float, default=Pushes.rate_hz,
                   help="--push-force: pushes started per second, on average")
    g.add_argument("--push-duration", type=positive_float, default=Pushes.duration_s,
                   help="--push-force: how long each push lasts (s)")
    g.add_argument("--dynamics", type=non_negative_float, nargs=3, default=None,
                   metavar=("MASS", "FRICTION", "STRENGTH"),
                   help="draw the humanoid's physics anew at every training episode: each body's mass and inertia, "
                        "the sliding friction and each actuator's PD gains scaled by factors uniform in 1 ± these "
                        "half-ranges (envs.config.Dynamics, domain randomisation; e.g. 0.15 0.3 0.15); default: "
                        "the nominal humanoid. Evaluation never randomises")
    g.add_argument("--pd-offset", type=non_negative_float, default=0.0, metavar="DEG",
                   help="with or without --dynamics: every training episode, each actuator's PD target is off by "
                        "a constant drawn uniformly from ±DEG degrees, unseen by the policy (Dynamics.offset_deg: "
                        "the few degrees every hinge of an IMU take is off); default 0: none")
    g.add_argument("--reverse", nargs="+", default=[], metavar="GLOB",
                   help="also train on the training clips whose SOURCE matches a GLOB (fnmatch, e.g. "
                        "'*_walk_*') played backwards in time: the same torques and contact forces perform them "
                        "(reference_motion.transforms.reversed_in_time), so a forward walk becomes a backward one")
    g.add_argument("--warp", type=glob_speeds, nargs="+", default=[], metavar="GLOB=S,S",
                   help="also train on the training clips whose SOURCE matches GLOB time-warped to each speed S, "
                        "beside --speeds (e.g. '*walk-back*=1.25,1.5': backward walks faster than any recorded)")
    g.add_argument("--postures", type=non_negative_int, default=0, metavar="N",
                   help="also train on N copies of every training reference (mirrored and time-warped ones "
                        "included), each carried with a random posture: a stoop, bent knees, a wide stance "
                        "(reference_motion.transforms.random_posture, drawn with --seed); default 0")
    g.add_argument("--stances", type=non_negative_int, default=0, metavar="N",
                   help="also train on N copies of every training reference (mirrored and time-warped ones "
                        "included) walked with the feet further apart, the body swaying as the wider steps need "
                        "(reference_motion.stance.wider_stance; drawn with --seed); default 0")
    g.add_argument("--stance-extra", type=float, nargs=2, default=STANCE_EXTRA_M, metavar=("LOW", "HIGH"),
                   help="how much further apart the --stances copies walk (m, drawn uniformly; default "
                        f"{STANCE_EXTRA_M[0]:g} to {STANCE_EXTRA_M[1]:g}: about the widest stance of the training "
                        "takes, chimpira's sideways walks, against a normal walk's)")
    g.add_argument("--posture-range", type=posture_range, nargs="*", default=[], metavar="NAME=LOW,HIGH",
                   help="with --postures, draw the posture change NAME from LOW to HIGH degrees instead of "
                        "reference_motion.transforms.PostureRanges' default (NAME: trunk_flexion, neck_flexion, "
                        "crouch, stance_width (each hip), elbow_flexion; a NAME given twice: the later range; "
                        "e.g. 'stance_width=-4,12' 'trunk_flexion=0,0'); given bare, PostureRanges' defaults")
    g = p.add_argument_group("PPO")
    g.add_argument("--total-steps", type=positive_int, default=3_000_000, help="environment (control) steps")
    g.add_argument("--n-envs", type=positive_int, default=None,
                   help="environments stepped together (one policy batch; default: 32 with --vec batched or "
                        "sharded-batched, what every shipped policy trained with, else 8; 64 in 2 sharded batches "
                        "is the fastest on 2 cores, README)")
    g.add_argument("--vec", choices=VEC_KINDS, default=None,
                   help="batched: the envs stepped as one batch in this process, their physics on --workers "
                        "threads (agents/batched_vec_env.py; the default, see README; MimicIMU-v0 and "
                        "its ablations); sharded-batched: the envs split over --workers shards, this process and "
                        "worker processes, each shard stepped as one batch (the batches' Python on every core too: "
                        "for many cores); sharded: the same shards with their envs stepped one at a time "
                        "(agents/vec_env.py); dummy: all envs in this process, one at a time; subproc: "
                        "one process per env (default: batched, sharded for MimicGait-v0)")
    g.add_argument("--workers", type=positive_int, default=None,
                   help="--vec batched: physics threads; --vec sharded(-batched): shards, this process included "
                        "(default: the cores, at most --n-envs)")
    g.add_argument("--net", default="256,256", help="hidden layer sizes of actor and critic (tanh)")
    g.add_argument("--device", default="cpu", choices=["cpu", "cuda", "auto"],
                   help="where the networks learn: cpu (fastest for small networks on a few cores), "
                        "cuda or auto (a GPU if there is one; on a many-core machine --vec sharded uses every core)")
    g.add_argument("--lr", type=positive_float, default=5e-5, help="Adam learning rate (ADAPT: 5e-5)")
    g.add_argument("--target-kl", type=positive_float, default=None,
                   help="follow this approximate KL per PPO update by adapting the learning rate after each "
                        "update (agents/lr_schedule.py; --lr is the starting rate; rsl_rl: 0.01); default: "
                        "the fixed --lr of ADAPT")
    g.add_argument("--n-steps", type=positive_int, default=None,
                   help="rollout length per environment (default: 8192 / --n-envs, 8192 steps per PPO update)")
    g.add_argument("--batch-size", type=positive_int, default=512, help="minibatch size")
    g.add_argument("--epochs", type=positive_int, default=6, help="optimisation epochs per rollout (ADAPT: 6)")
    g.add_argument("--gamma", type=fraction, default=0.99)
    g.add_argument("--gae-lambda", type=fraction, default=0.95)
    g.add_argument("--clip-range", type=positive_float, default=0.2)
    g.add_argument("--action-variance", type=positive_float, default=0.03,
                   help="fixed σ² of the Gaussian policy (with --init-from too: the source's is replaced)")
    g.add_argument("--seed", type=int, default=0)
    g.add_argument("--torch-threads", type=positive_int, default=None,
                   help="torch threads in the learner process, collecting and updating alike (default: 2 with "
                        "--vec dummy; with --vec batched 1 while collecting rollouts and one per core while "
                        "updating; else 1: the workers need the other cores)")
    g = p.add_argument_group("run")
    g.add_argument("--run-dir", type=output_dir, required=True)
    g.add_argument("--resume", action="store_true", help="continue from the newest checkpoint in --run-dir")
    g.add_argument("--init-from", type=Path, default=None,
                   help="start a new run from the weights and observation statistics of a shipped policy "
                        "(e.g. models/mimic_imu): same foot, observation and action set; --net the same or wider "
                        "(agents/warm_start.py: the run starts acting exactly as the source)")
    g.add_argument("--symmetric", action=argparse.BooleanOptionalAction, default=False,
                   help="train the mirror-symmetric actor (agents/symmetric_policy.py: the mean of the actor's action "
                        "and, mapped back, its action on the mirrored observation) with --init-from's weights; the "
                        "source's observation statistics are made mirror symmetric and frozen")
    g.add_argument("--privileged-critic", action=argparse.BooleanOptionalAction, default=False,
                   help="an asymmetric critic: the value network also reads each episode's hidden corruption and "
                        "randomised body (envs/privileged.py; agents/privileged_critic.py), the policy its own "
                        "observation only; the run's checkpoints load as their actor")
    g.add_argument("--critic-lr-scale", type=positive_float, default=1.0,
                   help="with --privileged-critic: the critic's layers learn at this multiple of --lr (the actor at "
                        "--lr), so a warm-started critic takes up its new inputs faster than the actor moves")
    g.add_argument("--kickstart", type=or_none(str), default=None, metavar="SET",
                   help="after each PPO update, pull the policy's mean action towards a teacher's on the last "
                        "rollout's states of the takes a policy set routes to a policy of its own "
                        "(agents/kickstart.py; the set's default and backward policies teach nothing); the "
                        "teachers read the run's observation (or the part before its reference window) and act "
                        "with its actions; 'none' turns it off in a resumed run")
    g.add_argument("--kickstart-epochs", type=positive_int, default=KickstartConfig.epochs,
                   help="passes over those states after each update")
    g.add_argument("--kickstart-lr", type=positive_float, default=KickstartConfig.lr,
                   help="Adam's learning rate of those passes (PPO's --lr is separate)")
    g.add_argument("--kickstart-corrupted", action="store_true",
                   help="the teachers also teach the taught takes' IMU-corrupted episodes (default: clean ones only)")
    g.add_argument("--checkpoint-every", type=positive_int, default=100_000, help="steps between checkpoints")
    g.add_argument("--eval-every", type=positive_int, default=200_000, help="steps between evaluations")
    g.add_argument("--eval-episodes", type=positive_int, default=5, help="rollouts per evaluation clip (ADAPT: 20)")
    g.add_argument("--eval-strength", type=non_negative_float, default=None,
                   help="evaluate on IMU-corrupted evaluation clips of this strength (default: clean)")
    g.add_argument("--stop-at-sr90", type=fraction, default=None,
                   help="stop early once an evaluation reaches this SR90 (and save a checkpoint)")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    return p


def artefact_mix(args: argparse.Namespace, corrupted_fraction: float) -> ArtefactMix | None:
    """The run's corrupted references (``--strength``, ``--variants-per-clip``, its variant seed,
    ``--judge``, ``--denoise``) in ``corrupted_fraction`` of the episodes, and how every reference is
    prepared before the policy tracks it (``--even-legs``, ``--part-legs``, ``--ground``, ``--swing-lift``);
    ``None`` when there is neither."""
    steps = preparation_of(args)
    if corrupted_fraction <= 0 and not prepares_any(steps):
        return None
    return ArtefactMix(recipe=ArtefactRecipe.imu(), strength=tuple(args.strength), fraction=corrupted_fraction,
                       variants_per_clip=args.variants_per_clip, seed=variant_seed(args), judge=args.judge,
                       denoiser=args.denoise, denoise_slow_s=args.denoise_slow, **steps)


def check_kickstart(args: argparse.Namespace) -> None:
    """A :class:`ValueError` when ``--kickstart-epochs``, ``--kickstart-lr`` or ``--kickstart-corrupted``
    is set without ``--kickstart``: they would do nothing."""
    if args.kickstart is not None:
        return
    given = [flag for flag, on in (("--kickstart-epochs", args.kickstart_epochs != KickstartConfig.epochs),
                                   ("--kickstart-lr", args.kickstart_lr != KickstartConfig.lr),
                                   ("--kickstart-corrupted", args.kickstart_corrupted)) if on]
    if given:
        raise ValueError(f"{' and '.join(given)} set{'s' if len(given) == 1 else ''} the kickstarting that "
                         f"--kickstart SET asks for; give it")


def kickstart_config(args: argparse.Namespace) -> KickstartConfig:
    """The supervised step between PPO updates that ``--kickstart``, ``--kickstart-epochs``,
    ``--kickstart-lr`` and ``--kickstart-corrupted`` ask for."""
    return KickstartConfig(policy_set=repository_relative(args.kickstart), epochs=args.kickstart_epochs,
                           lr=args.kickstart_lr, corrupted=args.kickstart_corrupted)


def kickstarter(args: argparse.Namespace, env: gym.Env, clips: list[str] | list[Motion]) -> Kickstart:
    """The callback that kickstarts the run (``--kickstart``): its teachers read ``env``'s observation
    and teach some episodes of the training ``clips`` (:func:`training_motions`: SOURCE strings or clips)."""
    config = kickstart_config(args)
    teaching = Teaching.load(args.kickstart, env)
    names = [clip if isinstance(clip, str) else clip.name for clip in clips]
    teaching.check_teaches(names, args.corrupted_fraction, config.corrupted)
    return Kickstart(teaching, config, args.seed)


def env_kwargs(args: argparse.Namespace, clips: list, corrupted_fraction: float) -> dict:
    kwargs = {"clips": clips, "artefacts": artefact_mix(args, corrupted_fraction), "foot": foot(args),
              "config": env_config(args)}
    if args.env_id == GAIT_ENV_ID:
        kwargs.update(contacts=args.contacts, gait=gait_config(args))
    return kwargs


def pushes(args: argparse.Namespace) -> Pushes | None:
    """The training envs' random pushes (``--push-force``), or ``None``; never the evaluation's."""
    if args.push_force is None:
        return None
    if args.env_id == GAIT_ENV_ID:
        raise ValueError(f"--push-force shoves MimicEnv's character; {GAIT_ENV_ID} does not take pushes")
    return Pushes(force_n=tuple(args.push_force), duration_s=args.push_duration, rate_hz=args.push_rate)


def dynamics(args: argparse.Namespace) -> Dynamics | None:
    """The training envs' randomised physics (``--dynamics``, ``--pd-offset``), or ``None``; never the evaluation's."""
    if args.dynamics is None and args.pd_offset == 0:
        return None
    if args.env_id == GAIT_ENV_ID:
        raise ValueError(f"--dynamics and --pd-offset randomise MimicEnv's humanoid; {GAIT_ENV_ID} does not take them")
    mass, friction, strength = args.dynamics or (0.0, 0.0, 0.0)
    try:
        return Dynamics(mass=mass, friction=friction, strength=strength, offset_deg=args.pd_offset)
    except ValueError as e:
        raise ValueError(f"--dynamics {mass:g} {friction:g} {strength:g} --pd-offset {args.pd_offset:g}: {e}") from None


def variant_seed(args: argparse.Namespace) -> int | None:
    """``ArtefactMix.seed`` of the run: with in-process or sharded envs one seed, so that the envs make
    the same corrupted variants and the envs of a process share them (one build, one copy per
    process; the run then has ``--variants-per-clip`` variants of each clip in all, not that many per
    env); with one subprocess per env each env its own (``None``)."""
    return None if args.vec == "subproc" else args.seed


def vec_kind(args: argparse.Namespace) -> str:
    """How the run's envs are stepped: ``--vec``, by default batched (sharded for ``MimicGait-v0``,
    whose reward :class:`BatchedMimicVecEnv` does not batch)."""
    if args.vec in BATCHED_KINDS and args.env_id == GAIT_ENV_ID:
        raise ValueError(f"--vec {args.vec} steps MimicEnv's own reward; {GAIT_ENV_ID} needs --vec sharded, dummy or "
                         "subproc")
    return args.vec or ("sharded" if args.env_id == GAIT_ENV_ID else "batched")


def vec_env_settings(args: argparse.Namespace) -> tuple[type, dict, int, int]:
    """The run's vectorized-env class, its keyword arguments, and the learner's torch threads while
    collecting rollouts and while updating."""
    kind = vec_kind(args)
    if kind in BATCHED_KINDS:  # the cores step the envs while collecting and are free while updating
        collect, update = args.torch_threads or 1, args.torch_threads or shard_count(None, args.n_envs)
        if kind == "batched":
            return BatchedMimicVecEnv, {"n_threads": shard_count(args.workers, args.n_envs)}, collect, update
        return ShardedVecEnv, {"n_workers": shard_count(args.workers, args.n_envs), "shard": BatchShard}, collect, update
    threads = args.torch_threads or (2 if kind == "dummy" else 1)
    if kind == "sharded":
        return ShardedVecEnv, {"n_workers": shard_count(args.workers, args.n_envs)}, threads, threads
    return (SubprocVecEnv if kind == "subproc" else DummyVecEnv), {}, threads, threads


class UpdateThreads(BaseCallback):
    """Give the learner ``update`` torch threads while PPO updates and ``collect`` while it collects
    rollouts: with the envs stepped as batches (``--vec batched``, ``sharded-batched``) the cores are
    free during updates, and more torch threads during the small forward passes of a rollout only
    wait on the physics."""

    def __init__(self, collect: int, update: int):
        super().__init__()
        self.collect, self.update = collect, update
        self._before = torch.get_num_threads()

    def _on_training_start(self) -> None:
        self._before = torch.get_num_threads()

    def _on_training_end(self) -> None:
        torch.set_num_threads(self._before)

    def _on_rollout_start(self) -> None:
        torch.set_num_threads(self.collect)

    def _on_rollout_end(self) -> None:
        torch.set_num_threads(self.update)

    def _on_step(self) -> bool:
        return True


def foot(args: argparse.Namespace) -> str:
    """The run's foot model: ``--foot``, else two segments for ``MimicGait-v0`` and one otherwise."""
    return args.foot or ("two" if args.env_id == GAIT_ENV_ID else "one")


VEC_KINDS = ("sharded-batched", "batched", "sharded", "dummy", "subproc")
"""``--vec`` choices: how the training envs are stepped (``agents/batched_vec_env.py``,
``agents/vec_env.py``, stable-baselines3)."""
BATCHED_KINDS = ("sharded-batched", "batched")
"""The kinds that step MimicEnv's reward and observation as batches (:mod:`agents.batched_vec_env`)."""

STEPS_PER_UPDATE = 8192
"""Environment steps per PPO update by default (``--n-steps`` is this over ``--n-envs``)."""

def gait_config(args: argparse.Namespace) -> GaitConfig:
    """``MimicGait-v0``'s reward constants for this run: ContactVision's, or an ablation's."""
    return GaitConfig().ablated(args.gait_ablation)


def env_config(args: argparse.Namespace) -> MimicConfig:
    """The environments' constants for this run (defaults, with ``--track-cache``, ``--reference-cache``,
    ``--obs-frame``, ``--com-offset``, ``--velocity-feedforward``, ``--lookahead``, ``--lookbehind``, ``--steer-gain``,
    ``--action-limit``, ``--physics-rate-hz``, ``--still-feet-*`` and ``--com-velocity-*``)."""
    return MimicConfig(track_cache_size=args.track_cache, reference_cache_size=args.reference_cache,
                       obs_frame=args.obs_frame, com_offset=args.com_offset,
                       velocity_feedforward=args.velocity_feedforward,
                       lookahead=tuple(args.lookahead), lookbehind=tuple(args.lookbehind),
                       steer_gain_hz=args.steer_gain,
                       physics_rate_hz=args.physics_rate_hz, action_limit_rad=args.action_limit,
                       still_feet_weight=args.still_feet_weight, still_feet_alpha=args.still_feet_alpha,
                       com_velocity_weight=args.com_velocity_weight, com_velocity_alpha=args.com_velocity_alpha)


def training_clips(args: argparse.Namespace) -> list[str]:
    clips = expand_clips(args.clips)
    unknown = set(args.exclude) - set(clips)
    if unknown:
        raise ValueError(f"--exclude names clips not in the training set: {sorted(unknown)}")
    return [c for c in clips if c not in args.exclude]


def evaluation_clips(args: argparse.Namespace) -> list[str]:
    """The clips the periodic evaluation runs on: ``--eval-clips`` (sets expanded), else the training clips."""
    return expand_clips(args.eval_clips) if args.eval_clips else training_clips(args)


def training_motions(args: argparse.Namespace) -> list[str] | list[Motion]:
    """The training clips as the envs get them: SOURCE strings, or, with ``--mirror``,
    ``--speeds`` or mocap options (``--joint-map`` ...), the loaded clips plus their mirrored and
    time-warped copies."""
    clips = training_clips(args)
    mocap = mocap_options(args)
    if (not args.mirror and list(args.speeds) == [1.0] and mocap == MocapOptions() and not args.reverse
            and not args.postures and not args.warp and not args.stances):
        return clips
    motions = load_training_motions(clips, FOOT_MODELS[foot(args)], args.mirror, args.speeds, mocap,
                                    reversed_clips(clips, args.reverse), warped_clips(clips, args.warp))
    return motions + reposed_copies(motions, args, args.seed)


def reposed_copies(motions: list[Motion], args: argparse.Namespace, seed: int) -> list[Motion]:
    """The ``--postures`` and then the ``--stances`` copies of ``motions``, drawn with ``seed``'s
    streams (:data:`POSTURE_STREAM`, :data:`STANCE_STREAM`): the same copies for the same seed and
    ranges (``distill.py`` makes them so too)."""
    return (posture_copies(motions, args.postures, [seed, POSTURE_STREAM], posture_ranges(args))
            + stance_copies(motions, args.stances, [seed, STANCE_STREAM], stance_extra(args)))


POSTURE_STREAM, STANCE_STREAM = 7, 8
"""Streams of ``--seed``'s random numbers that draw the posture and the stance copies (apart from
PPO's and from each other's)."""


def matching_clips(clips: list[str], globs: list[str], option: str) -> list[str]:
    """The clips of ``clips`` whose SOURCE matches one of ``globs`` (:func:`fnmatch.fnmatchcase`);
    a glob that matches none is an error naming ``option``, so a typo does not silently train on
    nothing new."""
    for pattern in globs:
        if not any(fnmatch.fnmatchcase(c, pattern) for c in clips):
            raise ValueError(f"{option} {pattern!r} matches none of the {len(clips)} training clips "
                             f"(e.g. {clips[0]!r}); quote the glob so that the shell leaves it alone")
    return [c for c in clips if any(fnmatch.fnmatchcase(c, p) for p in globs)]


def reversed_clips(clips: list[str], globs: list[str]) -> list[str]:
    """The clips of ``clips`` that ``--reverse``'s ``globs`` name (:func:`matching_clips`)."""
    return matching_clips(clips, globs, "--reverse")


def parse_glob_speeds(text: str) -> tuple[str, list[float]]:
    """A ``--warp`` value ``GLOB=S,S,...`` as ``(glob, speeds)``, every speed a finite number > 0;
    :class:`argparse.ArgumentTypeError` says what is wrong."""
    pattern, sep, speeds = text.rpartition("=")
    try:
        values = [float(v) for v in speeds.split(",")]
    except ValueError:
        values = []
    if not sep or not pattern or not values or not all(math.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}: expected GLOB=SPEED[,SPEED...] with positive speeds, "
                                         f"e.g. '*walk-back*=1.25,1.5'")
    return pattern, values


def parse_posture_range(text: str) -> tuple[str, tuple[float, float]]:
    """A ``--posture-range`` value ``NAME=LOW,HIGH`` as ``(field of PostureRanges, (low, high))``
    (degrees, checked by :class:`PostureRanges`); :class:`argparse.ArgumentTypeError` says what is wrong."""
    name, _, bounds = text.partition("=")
    names = [f.name.removesuffix("_deg") for f in fields(PostureRanges)]
    try:
        low, high = (float(v) for v in bounds.split(","))
        if name not in names:
            raise ValueError(f"no posture change {name!r}")
        PostureRanges(**{f"{name}_deg": (low, high)})
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected NAME=LOW,HIGH (finite degrees, LOW <= HIGH) with NAME "
                                         f"one of {', '.join(names)}, e.g. 'stance_width=-4,12'") from None
    return f"{name}_deg", (low, high)


def posture_range(text: str) -> str:
    """A ``--posture-range`` value checked by :func:`parse_posture_range` and returned as given."""
    parse_posture_range(text)
    return text


def posture_ranges(args: argparse.Namespace) -> PostureRanges:
    """The ranges ``--postures`` copies are drawn from: :class:`PostureRanges`' defaults with
    ``--posture-range``'s changes (a later value for the same change wins)."""
    if args.posture_range and not args.postures:
        raise ValueError("--posture-range changes the postures of --postures copies; give --postures N as well (or "
                         "a bare --posture-range to drop the ranges)")
    return PostureRanges(**dict(parse_posture_range(v) for v in args.posture_range))


def stance_extra(args: argparse.Namespace) -> tuple[float, float]:
    """``--stance-extra LOW HIGH`` (m), checked (:func:`reference_motion.library.check_stance_extra`)."""
    return check_stance_extra(args.stance_extra, "--stance-extra")


def glob_speeds(text: str) -> str:
    """A ``--warp`` value checked by :func:`parse_glob_speeds` and returned as given (``args.json``
    stores it so)."""
    parse_glob_speeds(text)
    return text


def warped_clips(clips: list[str], warps: list[str]) -> dict[str, list[float]]:
    """The extra time-warp speeds ``--warp``'s ``GLOB=S,S`` values give each clip of ``clips`` they
    name, ``{clip: speeds}`` (speeds in the order first given; a glob matching no clip is an error)."""
    out: dict[str, list[float]] = {}
    for value in warps:
        pattern, speeds = parse_glob_speeds(value)
        for clip in matching_clips(clips, [pattern], "--warp"):
            out[clip] = list(dict.fromkeys(out.get(clip, []) + speeds))
    return out


def load_training_motions(clips: list[str], model: str, mirror: bool, speeds: list[float] = (1.0,),
                          mocap: MocapOptions = MocapOptions(), reverse: list[str] = (),
                          warps: dict[str, list[float]] | None = None) -> list[Motion]:
    """``clips`` loaded for ``model`` (each at least two episodes long at its fastest warp, looped
    if need be), those named in ``reverse`` also played backwards in time, then augmented:
    time-warped to each of ``speeds`` and, if ``mirror``, mirrored; last, each clip named in
    ``warps`` ({clip: speeds}, :func:`warped_clips`) also at those of its extra speeds that
    ``speeds`` lacks (mirrored too), so no reference is there twice."""
    warps = {c: [s for s in extra if s not in speeds] for c, extra in (warps or {}).items()}
    frames = 2 * (MimicConfig().episode_frames + 1)
    motions = [load_motion(c, model, min_frames=int(frames * max([*speeds, *warps.get(c, [])])) + 2, mocap=mocap)
               for c in clips]
    originals = dict(zip(clips, motions))
    motions += [reversed_in_time(m) for c, m in zip(clips, motions) if c in reverse]
    extra = [m for c, s in warps.items() if s for m in augmented([originals[c]], mirrored=mirror, speeds=s)]
    return augmented(motions, mirrored=mirror, speeds=speeds) + extra


WALL_FILE = "wall.json"
"""The run's training wall time at its newest checkpoint, in the run directory."""


def recorded_progress(run_dir: Path) -> tuple[int, float] | None:
    """``(steps, wall time in s)`` the run in ``run_dir`` has trained so far: at its newest
    checkpoint (``wall.json``, written with each), else at its last evaluation (runs from before
    ``wall.json``); ``None`` when it has recorded neither."""
    wall = run_dir / WALL_FILE
    if wall.is_file():
        record = json.loads(wall.read_text())
    else:
        log = run_dir / "evaluations.jsonl"
        lines = log.read_text().splitlines() if log.is_file() else []
        if not lines:
            return None
        record = json.loads(lines[-1])
    return int(record["steps"]), float(record["wall_s"])


class CheckpointAndEvaluate(BaseCallback):
    """Saves model + observation statistics every ``checkpoint_every`` steps; evaluates every
    ``eval_every`` steps with ADAPT's protocol, logs the metrics and keeps the best checkpoint."""

    def __init__(self, run_dir: Path, eval_env: gym.Env, args: argparse.Namespace):
        super().__init__()
        self.run_dir, self.eval_env, self.args = run_dir, eval_env, args
        self.best_path = run_dir / "best" / "sidecar.json"
        self.best = json.loads(self.best_path.read_text())["score"] if self.best_path.exists() else -math.inf
        self._next_ckpt = self._next_eval = 0

    def _on_training_start(self) -> None:
        self._t0 = time.time()
        progress = recorded_progress(self.run_dir)
        self._wall_before = progress[1] if progress else 0.0  # resumed runs add up
        n = self.num_timesteps
        self._next_ckpt = (n // self.args.checkpoint_every + 1) * self.args.checkpoint_every
        self._next_eval = (n // self.args.eval_every + 1) * self.args.eval_every

    def wall_s(self) -> float:
        """Training wall time (s) of the run so far, earlier commands included."""
        return self._wall_before + time.time() - self._t0

    def _save(self, directory: Path, stem: str, policy: MimicPolicy | None = None) -> None:
        """Save model and observation statistics (the run's, or ``policy``'s), each file whole or not at
        all, the statistics first (a ``step_N.zip`` is only there with its statistics); Ctrl-C or ``kill``
        during the save takes effect after it (:func:`deferred_signals`)."""
        model, statistics = ((self.model, self.model.get_vec_normalize_env()) if policy is None
                             else (policy.model, policy.normalizer))
        with deferred_signals():
            with atomic_write(directory / f"{stem}_vecnormalize.pkl") as tmp:
                statistics.save(str(tmp))
            with atomic_write(directory / f"{stem}.zip") as tmp:
                model.save(tmp)

    def _on_step(self) -> bool:
        if self.num_timesteps >= self._next_ckpt:
            self.save_checkpoint()
            self._next_ckpt += self.args.checkpoint_every
        if self.num_timesteps >= self._next_eval:
            sr90 = self._evaluate()
            self._next_eval += self.args.eval_every
            target = getattr(self.args, "stop_at_sr90", None)
            if target is not None and sr90 >= target:
                print(f"SR90 {sr90:.2f} >= {target}: stopping at {self.num_timesteps} steps", flush=True)
                return False
        return True

    def _evaluate(self) -> float:
        """Evaluate, log, keep the best; returns the SR90."""
        model, statistics = self.model, self.model.get_vec_normalize_env()
        if isinstance(model.policy, PrivilegedCriticPolicy):  # evaluated as the actor it is
            model, statistics = actor_only(model, statistics)
        policy = MimicPolicy(self.run_dir, model, statistics)
        start = time.perf_counter()
        corrupted = getattr(self.args, "eval_strength", None) is not None
        summary, _ = evaluate(self.eval_env, policy, episodes=self.args.eval_episodes, corrupted=corrupted)
        for key in ("ELR_mean", "SR90", "RDE_mean", "MRR_mean"):
            self.logger.record(f"eval/{key}", summary[key])
        score = summary["ELR_mean"] + 0.1 * summary["MRR_mean"]  # survive first, then track closely
        record = {"steps": self.num_timesteps, "wall_s": self.wall_s(),
                  "eval_strength": getattr(self.args, "eval_strength", None),
                  "eval_s": time.perf_counter() - start, "score": score, **summary}
        with open(self.run_dir / "evaluations.jsonl", "a") as f:
            f.write(json.dumps(record) + "\n")
        if score > self.best:
            self.best = score
            with deferred_signals():  # the best policy's files and its sidecar, all or none
                self._save(self.run_dir / "best", "model", policy)  # as evaluated: a privileged critic's actor
                self._sidecar(record).save(self.best_path)
        print(f"[eval @ {self.num_timesteps}] ELR {summary['ELR_mean']:.3f} SR90 {summary['SR90']:.2f} "
              f"MRR {summary['MRR_mean']:.3f} (best score {self.best:.3f})", flush=True)
        return summary["SR90"]

    def _sidecar(self, record: dict) -> PolicySidecar:
        """How the policy of ``record`` (``steps``, ``wall_s``; an evaluated one also ``score`` and
        the metrics) was made and how it scored (``agents/policy.py`` reads it)."""
        args = self.args
        ppo = PPOSettings(**{f.name: getattr(args, f.name) for f in fields(PPOSettings)})
        push, varied = pushes(args), dynamics(args)
        steps = preparation_of(args)
        clips = training_clips(args)
        training = TrainingRecord(
            clips=clips,
            eval_clips=evaluation_clips(args),
            corrupted_fraction=args.corrupted_fraction, strength=tuple(args.strength), judge=args.judge,
            denoiser=repository_relative(args.denoise), denoise_slow_s=args.denoise_slow,
            **preparation_record(steps, lift_key="lift"),
            mirror=args.mirror, speeds=list(args.speeds),
            reversed_clips=reversed_clips(clips, args.reverse),
            warps=warped_clips(clips, args.warp),
            postures=args.postures, posture_seed=args.seed,
            posture_ranges=asdict(posture_ranges(args)) if args.postures else None,
            stances=args.stances, stance_extra_m=stance_extra(args) if args.stances else None,
            pushes=asdict(push) if push is not None else None,
            dynamics=asdict(varied) if varied is not None else None,
            init_from=str(args.init_from) if args.init_from else None,
            symmetric=isinstance(self.model.policy, SymmetricActorCriticPolicy),
            privileged_critic=isinstance(self.model.policy, PrivilegedCriticPolicy),
            kickstart=asdict(kickstart_config(args)) if args.kickstart else None,
            commands=[shlex.join(["python", *c]) for c in args.commands], seed=args.seed, steps=record["steps"],
            wall_s=record["wall_s"])
        gait = asdict(gait_config(args)) if args.env_id == GAIT_ENV_ID else None
        env = EnvSpec(args.env_id, foot(args), asdict(env_config(args)), gait, args.contacts)
        return PolicySidecar(env=env, ppo=ppo,
                             training=training, score=record.get("score"),
                             metrics={k: record[k] for k in ("ELR_mean", "ELR_std", "SR90", "RDE_mean", "MRR_mean",
                                                             "rollouts") if k in record})

    def save_checkpoint(self) -> None:
        """Save model, observation statistics and sidecar (the environment and settings it trains
        in, unevaluated) as ``checkpoints/step_N``, and the run's wall time then (``wall.json``:
        what a resumed command adds to)."""
        stem, wall_s = f"step_{self.num_timesteps}", self.wall_s()
        directory = self.run_dir / CHECKPOINTS_DIR
        with deferred_signals():  # the checkpoint's files and its sidecar, all or none
            self._save(directory, stem)
            self._sidecar({"steps": self.num_timesteps, "wall_s": wall_s}).save(directory / f"{stem}_{SIDECAR_FILE}")
        write_json(self.run_dir / WALL_FILE, {"steps": self.num_timesteps, "wall_s": wall_s})

    def _on_training_end(self) -> None:
        self.save_checkpoint()



def _interrupt(signum: int, frame: object) -> None:
    """Signal handler: stop training as Ctrl-C does (a checkpoint is saved)."""
    raise KeyboardInterrupt


@contextmanager
def deferred_signals(signals: tuple[int, ...] = (signal.SIGINT, signal.SIGTERM)) -> Iterator[None]:
    """Within the block, ``signals`` are only recorded; after it, the handlers from before run once
    for each signal that came (``SIG_DFL``: the signal is raised again; ``SIG_IGN``: nothing). A
    process-directed signal reaches whichever thread does not block it, and torch's threads do not,
    so masking the main thread does not keep a ``kill`` out of a checkpoint being written: a second
    ``kill`` during the save after the first once left a truncated file behind."""
    pending: list[int] = []
    previous = {s: signal.signal(s, lambda signum, frame: pending.append(signum)) for s in signals}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    for s in dict.fromkeys(pending):
        if callable(previous[s]):
            previous[s](s, None)
        elif previous[s] == signal.SIG_DFL:
            signal.raise_signal(s)


def policy_kwargs(net: str, action_variance: float) -> dict:
    """SB3 ``MlpPolicy`` arguments of every mimic policy: actor and critic tanh MLPs of the hidden
    sizes ``net`` ("256,256"), Gaussian actions of variance ``action_variance`` (rad²)."""
    sizes = [int(n) for n in str(net).split(",")]
    return {"net_arch": {"pi": sizes, "vf": sizes}, "activation_fn": torch.nn.Tanh,
            "log_std_init": 0.5 * math.log(action_variance)}


def check_denoiser(args: argparse.Namespace) -> None:
    """Refuse ``--denoise`` before any work where it cannot act (no corrupted reference to denoise)
    or where the denoiser reads another humanoid or frame rate than the run's environments."""
    if args.corrupted_fraction == 0 and args.eval_strength is None:
        raise ValueError("--denoise passes corrupted references through the IMU denoiser; this run has none "
                         "(give --corrupted-fraction > 0 or --eval-strength)")
    net = shared_network(str(args.denoise), "denoiser")
    model, fps = FOOT_MODELS[foot(args)], env_config(args).frame_rate_hz
    if net.model != model or abs(net.fps - fps) > 1e-6:
        raise ValueError(f"{args.denoise}: an IMU denoiser for {net.model} at {net.fps:g} Hz; this run's environments "
                         f"simulate {model} at {fps:g} Hz")


def check_preparation(args: argparse.Namespace) -> None:
    """Refuse, before any work, ``--swing-from`` without ``--swing-lift`` and ``--judge given`` where
    no reference is prepared (it would judge as ``corrupted`` does)."""
    mix = artefact_mix(args, args.corrupted_fraction)  # grounding_of and swing_lift_of refuse bad options
    if args.judge == "given" and (mix is None or not mix.prepares(args.corrupted_fraction > 0)):
        raise ValueError("--judge given judges against the reference as made, before --denoise, --even-legs, "
                         "--part-legs, --ground and --swing-lift prepare it; this run prepares none (give one of them)")
    if args.judge in ("clean", *JUDGED_WITHOUT) and not args.corrupted_fraction:
        raise ValueError(f"--judge {args.judge} judges corrupted episodes against another reference; this run "
                         f"has none (give --corrupted-fraction > 0)")


def check_privileged_critic(args: argparse.Namespace, run_dir: Path) -> None:
    """Refuse, before any work, ``--privileged-critic`` with what reads the rollouts' observations as the
    policy's own (the symmetric actor mirrors every column, the kickstarting teachers label them),
    ``--critic-lr-scale`` without it, and a resumed run whose network is of the other kind or whose
    critic learned at another rate (its optimizer's groups are the checkpoint's)."""
    privileged, scale = args.privileged_critic, args.critic_lr_scale  # run_args gives an older run the defaults
    checkpoint = newest_checkpoint(run_dir) if args.resume else None
    if checkpoint is not None:
        policy = PPO.load(checkpoint, device="cpu").policy
        trained = isinstance(policy, PrivilegedCriticPolicy)
        if trained != privileged:
            raise ValueError(f"{run_dir}: its critic was trained {'with' if trained else 'without'} the privileged "
                             f"inputs; resume it {'with' if trained else 'without'} --privileged-critic")
        if trained and policy.critic_lr_scale != scale:
            raise ValueError(f"{run_dir}: its critic learned at --critic-lr-scale {policy.critic_lr_scale:g}; resume "
                             f"it with that")
    if not privileged and scale != 1.0:
        raise ValueError("--critic-lr-scale sets the privileged critic's learning rate; give --privileged-critic")
    if privileged:
        for flag, on in (("--symmetric", args.symmetric), ("--kickstart", args.kickstart is not None)):
            if on:
                raise ValueError(f"--privileged-critic appends the critic's inputs to the stored observations; "
                                 f"{flag} reads them as the policy's own: give one of the two")


def check_symmetric(args: argparse.Namespace, run_dir: Path) -> None:
    """Refuse, before any work, a run whose actor would not be what ``--symmetric`` says: the
    symmetric actor without a policy to start from (its frozen statistics are the source's), a
    warm start from a symmetric network without ``--symmetric`` (the plain half would act), and a
    resumed run whose network is of the other kind."""
    checkpoint = newest_checkpoint(run_dir) if args.resume else None
    if checkpoint is not None:
        trained = load_policy(checkpoint).symmetric_network
        if trained != args.symmetric:
            raise ValueError(f"{run_dir}: its network was trained {'as' if trained else 'without'} the symmetric actor; "
                             f"resume it {'with' if trained else 'without'} --symmetric")
    elif args.symmetric and args.init_from is None:
        raise ValueError("--symmetric trains the symmetric actor of a trained policy: give --init-from (frozen "
                         "observation statistics need a policy's to start from)")
    elif args.init_from is not None and not args.symmetric and load_policy(args.init_from).symmetric_network:
        raise ValueError(f"{args.init_from}: a network trained as the symmetric actor; train on with --symmetric "
                         "(without it the run would act with one of its mirror halves)")


def newest_checkpoint(run_dir: Path) -> Path | None:
    found = [(int(CHECKPOINT.search(p.name).group(1)), p) for p in (run_dir / CHECKPOINTS_DIR).glob("step_*.zip")
             if CHECKPOINT.search(p.name)]
    return max(found)[1] if found else None


def run_args(run_dir: Path, parser: CliParser | None = None) -> argparse.Namespace:
    """The settings the run in ``run_dir`` trained with: its ``args.json`` over ``parser``'s
    defaults (default: :func:`build_parser`'s), so options newer than the run keep their defaults."""
    saved = Path(run_dir) / "args.json"
    if not saved.exists():
        raise FileNotFoundError(f"{saved}: not found: no run in {run_dir} to resume or read")
    defaults = (parser or build_parser()).parse_args(["--run-dir", str(run_dir)])
    return argparse.Namespace(**{**vars(defaults), **json.loads(saved.read_text()), "run_dir": Path(run_dir)})


def changed_settings(parser: argparse.ArgumentParser, stored: dict, given: argparse.Namespace,
                     explicit: set[str]) -> dict[str, tuple]:
    """The options a resuming command line sets to other values than the run's ``args.json``:
    ``{"--option": (stored, given)}`` among the ``explicit`` destinations (compared as JSON holds
    them, so a tuple equals its stored list); ``--resume`` and ``--run-dir`` are not settings."""
    def as_stored(value):
        return json.loads(json.dumps(value, default=str))

    options = {a.dest: a.option_strings[-1] for a in parser._actions if a.option_strings}
    settings = sorted(explicit - {"resume", "run_dir", "help"})
    return {options[dest]: (stored.get(dest), as_stored(getattr(given, dest))) for dest in settings
            if as_stored(stored.get(dest)) != as_stored(getattr(given, dest))}


@one_line_errors
def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    """Run the command line ``argv`` (default: ``sys.argv[1:]``): train, or resume, a run."""
    argv = sys.argv[1:] if argv is None else argv
    parser = build_parser(prog)
    args = parser.parse_args(argv)
    run_dir: Path = args.run_dir
    if args.resume:  # the stored settings, except what this command line sets explicitly
        stored = vars(run_args(run_dir, parser))
        history = stored.get("commands", [stored["command"]] if "command" in stored else [])
        given = {a.split("=", 1)[0] for a in argv if a.startswith("--")}  # "--stances=2" names --stances too
        explicit = {a.dest for a in parser._actions if given & set(a.option_strings)}
        for option, (before, after) in changed_settings(parser, stored, args, explicit).items():
            print(f"resuming with {option} changed: {before} -> {after} (checkpoints from now on record the new "
                  f"value; args.json's commands keep every command)", flush=True)
        args = argparse.Namespace(**{**stored, **{k: getattr(args, k) for k in explicit}, "run_dir": run_dir,
                                     "resume": True})
    elif (run_dir / "args.json").exists():
        raise ValueError(f"{run_dir}: already holds a run; pass --resume to continue it or pick a new --run-dir")
    else:
        history = []
    args.vec = vec_kind(args)  # recorded, so that a resumed run keeps its kind whatever the defaults become
    if args.n_envs is None:
        args.n_envs = 32 if args.vec in BATCHED_KINDS else 8
    if args.n_steps is None:  # the default: 8192 steps per update, however many envs
        args.n_steps = max(1, STEPS_PER_UPDATE // args.n_envs)
    if args.gait_ablation is not None and args.env_id != GAIT_ENV_ID:
        raise ValueError(f"--gait-ablation is an ablation of {GAIT_ENV_ID}; this run trains {args.env_id}")
    if args.denoise is not None:
        check_denoiser(args)
    check_slowing(args.denoise, args.denoise_slow)
    check_preparation(args)
    check_kickstart(args)
    check_privileged_critic(args, run_dir)
    check_symmetric(args, run_dir)
    push, varied = pushes(args), dynamics(args)  # refused here, before the clips take their time to load
    posture_ranges(args), stance_extra(args)
    vec_cls, vec_kwargs, collect_threads, update_threads = vec_env_settings(args)
    torch.set_num_threads(collect_threads)
    clips = training_motions(args)
    training_kwargs = env_kwargs(args, clips, args.corrupted_fraction)
    if push is not None:  # MimicGait-v0 takes neither argument (pushes() and dynamics() refuse it)
        training_kwargs["pushes"] = push
    if varied is not None:
        training_kwargs["dynamics"] = varied
    venv = make_vec_env(args.env_id, n_envs=args.n_envs, seed=args.seed, vec_env_cls=vec_cls, vec_env_kwargs=vec_kwargs,
                        env_kwargs=training_kwargs)
    privileged = args.privileged_critic
    if privileged:
        venv = PrivilegedObservation(venv)
    eval_kwargs = env_kwargs(args, evaluation_clips(args), 0.0)
    if args.eval_strength is not None:
        eval_kwargs["artefacts"] = ArtefactMix(strength=(args.eval_strength, args.eval_strength), fraction=1.0,
                                               variants_per_clip=args.eval_episodes, denoiser=args.denoise,
                                               denoise_slow_s=args.denoise_slow, **preparation_of(args),
                                               judge="given" if args.judge in ("given", *JUDGED_WITHOUT)
                                               else "corrupted")
    eval_env = gym.make(args.env_id, **eval_kwargs)
    eval_env.reset(seed=10_000 + args.seed)
    maps = MirrorMaps.of(eval_env) if args.symmetric else None  # refuses a layout it does not know, before the run
    teachers = [kickstarter(args, eval_env, clips)] if args.kickstart else []  # bad teachers: before the run
    # the run is recorded only now that every clip has loaded: bad input leaves no run behind
    run_dir.mkdir(parents=True, exist_ok=True)
    command = ["agents/train_ppo.py", *argv]
    args.commands = history + [command]  # every command that trained this run, in order
    write_json(run_dir / "args.json", {**vars(args), "run_dir": str(run_dir), "command": command})

    checkpoint = newest_checkpoint(run_dir) if args.resume else None
    if checkpoint is not None:
        stats = checkpoint.with_name(checkpoint.stem + "_vecnormalize.pkl")
        venv = VecNormalize.load(str(stats), venv)
        model = PPO.load(checkpoint, env=venv, device=args.device, tensorboard_log=str(run_dir / "tb"),
                         n_steps=args.n_steps)  # --n-steps with --n-envs on resume: the rollout the command asks for
        print(f"resuming from {checkpoint} at {model.num_timesteps} steps", flush=True)
    else:
        if args.resume:
            print(f"no checkpoint in {run_dir}; starting from scratch", flush=True)
        kwargs = policy_kwargs(args.net, args.action_variance)
        if maps is not None:
            kwargs["mirror"] = maps_as_kwargs(maps)
        if privileged:
            kwargs.update(policy_inputs=venv.policy_inputs, critic_lr_scale=args.critic_lr_scale)
        policy_class = (SymmetricActorCriticPolicy if maps is not None else PrivilegedCriticPolicy if privileged
                        else "MlpPolicy")
        model = PPO(policy_class, venv, learning_rate=args.lr,
                    n_steps=args.n_steps, batch_size=args.batch_size, n_epochs=args.epochs, gamma=args.gamma,
                    gae_lambda=args.gae_lambda, clip_range=args.clip_range, seed=args.seed, device=args.device,
                    tensorboard_log=str(run_dir / "tb"), verbose=0, policy_kwargs=kwargs)
        if args.init_from is not None:  # warm start: another run's weights and observation statistics
            venv = (warm_start_privileged if privileged else warm_start)(model, venv, load_policy(args.init_from),
                                                                        env_config(args), args.gamma)
            set_action_variance(model, args.action_variance)  # this run's noise, not the source's
            if maps is not None:  # the network mirrors normalised inputs: statistics symmetric, and kept so
                symmetric = symmetrise_statistics(venv.obs_rms, maps)  # the first layers absorb the change
                model.policy.load_state_dict(renormalised_inputs(model.policy.state_dict(), venv.obs_rms, symmetric,
                                                                 venv.epsilon))
                venv.obs_rms, venv.training = symmetric, False
            model.set_env(venv)
            print(f"initialised from {args.init_from}{' as its symmetric actor' if maps is not None else ''}",
                  flush=True)
        else:
            venv = observation_normalizer(venv, args.gamma)
            model.set_env(venv)
    model.policy.log_std.requires_grad_(False)  # fixed exploration noise (ADAPT: σ² = 0.03)
    remaining = args.total_steps - model.num_timesteps
    if remaining <= 0:
        print(f"run already has {model.num_timesteps} >= --total-steps {args.total_steps} steps")
        venv.close()
        return
    callback = CheckpointAndEvaluate(run_dir, eval_env, args)
    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}  # restored when training ends
    signal.signal(signal.SIGTERM, _interrupt)  # `kill` saves a checkpoint too (background jobs ignore SIGINT)
    try:
        # the teachers before UpdateThreads: their fit at a rollout's start runs with the update's threads
        callbacks = [callback, *teachers, UpdateThreads(collect_threads, update_threads), *kl_following(args.target_kl)]
        model.learn(remaining, callback=CallbackList(callbacks),
                    reset_num_timesteps=checkpoint is None, tb_log_name="ppo",
                    progress_bar=not args.no_progress)
    except KeyboardInterrupt:  # Ctrl-C, `kill` or `timeout`: keep what was learned, resumable with --resume
        for s in (signal.SIGINT, signal.SIGTERM):  # stopping already: a second signal must not cut the save short
            signal.signal(s, signal.SIG_IGN)
        callback.save_checkpoint()
        print(f"interrupted at {model.num_timesteps} steps; checkpoint saved, continue with --resume", flush=True)
    finally:
        venv.close()
        for s, handler in handlers.items():
            signal.signal(s, handler)


if __name__ == "__main__":
    main()
