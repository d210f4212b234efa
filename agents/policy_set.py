"""A policy set: shipped policies, each for a class of motion, and the rule that picks one per clip.

A clip is routed before anything is simulated, from the reference alone: a clip whose name matches
a glob of ``clips`` (:func:`fnmatch.fnmatchcase`; the first that matches, in the file's order) goes
to that policy (a specialist for takes the others do not perform); so does a copy made of such a
clip, whose name adds its transforms to the clip's (``"NAME (mirrored) (x1.5 speed)"``,
:func:`source_name`), so that a glob naming a take exactly routes its mirrored, time-warped,
reversed and posture copies with it (a glob may name a copy to route it apart: ``"*(reversed)*"``,
listed first); else a clip whose root moves backwards relative to the pelvis heading (median speed
along the heading below ``-backward_speed_mps``) goes to the ``backward`` policy; else the optional
rules, in the order of :data:`OPTIONAL_RULES`, each only if the set has its policy:

- ``dash``: a clip whose root's median horizontal speed is above ``dash_speed_mps`` (an expert for sprinting);
- ``fast``: the same above ``fast_speed_mps`` (an expert for running, in the manner of PHC's primitives, Luo et
  al. 2023);
- ``sideways``: a clip whose root's median speed across the pelvis heading is above ``sideways_speed_mps``
  (either way, :func:`walks_sideways`);
- ``turn``: a clip whose pelvis heading turns faster than ``turn_rate_rad_s`` on average over the clip (either
  way, :func:`turns`);

and every other clip goes to ``default``. The rules read the clip as given (corrupted or not), so they
need no ground truth. On the motion library the backward rule separates the 15 backward walks (median
heading speed −0.35 to −0.94 m/s) from every other take (≥ 0.00 m/s); the training split's walks go
at median speeds up to 1.57 m/s (1.96 at the 1.25× pace training plays them at), its runs at
1.49–3.22 m/s and its dashes at 2.49–4.41 m/s (above 3.0 m/s: 7 of its 10 dashes and 2 of its 10
runs). Across the heading its takes other than sideways walks and slower than 2 m/s go at median
speeds of at most 0.14 m/s either way clean and 0.18 m/s in any of 10 IMU draws (the IMU's heading
drift turns the heading against the path), its sideways walks at 0.07–0.53 m/s, 15 of its 22 above
0.2 m/s clean (``bench/rounds/r36/route_speeds.py``, ``bench/results/round36_route_speeds.json``).
DeepMimic's training turns turn at 0.425 and 1.389 rad/s, every other training take at most 0.140 in
any IMU draw (``bench/rounds/r37/route_turns.py``, ``bench/results/round37_route_turns.json``).

On disk a policy set is a directory holding ``policy_set.json``::

    {"format": "physmimic.policy_set/1", "default": "../mimic_general",
     "backward": "../mimic_walk_back", "backward_speed_mps": 0.2,
     "dash": "../mimic_dash", "dash_speed_mps": 3.0,
     "fast": "../mimic_fast", "fast_speed_mps": 2.0,
     "sideways": "../mimic_sideways", "sideways_speed_mps": 0.2,
     "turn": "../mimic_turning", "turn_rate_rad_s": 0.3,
     "clips": {"*dash_active_001*": "../dash_active"}}

with the policy directories relative to it (``dash``, ``fast``, ``sideways``, ``turn`` and ``clips``
optional). ``agents/evaluate.py`` and ``agents/clean.py`` take a policy set wherever they take a policy.

A set may also give a member the preparation it tracks best behind an IMU denoiser: ``"denoise_slow_s":
{"dash": 0.5}`` tracks the takes routed to the ``dash`` policy behind the denoiser's corrections slowed to 0.5 s
(:class:`perception.imu_denoiser.SlowCorrections`, ``--denoise-slow 0.5``) whatever the command line's
``--denoise-slow`` says for the others (:func:`member_denoiser`); without a denoiser it changes nothing.
"""

from __future__ import annotations

import fnmatch
import json
import math
import numbers
import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from agents.policy import MimicPolicy, PolicyError, load_policy
from perception.imu_denoiser import DenoiserEnsemble, IMUDenoiser, SlowCorrections, slowed, slowing_of
from reference_motion import quality
from reference_motion import rotations as rot
from reference_motion.motion import Motion

SET_FILE = "policy_set.json"
FORMAT = "physmimic.policy_set/1"
OPTIONAL_RULES = ("dash", "fast", "sideways", "turn")
"""The optional rules, in the order they route: each a policy directory field, its threshold field
(:data:`RULE_THRESHOLDS`) and its test (:data:`RULE_TESTS`)."""
RULE_THRESHOLDS = {"dash": "dash_speed_mps", "fast": "fast_speed_mps", "sideways": "sideways_speed_mps",
                   "turn": "turn_rate_rad_s"}
"""Each optional rule's threshold field (its unit in its name: m/s or rad/s)."""
THRESHOLD_FIELDS = ("backward_speed_mps", *RULE_THRESHOLDS.values())
"""Every threshold field of a set: the backward rule's and the optional rules'."""
ROLES = ("default", "backward", *OPTIONAL_RULES)
"""The set's policy fields, each a role a member can play (the clips' globs aside)."""
SET_FIELDS = {"format", "default", "backward", "clips", "denoise_slow_s", *OPTIONAL_RULES, *THRESHOLD_FIELDS}
"""The fields ``policy_set.json`` may hold."""


def heading_frame_velocity(qpos: np.ndarray, fps: float) -> np.ndarray:
    """``(T, 2)`` the root's horizontal velocity (m/s) in each frame of ``qpos (T, nq)`` (free joint
    first: position, then w-x-y-z quaternion; world, z up), in the pelvis heading's frame: along the
    heading (its x axis projected on the ground; negative while moving backwards), then across it
    (positive to the left)."""
    if len(qpos) < 2:
        raise ValueError(f"the root's velocity needs at least 2 frames, got {len(qpos)}")
    return quality.heading_frame_velocity(qpos[:, :2], rot.yaw(qpos[:, 3:7]), fps)


def heading_speeds(qpos: np.ndarray, fps: float) -> np.ndarray:
    """``(T,)`` the root's horizontal velocity (m/s) along the pelvis heading (:func:`heading_frame_velocity`)."""
    return heading_frame_velocity(qpos, fps)[:, 0]


TRANSFORM_SUFFIXES = re.compile(
    r"(?: \((?:mirrored|reversed|x[0-9.e+-]+ speed|posture(?: \d+)?|turned -?[0-9.e+-]+°|stance [+-][0-9.e+-]+ m)\))+$")
"""The suffixes :mod:`reference_motion.transforms`, :func:`reference_motion.library.posture_copies`
and :func:`reference_motion.stance.wider_stance` append to the name of a copy: ``" (mirrored)"``,
``" (reversed)"``, ``" (x1.5 speed)"``, ``" (posture 0)"``, ``" (turned 90°)"``,
``" (stance +0.2 m)"``, any number of them in a row."""


def source_name(name: str) -> str:
    """The name of the clip a copy named ``name`` was made from: ``name`` without the transforms'
    suffixes (``"walk_001 (mirrored) (x1.5 speed)"`` → ``"walk_001"``); other parentheses, such as
    ``" (cleaned)"``, stay."""
    return TRANSFORM_SUFFIXES.sub("", name)


def walks_backward(motion: Motion, backward_speed_mps: float) -> bool:
    """Whether ``motion``'s median heading speed (:func:`heading_speeds`) is below ``-backward_speed_mps``."""
    return bool(np.median(heading_speeds(motion.qpos, motion.fps)) < -backward_speed_mps)


def walks_sideways(motion: Motion, sideways_speed_mps: float) -> bool:
    """Whether the median of ``motion``'s root velocity across the pelvis heading
    (:func:`heading_frame_velocity`, m/s, either way) is above ``sideways_speed_mps`` (m/s)."""
    return bool(abs(np.median(heading_frame_velocity(motion.qpos, motion.fps)[:, 1])) > sideways_speed_mps)


def goes_fast(motion: Motion, fast_speed_mps: float) -> bool:
    """Whether ``motion``'s root's median horizontal speed (:func:`median_ground_speed`, m/s) is above
    ``fast_speed_mps`` (m/s)."""
    return median_ground_speed(motion.qpos, motion.fps) > fast_speed_mps


def turn_rate(qpos: np.ndarray, fps: float) -> float:
    """How fast the pelvis heading of ``qpos (T, nq)`` (free joint first; world, z up) turns on average (rad/s,
    either way): the heading's net change from the first frame to the last, unwrapped, over the clip's
    duration (at least 2 frames). A clip that turns and turns back counts as straight; a walk's sway from step
    to step cancels where the clip ends at the phase it began at, and otherwise adds at most its peak-to-peak
    angle over the duration (DeepMimic's 0.8 s run, swaying about 20°, could read 0.44 rad/s; the training
    takes other than DeepMimic's turns read at most 0.14, ``bench/results/round37_route_turns.json``)."""
    if len(qpos) < 2:
        raise ValueError(f"turn_rate needs at least 2 frames, got {len(qpos)}")
    heading = np.unwrap(rot.yaw(qpos[:, 3:7]))
    return float(abs(heading[-1] - heading[0]) * fps / (len(qpos) - 1))


def turns(motion: Motion, turn_rate_rad_s: float) -> bool:
    """Whether ``motion``'s pelvis heading turns faster than ``turn_rate_rad_s`` (rad/s, :func:`turn_rate`)."""
    return turn_rate(motion.qpos, motion.fps) > turn_rate_rad_s


def median_ground_speed(qpos: np.ndarray, fps: float) -> float:
    """The median horizontal speed (m/s) of the root over the frames of ``qpos (T, nq)`` (world, z up;
    at least 2 frames)."""
    if len(qpos) < 2:
        raise ValueError(f"median_ground_speed needs at least 2 frames, got {len(qpos)}")
    return float(np.median(np.linalg.norm(np.gradient(qpos[:, :2], 1.0 / fps, axis=0), axis=1)))


RULE_TESTS: dict[str, Callable[[Motion, float], bool]] = {"dash": goes_fast, "fast": goes_fast,
                                                           "sideways": walks_sideways, "turn": turns}
"""Each optional rule's test of a clip against the rule's threshold (:data:`RULE_THRESHOLDS`)."""


@dataclass(frozen=True)
class PolicySet:
    """Policies by motion class.

    Attributes:
        path: the set's directory.
        default: directory of the policy for every clip not routed elsewhere.
        backward: directory of the policy for clips walked backwards.
        backward_speed_mps: a clip whose median heading speed is below minus this (m/s) is walked backwards.
        clips: ``((glob, directory), ...)``: a clip whose name matches a glob goes to its policy,
            before the other rules (the first glob that matches).
        dash: directory of the policy for clips whose root moves faster than ``dash_speed_mps``
            (median horizontal speed, :func:`median_ground_speed`), after the backward rule;
            ``None``: no such rule.
        dash_speed_mps: that speed (m/s).
        fast: directory of the policy for clips whose root moves faster than ``fast_speed_mps``
            (median horizontal speed), after the dash rule; ``None``: no such rule.
        fast_speed_mps: that speed (m/s).
        sideways: directory of the policy for clips walked sideways (:func:`walks_sideways` with
            ``sideways_speed_mps``), after the fast rule; ``None``: no such rule.
        sideways_speed_mps: that speed (m/s).
        turn: directory of the policy for clips whose pelvis heading turns faster than ``turn_rate_rad_s``
            (:func:`turns`), after the sideways rule; ``None``: no such rule.
        turn_rate_rad_s: that rate (rad/s).
        denoise_slow_s: ``((role, seconds), ...)``: the takes routed to the policy of each ``role`` (one of
            :data:`ROLES`) are tracked behind an IMU denoiser's corrections slowed to these seconds
            (:func:`member_denoiser`); every other member as the command line says.
    """

    path: Path
    default: Path
    backward: Path
    backward_speed_mps: float = 0.2
    clips: tuple[tuple[str, Path], ...] = ()
    dash: Path | None = None
    dash_speed_mps: float = 3.0
    fast: Path | None = None
    fast_speed_mps: float = 2.0
    sideways: Path | None = None
    sideways_speed_mps: float = 0.2
    turn: Path | None = None
    turn_rate_rad_s: float = 0.3
    denoise_slow_s: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        for name in THRESHOLD_FIELDS:
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, numbers.Real) or not (math.isfinite(value) and value >= 0):
                unit = "rad/s" if name.endswith("_rad_s") else "m/s"
                raise PolicyError(f"{self.path / SET_FILE}: {name} must be a finite number >= 0 ({unit}), got {value!r}")
            object.__setattr__(self, name, float(value))
        if self.dash is not None and self.fast is not None and self.dash_speed_mps <= self.fast_speed_mps:
            raise PolicyError(f"{self.path / SET_FILE}: dash_speed_mps ({self.dash_speed_mps:g} m/s) must be above "
                              f"fast_speed_mps ({self.fast_speed_mps:g} m/s): the dash rule routes first, so the fast "
                              "policy would get no clip")
        slowing = []
        for role, seconds in self.denoise_slow_s:
            if role not in ROLES or getattr(self, role) is None:
                raise PolicyError(f"{self.path / SET_FILE}: denoise_slow_s names {role!r}, expected a role the set has "
                                  f"a policy for: {', '.join(r for r in ROLES if getattr(self, r) is not None)}")
            if isinstance(seconds, bool) or not isinstance(seconds, numbers.Real) or not (math.isfinite(seconds)
                                                                                          and seconds > 0):
                raise PolicyError(f"{self.path / SET_FILE}: denoise_slow_s of {role} must be a finite number of "
                                  f"seconds > 0, got {seconds!r}")
            slowing.append((role, float(seconds)))
        object.__setattr__(self, "denoise_slow_s", tuple(slowing))
        for policy in self.policies:
            given = {seconds for role, seconds in slowing if getattr(self, role) == policy}
            unslowed = [role for role in ROLES if getattr(self, role) == policy and role not in dict(slowing)]
            if len(given) > 1 or (given and unslowed):
                raise PolicyError(f"{self.path / SET_FILE}: {policy} plays several roles with different "
                                  f"denoise_slow_s; a member tracks one way")

    def slowing(self, policy: Path) -> float | None:
        """The seconds of denoiser corrections the set gives its member ``policy`` (a path of
        :attr:`policies`) in :attr:`denoise_slow_s`; ``None``: as the command line says."""
        return next((seconds for role, seconds in self.denoise_slow_s if getattr(self, role) == Path(policy)), None)

    def denoiser_for(self, policy: Path, denoiser: IMUDenoiser | DenoiserEnsemble | SlowCorrections | None,
                     ) -> IMUDenoiser | DenoiserEnsemble | SlowCorrections | None:
        """The denoiser the member ``policy`` (a path of :attr:`policies`) tracks its takes behind: ``denoiser``
        as the command line made it, or, where :meth:`slowing` gives the member seconds, that denoiser's
        corrections slowed to them (the command line's slowing replaced; a clip glob routing to the same policy
        is slowed with it); ``None`` stays ``None`` (takes tracked as given)."""
        seconds = self.slowing(policy)
        if denoiser is None or seconds is None:
            return denoiser
        return slowed(denoiser.denoiser if isinstance(denoiser, SlowCorrections) else denoiser, seconds)

    def route(self, motion: Motion) -> Path:
        """The directory of the policy that performs ``motion``."""
        names = (motion.name, source_name(motion.name))
        named = next((policy for glob, policy in self.clips if any(fnmatch.fnmatchcase(n, glob) for n in names)), None)
        if named is not None:
            return named
        if walks_backward(motion, self.backward_speed_mps):
            return self.backward
        for rule in OPTIONAL_RULES:
            policy = getattr(self, rule)
            if policy is not None and RULE_TESTS[rule](motion, getattr(self, RULE_THRESHOLDS[rule])):
                return policy
        return self.default

    def grouped(self, motions: list[Motion]) -> dict[Path, list[int]]:
        """The indices of ``motions`` grouped by the policy that performs each (:meth:`route`: its
        directory, or a run's checkpoint file where the set names one), the groups in order of first
        use and the indices in order."""
        groups: dict[Path, list[int]] = {}
        for i, motion in enumerate(motions):
            groups.setdefault(self.route(motion), []).append(i)
        return groups

    @property
    def policies(self) -> list[Path]:
        """Every policy of the set (a directory, or a run's checkpoint file), each once: default,
        backward, the optional rules' in :data:`OPTIONAL_RULES`' order, then the clips' policies."""
        optional = [getattr(self, rule) for rule in OPTIONAL_RULES if getattr(self, rule) is not None]
        return list(dict.fromkeys([self.default, self.backward, *optional, *(policy for _, policy in self.clips)]))

    def save(self) -> Path:
        """Write ``policy_set.json`` (policy paths relative to the set's directory)."""
        self.path.mkdir(parents=True, exist_ok=True)

        def rel(policy: Path) -> str:
            return os.path.relpath(policy.resolve(), self.path.resolve())

        spec = {"format": FORMAT, "default": rel(self.default), "backward": rel(self.backward),
                "backward_speed_mps": self.backward_speed_mps}
        for rule in OPTIONAL_RULES:
            if getattr(self, rule) is not None:
                spec |= {rule: rel(getattr(self, rule)), RULE_THRESHOLDS[rule]: getattr(self, RULE_THRESHOLDS[rule])}
        if self.clips:
            spec["clips"] = {glob: rel(policy) for glob, policy in self.clips}
        if self.denoise_slow_s:
            spec["denoise_slow_s"] = dict(self.denoise_slow_s)
        out = self.path / SET_FILE
        out.write_text(json.dumps(spec, indent=1))
        return out


def is_policy_set(path: str | Path) -> bool:
    """Whether ``path`` is a policy-set directory (holds ``policy_set.json``)."""
    return (Path(path) / SET_FILE).is_file()


def load_policy_set(path: str | Path) -> PolicySet:
    """Read a policy-set directory; :class:`PolicyError` names a missing file or field. The policies'
    paths are the set's joined with the file's relative ones and normalised (``SET/../mimic_walk`` →
    ``mimic_walk`` beside ``SET``), so that records name each policy by its own path."""
    path = Path(path)

    def member(relative: str) -> Path:
        return Path(os.path.normpath(path / relative))

    file = path / SET_FILE
    try:
        spec = json.loads(file.read_text())
    except (OSError, json.JSONDecodeError) as err:
        raise PolicyError(f"{file}: cannot read the policy set: {err}") from err
    if not isinstance(spec, dict):
        raise PolicyError(f"{file}: holds a JSON {type(spec).__name__}, expected an object with format, default and backward")
    if spec.get("format") != FORMAT:
        raise PolicyError(f"{file}: format {spec.get('format')!r}, expected {FORMAT!r}")
    missing = [k for k in ("default", "backward") if not isinstance(spec.get(k), str)]
    if missing:
        raise PolicyError(f"{file}: field(s) {', '.join(missing)} missing; expected policy directories relative to {path}")
    unknown = sorted(set(spec) - SET_FIELDS)
    if unknown:
        raise PolicyError(f"{file}: unknown field(s) {', '.join(unknown)}; expected only {', '.join(sorted(SET_FIELDS))}")
    optional = {}
    for rule in OPTIONAL_RULES:
        threshold = RULE_THRESHOLDS[rule]
        if threshold in spec and rule not in spec:
            raise PolicyError(f"{file}: {threshold} is given without {rule}, the policy directory it sends "
                              f"{rule} clips to")
        policy = spec.get(rule)
        if rule in spec and not isinstance(policy, str):
            raise PolicyError(f"{file}: {rule} must be a policy directory relative to {path}, got {policy!r}")
        if policy is not None:
            optional |= {rule: member(policy), threshold: spec.get(threshold, getattr(PolicySet, threshold))}
    clips = spec.get("clips", {})
    if not (isinstance(clips, dict) and all(isinstance(v, str) for v in clips.values())):
        raise PolicyError(f"{file}: clips must be an object of clip-name globs to policy directories relative to "
                          f"{path}, got {clips!r}")
    slowing = spec.get("denoise_slow_s", {})
    if not isinstance(slowing, dict):
        raise PolicyError(f"{file}: denoise_slow_s must be an object of roles to seconds, e.g. {{\"dash\": 0.5}}, "
                          f"got {slowing!r}")
    return PolicySet(path, member(spec["default"]), member(spec["backward"]),
                     spec.get("backward_speed_mps", PolicySet.backward_speed_mps),
                     tuple((glob, member(policy)) for glob, policy in clips.items()), **optional,
                     denoise_slow_s=tuple(slowing.items()))


def slowing_label(path: str | Path, denoiser: object) -> str:
    """What results add to the name of the policy set ``path`` tracking takes behind ``denoiser`` for the
    members it slows its own way (:attr:`PolicySet.denoise_slow_s`), e.g. ``" + its dash policy's
    denoiser corrections slowed to 0.5 s"``; ``""`` for a plain policy, no denoiser or no such member."""
    if denoiser is None or not is_policy_set(path):
        return ""
    return "".join(f" + its {role} policy's denoiser corrections slowed to {seconds:g} s"
                   for role, seconds in load_policy_set(path).denoise_slow_s)


def member_denoiser(path: str | Path, policy: MimicPolicy,
                    denoiser: IMUDenoiser | DenoiserEnsemble | SlowCorrections | None,
                    ) -> IMUDenoiser | DenoiserEnsemble | SlowCorrections | None:
    """The denoiser ``policy`` (a member :func:`route_clips` loaded from the set ``path``, or a plain
    policy directory ``path``) tracks its takes behind: :meth:`PolicySet.denoiser_for` of the set,
    ``denoiser`` itself for a plain policy or none."""
    if denoiser is None or not is_policy_set(path):
        return denoiser
    return load_policy_set(path).denoiser_for(policy.source or policy.path, denoiser)


def slowed_members(behind: Mapping[str, object], denoiser: object) -> dict[str, float | None]:
    """``{member: seconds}`` for the members of ``behind`` (``{member name: the denoiser it tracks its
    takes behind}``, :func:`member_denoiser`'s) that a policy set slows its own way rather than tracking them
    behind ``denoiser``, the one the command line gave: what results record as ``denoise_slow_s_of_members``
    (empty for a plain policy or a set that slows none)."""
    return {name: slowing_of(own) for name, own in behind.items() if own is not denoiser}


def route_clips(path: str | Path, load: Callable[[str], list[Motion]]) -> list[tuple[MimicPolicy, list[Motion]]]:
    """The clips ``load(foot)`` returns (``foot``: the policies' foot model, ``"one"`` or ``"two"``),
    grouped by the policy that performs them: ``[(policy, clips), ...]``, one group for a plain
    policy directory ``path``, one per policy used for a policy set (clips in their order)."""
    if not is_policy_set(path):
        policy = load_policy(path)
        return [(policy, load(policy.foot))]
    policy_set = load_policy_set(path)
    policies = {p: load_policy(p) for p in policy_set.policies}
    feet = {p.foot for p in policies.values()}
    if len(feet) > 1:
        raise PolicyError(f"{policy_set.path / SET_FILE}: its policies drive different humanoids ({sorted(feet)}); "
                          "a policy set needs one foot model")
    motions = load(feet.pop())
    return [(policies[p], [motions[i] for i in indices]) for p, indices in policy_set.grouped(motions).items()]
