"""Kickstarting PPO on the takes a policy cannot find by itself (``train_ppo.py --kickstart SET``).

PPO trains the policy on every take as before; after each of its updates, before the next rollout, a
supervised step pulls the policy's mean action towards a teacher's on the states of the takes a
teacher is given for (Schmitt et al. 2018, "Kickstarting deep reinforcement learning": an auxiliary
imitation loss on the student's own states). The teachers are the clip-routed policies of a policy
set (``agents/policy_set.py``; its ``default`` and ``backward`` policies teach nothing: PPO alone
trains every other take). Unlike a DAgger student (``agents/distill.py``), the network keeps its own
weights and its PPO objective on every take, so what PPO made it robust to is not re-fitted away.

For a rollout's states of taught takes (their clip's name, or the clip it was copied from, matches a
glob of the set; by default only in clean episodes, :attr:`KickstartConfig.corrupted`), with ``s`` the
observation normalised as PPO saw it, ``a_T`` the teacher's mean action on the raw observation (its
first values, as :func:`agents.teachers.check_teacher_layouts` allows) and ``μ(s)`` the policy's mean
action, :attr:`KickstartConfig.epochs` passes of minibatch Adam minimise
``mean ||μ(s) − a_T||²`` (rad²).
"""

from __future__ import annotations

import fnmatch
from dataclasses import asdict, dataclass
from pathlib import Path

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3.common.callbacks import BaseCallback

from agents.policy import MimicPolicy, load_policy
from agents.policy_set import load_policy_set, source_name
from agents.teachers import check_teacher_layouts, mean_actions, observing_in


@dataclass(frozen=True)
class KickstartConfig:
    """The supervised step between PPO updates.

    Attributes:
        policy_set: the policy set whose clip-routed policies teach (``--kickstart``).
        epochs: passes over the last rollout's taught states after each PPO update (``--kickstart-epochs``).
        lr: Adam's learning rate of those passes (``--kickstart-lr``; PPO's is separate).
        batch_size: states per minibatch.
        corrupted: whether the teachers also teach the taught takes' IMU-corrupted episodes
            (``--kickstart-corrupted``). Off by default: a teacher trained on clean takes chases a
            corrupted reference's artefacts, and the policy would learn to chase them too.
    """

    policy_set: str
    epochs: int = 2
    lr: float = 5e-5
    batch_size: int = 512
    corrupted: bool = False

    def __post_init__(self) -> None:
        if self.epochs < 1 or self.batch_size < 1 or not self.lr > 0:
            raise ValueError(f"KickstartConfig: epochs and batch_size must be >= 1 and lr > 0, got {asdict(self)}")


def taught_globs(policy_set: str | Path) -> list[tuple[str, Path]]:
    """``[(glob, teacher directory), ...]``: the clip-routed policies of ``policy_set``; a
    :class:`ValueError` naming the set when it routes no clip (it would teach nothing)."""
    routes = list(load_policy_set(policy_set).clips)
    if not routes:
        raise ValueError(f"--kickstart {policy_set}: the policy set routes no clip to a policy of its own "
                         f"(its 'clips'); nothing would be taught")
    return routes


class Teaching:
    """Which teacher, if any, teaches a clip: the first glob of the set that the clip's name or its
    source's name (without the transforms' suffixes) matches, as the set routes clips."""

    def __init__(self, routes: list[tuple[str, int]], teachers: list[MimicPolicy]):
        """``routes``: ``[(glob, index in teachers), ...]`` in the set's order."""
        self.routes, self.teachers = routes, teachers
        self._cache: dict[str, int | None] = {}

    @classmethod
    def load(cls, policy_set: str | Path, env: gym.Env) -> Teaching:
        """The teachers of ``policy_set``, each observing in ``env``'s frame (a teacher trained in
        another frame of the same layout is turned into it, :meth:`MimicPolicy.observing`; another
        layout raises :class:`agents.policy.PolicyError`) and checked to read ``env``'s observation
        and act with its actions (:func:`agents.teachers.check_teacher_layouts`)."""
        routes = taught_globs(policy_set)
        directories = list(dict.fromkeys(directory.resolve() for _, directory in routes))
        frame = env.unwrapped.config.obs_frame
        teachers = [observing_in(load_policy(directory), frame, "the run") for directory in directories]
        check_teacher_layouts(teachers, env)
        return cls([(glob, directories.index(directory.resolve())) for glob, directory in routes], teachers)

    def check_teaches(self, clips: list[str], corrupted_fraction: float, corrupted: bool) -> None:
        """A :class:`ValueError` unless some of the training ``clips`` (names) have a teacher and some of
        their episodes are taught: clean ones, unless ``corrupted`` (:attr:`KickstartConfig.corrupted`),
        are ``1 - corrupted_fraction`` of them."""
        if not any(self.teacher_of(clip) is not None for clip in clips):
            globs = ", ".join(glob for glob, _ in self.routes)
            raise ValueError(f"--kickstart: no training clip matches a glob of the set ({globs}); nothing would be "
                             f"taught")
        if corrupted_fraction >= 1 and not corrupted:
            raise ValueError("--kickstart teaches clean episodes only, and --corrupted-fraction 1 leaves none: give "
                             "--kickstart-corrupted or a lower --corrupted-fraction")

    def teacher_of(self, clip: str) -> int | None:
        """Index in :attr:`teachers` of ``clip``'s teacher, or ``None``: PPO alone trains it."""
        if clip not in self._cache:
            names = (clip, source_name(clip))
            self._cache[clip] = next((teacher for glob, teacher in self.routes
                                      if any(fnmatch.fnmatchcase(n, glob) for n in names)), None)
        return self._cache[clip]


def kickstart_loss(mean_actions: torch.Tensor, teacher_actions: torch.Tensor) -> torch.Tensor:
    """Mean over states of ``||μ − a_T||²`` for ``(N, A)`` mean actions and teacher actions (rad)."""
    return ((mean_actions - teacher_actions) ** 2).sum(dim=1).mean()


class Kickstart(BaseCallback):
    """Gathers, while PPO collects a rollout, the states of taught takes (normalised as PPO saw them,
    and raw for the teachers); after the update that follows, fits the policy's mean action to the
    teachers' on them (:func:`kickstart_loss`). ``logger`` records ``kickstart/states`` and
    ``kickstart/loss`` (before the passes) after each rollout that met taught states. Its Adam starts
    afresh with every ``learn`` (a resumed run included): its moments are not in the checkpoint."""

    def __init__(self, teaching: Teaching, config: KickstartConfig, seed: int = 0):
        super().__init__()
        self.teaching, self.config = teaching, config
        self.rng = np.random.default_rng(seed)
        self._normalised: list[np.ndarray] = []
        self._raw: list[np.ndarray] = []
        self._who: list[int] = []
        self._acted_raw: np.ndarray | None = None
        self.optimizer: torch.optim.Optimizer | None = None

    def _on_training_start(self) -> None:
        self.optimizer = torch.optim.Adam(self.model.policy.parameters(), lr=self.config.lr)

    def _on_rollout_start(self) -> None:
        if self._who:
            self.fit()
        self._acted_raw = self.training_env.get_original_obs()

    def _on_step(self) -> bool:
        acted = self.locals["obs_tensor"].cpu().numpy()  # what the policy acted on, normalised
        for i, info in enumerate(self.locals["infos"]):  # on a done step the info is still the acted episode's
            teacher = self.teaching.teacher_of(info["clip"])
            if teacher is not None and (self.config.corrupted or not info["corrupted"]):
                self._normalised.append(acted[i])
                self._raw.append(self._acted_raw[i])
                self._who.append(teacher)
        self._acted_raw = self.training_env.get_original_obs()  # the next states acted on
        return True

    def labels(self) -> tuple[np.ndarray, np.ndarray]:
        """``(N, D)`` normalised states and ``(N, A)`` teacher mean actions of what was gathered."""
        raw, who = np.asarray(self._raw, np.float32), np.asarray(self._who)
        actions = np.zeros((len(who), self.model.action_space.shape[0]), np.float32)
        for i, teacher in enumerate(self.teaching.teachers):
            rows = np.flatnonzero(who == i)
            if len(rows):
                inputs = teacher.model.observation_space.shape[0]
                actions[rows] = mean_actions(teacher, raw[rows, :inputs])
        return np.asarray(self._normalised, np.float32), actions

    def fit(self) -> float:
        """The passes over the gathered states; clears them; returns the loss before them."""
        obs, actions = self.labels()
        self._normalised, self._raw, self._who = [], [], []
        policy = self.model.policy
        x, y = torch.as_tensor(obs, device=policy.device), torch.as_tensor(actions, device=policy.device)
        with torch.no_grad():
            before = float(kickstart_loss(policy.get_distribution(x).distribution.mean, y))
        policy.set_training_mode(True)
        for _ in range(self.config.epochs):
            order = self.rng.permutation(len(x))
            for start in range(0, len(x), self.config.batch_size):
                rows = order[start:start + self.config.batch_size]
                loss = kickstart_loss(policy.get_distribution(x[rows]).distribution.mean, y[rows])
                self.optimizer.zero_grad()
                loss.backward()
                torch.nn.utils.clip_grad_norm_(policy.parameters(), self.model.max_grad_norm)
                self.optimizer.step()
        policy.set_training_mode(False)
        self.logger.record("kickstart/states", len(x))
        self.logger.record("kickstart/loss", before)
        return before
