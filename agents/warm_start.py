"""Warm-starting a PPO run from a trained policy (``train_ppo.py --init-from``), also across an
observation that gained inputs or onto wider hidden layers.

A policy trained on ADAPT's world-frame observation (:mod:`envs.observations`) can be carried to
the same observation with ``dp_com`` (``MimicConfig.com_offset``) or with a window of the reference
(``MimicConfig.lookahead``, ``lookbehind``), and a policy with a window to one with more of its steps (``1 2 4 8``
to ``1 2 4 8 16 32``; the steps it saw keep their weights): the first layer of actor and critic gets zero weights for the new
inputs, so the widened network computes exactly what the source did until training gives those
inputs weight, and the observation statistics get an entry for them (a fixed scale for
``dp_com``; for the window, which is the reference's alone, the mean and variance of the run's
own environments over :data:`LOOKAHEAD_SAMPLE_RESETS` resets).

A key-joint policy can seed a run that drives every hinge (``MimicFullAction-v0``,
:func:`drive_more_hinges`): its action rows and previous-action inputs move with their actuators,
and the newly driven hinges start at a zero offset, which is what the source gave them. Any other
mismatch of spaces is an error.

A policy can also seed a run with wider hidden layers (``--net 512,512`` from a ``256,256``
policy), to give a network that underfits its data more capacity without starting over: the
source's weights fill the top-left block of each layer, the new units get the new network's own
random input weights, and every weight from a new unit into an old one or into an output is zero
(:func:`widen_hidden`). The new units are then computed but not read, so the run starts acting
and valuing exactly as the source; their outgoing weights have non-zero gradients (a new unit's
tanh activation is not zero), so training brings them in.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecEnv, VecNormalize
from stable_baselines3.common.running_mean_std import RunningMeanStd

from agents.policy import MimicPolicy, PolicyError
from agents.privileged_critic import PrivilegedObservation, plain_model, widen_critic
from envs.config import FOOT_MODELS, MimicConfig
from envs.mimic import driven_actuators
from envs.observations import WINDOW_PARTS, observation_slices, same_layout
from reference_motion.humanoid.model import load_model

FIRST_LAYERS = ("mlp_extractor.policy_net.0.weight", "mlp_extractor.value_net.0.weight")
"""Parameters of SB3's ``MlpPolicy`` that read the observation: ``(hidden, D)`` each."""

COM_OFFSET_STD_M = 0.2
"""Running std (m) given to each new ``dp_com`` input: the offsets a tracking policy lives with are
0–0.9 m (the lag termination is at ~0.9 m of head distance), so normalised inputs are near unit
size. The statistics keep the source's count (tens of millions of steps), so this scale stays
all but fixed for the rest of the run (0.200 / 0.200 / 0.192 m after 2.4 M steps)."""


LOOKAHEAD_SAMPLE_RESETS = 64
"""Resets of the run's environments whose observations give the new lookahead inputs' running mean
and variance (64 × the number of envs start states, at random clips and frames)."""

LOOKAHEAD_MIN_STD = 1e-3
"""Smallest running std (m or m/s) given to a new lookahead input, so that a nearly constant one
is not scaled up without bound."""


def sampled_statistics(venv: VecEnv, columns: slice, resets: int) -> tuple[np.ndarray, np.ndarray]:
    """Mean and variance ``(D,)`` of observation ``columns`` over ``resets`` resets of every env of
    ``venv`` (raw observations, before normalisation)."""
    samples = np.concatenate([venv.reset()[:, columns] for _ in range(resets)])
    return samples.mean(axis=0), np.maximum(samples.var(axis=0), LOOKAHEAD_MIN_STD**2)


def window_slice(slices: dict[str, slice]) -> slice | None:
    """The observation columns of the reference window (``lookahead`` and ``lookbehind``
    together, which end the observation) in the layout ``slices``; ``None`` without either."""
    parts = [slices[name] for name in WINDOW_PARTS if name in slices]
    return slice(parts[0].start, parts[-1].stop) if parts else None


def describe_steps(window_steps: tuple[int, ...] | list[int]) -> str:
    """``MimicConfig.window_steps`` as the options give them: "lookahead 1 2, lookbehind 4" (or "no window")."""
    ahead, behind = [k for k in window_steps if k > 0], [-k for k in window_steps if k < 0]
    parts = [f"{name} {' '.join(map(str, ks))}" for name, ks in (("lookahead", ahead), ("lookbehind", behind)) if ks]
    return ", ".join(parts) or "no window"


def added_window_steps(source_steps: tuple[int, ...], steps: tuple[int, ...], source: str) -> list[int]:
    """The steps of a run's reference window ``steps`` that a policy seeing ``source_steps`` does not
    see (each as ``MimicConfig.window_steps`` gives them), in the run's order; raises
    :class:`PolicyError`, naming ``source``, if the policy sees a step the run's window lacks."""
    missing = [step for step in source_steps if step not in steps]
    if missing:
        raise PolicyError(f"{source}: observes the reference window {describe_steps(source_steps)}; this run's "
                          f"({describe_steps(steps)}) lacks {describe_steps(missing)}. A warm start may add window "
                          f"steps, not drop them")
    return [step for step in steps if step not in source_steps]


def widen_by_window(state_dict: dict[str, torch.Tensor], mean: np.ndarray, var: np.ndarray, venv: VecEnv,
                    resets: int = LOOKAHEAD_SAMPLE_RESETS, source_steps: tuple[int, ...] = ()
                    ) -> tuple[dict[str, torch.Tensor], np.ndarray, np.ndarray]:
    """A policy's ``state_dict`` and observation statistics ``mean``, ``var`` ``(D,)`` carried to
    the environments of ``venv``, whose reference window (:func:`window_slice`, ending the
    observation) shows the steps of ``MimicConfig.window_steps``, a superset of the policy's own
    ``source_steps`` (empty: a policy without a window). The policy's window steps keep their
    weights and statistics; each new step's inputs get zero first-layer weights (:func:`remap_inputs`,
    so the policy acts as before) and their mean and variance over ``resets`` resets of every env of
    ``venv`` (:func:`sampled_statistics`). Raises :class:`PolicyError` unless the observation is
    exactly the policy's with those steps added."""
    window = window_slice(venv.get_attr("obs_slices", indices=[0])[0])
    steps = venv.get_attr("config", indices=[0])[0].window_steps
    per_step = (window.stop - window.start) // len(steps) if window is not None else 0
    added_window_steps(source_steps, steps, "the policy")
    if (window is None or window.stop != venv.observation_space.shape[0]
            or window.start + per_step * len(source_steps) != len(mean)):
        raise PolicyError(f"the environment's observation ({venv.observation_space.shape[0]} values) is not the "
                          f"policy's ({len(mean)}; {describe_steps(source_steps)}) with more steps of a reference "
                          f"window ({describe_steps(steps)})")
    source_index = np.arange(window.stop)
    for at, step in enumerate(steps):
        block = slice(window.start + at * per_step, window.start + (at + 1) * per_step)
        source_index[block] = (window.start + source_steps.index(step) * per_step + np.arange(per_step)
                               if step in source_steps else -1)
    new = source_index < 0
    window_mean, window_var = sampled_statistics(venv, window, resets)
    sampled_mean, sampled_var = np.zeros(window.stop), np.ones(window.stop)
    sampled_mean[window], sampled_var[window] = window_mean, window_var
    return (remap_inputs(state_dict, source_index),
            np.where(new, sampled_mean, mean[source_index]), np.where(new, sampled_var, var[source_index]))


def observation_normalizer(venv: VecEnv, gamma: float) -> VecNormalize:
    """The running observation normalisation every run uses (observations only, not rewards)."""
    return VecNormalize(venv, norm_obs=True, norm_reward=False, gamma=gamma)


def renormalised_inputs(state_dict: dict[str, torch.Tensor], old: RunningMeanStd, new: RunningMeanStd,
                        epsilon: float) -> dict[str, torch.Tensor]:
    """A copy of an SB3 ``MlpPolicy`` ``state_dict`` whose first layers (:data:`FIRST_LAYERS` and
    their biases), given observations normalised by the statistics ``new`` (``(o − μ) / √(σ² + ε)``,
    VecNormalize's), compute what the source's did on the same raw observations normalised by
    ``old``: ``W' = W diag(s_new / s_old)``, ``b' = b + W (μ_new − μ_old) / s_old``."""
    s_old, s_new = np.sqrt(old.var + epsilon), np.sqrt(new.var + epsilon)
    scale = torch.as_tensor(s_new / s_old, dtype=torch.float32)
    shift = torch.as_tensor((new.mean - old.mean) / s_old, dtype=torch.float32)
    out = dict(state_dict)
    for name in FIRST_LAYERS:
        weight, bias = state_dict[name], name.replace(".weight", ".bias")
        out[name] = weight * scale.to(weight)
        out[bias] = state_dict[bias] + weight @ shift.to(weight)
    return out


def widen_inputs(state_dict: dict[str, torch.Tensor], insert_at: int, n_new: int) -> dict[str, torch.Tensor]:
    """A copy of an SB3 ``MlpPolicy`` ``state_dict`` whose first layers (:data:`FIRST_LAYERS`) take
    ``n_new`` more inputs at index ``insert_at``, with zero weights: the widened network's outputs
    equal the source's for any values of the new inputs."""
    n_inputs = first_layers(state_dict)[FIRST_LAYERS[0]].shape[1]
    if not 0 <= insert_at <= n_inputs:
        raise PolicyError(f"warm start: cannot insert inputs at {insert_at} into {FIRST_LAYERS[0]} of {n_inputs} inputs")
    return remap_inputs(state_dict, np.concatenate([np.arange(insert_at), np.full(n_new, -1),
                                                    np.arange(insert_at, n_inputs)]))


def remap_inputs(state_dict: dict[str, torch.Tensor], source_index: np.ndarray) -> dict[str, torch.Tensor]:
    """A copy of an SB3 ``MlpPolicy`` ``state_dict`` whose first layers (:data:`FIRST_LAYERS`) read
    ``len(source_index)`` inputs: input ``i`` takes the weights of the source's input
    ``source_index[i]``, or zero weights where that is ``-1`` (a new input the network does not read)."""
    source_index = np.asarray(source_index)
    out = dict(state_dict)
    for name, weight in first_layers(state_dict).items():
        if source_index.max(initial=-1) >= weight.shape[1]:
            raise PolicyError(f"warm start: {name} has {weight.shape[1]} inputs, not {source_index.max() + 1}")
        index = torch.as_tensor(np.maximum(source_index, 0), device=weight.device)
        keep = torch.as_tensor(source_index >= 0, device=weight.device).to(weight.dtype)
        out[name] = weight[:, index] * keep
    return out


def first_layers(state_dict: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """The weights of :data:`FIRST_LAYERS` in an SB3 ``MlpPolicy`` ``state_dict``; raises
    :class:`PolicyError` naming the first one it lacks."""
    for name in FIRST_LAYERS:
        if name not in state_dict:
            raise PolicyError(f"warm start: the source policy has no {name!r}; not an SB3 MlpPolicy")
    return {name: state_dict[name] for name in FIRST_LAYERS}


def widen_hidden(source: dict[str, torch.Tensor], target: dict[str, torch.Tensor]) -> dict[str, torch.Tensor]:
    """``source`` (an SB3 ``MlpPolicy`` ``state_dict``) embedded in the network with wider hidden
    layers whose freshly initialised ``state_dict`` is ``target``. A weight ``(out, in)`` takes the
    source's ``[:o, :i]`` block; its rows past ``o`` (new units) keep ``target``'s initial values,
    and its columns past ``i`` are zero in the first ``o`` rows (an old unit or an output does not
    read a new unit), so the result computes the source's actions and values for every input.
    Biases take the source's first entries.

    Only hidden units may be new: rows (and biases) of the ``mlp_extractor`` layers, and the
    columns that read them in the next layer or in ``action_net`` / ``value_net``. Raises
    :class:`PolicyError` naming a parameter the networks do not share, one that would shrink, or
    one whose observation inputs, actions or log-std would grow (those would not act as the source)."""
    if source.keys() != target.keys():
        differ = sorted(source.keys() ^ target.keys())
        raise PolicyError(f"warm start: the source policy and this run's network have different layers ({differ}); "
                          f"--net may widen the source's hidden layers, not change how many there are")
    out = {}
    for name, weights in source.items():
        fresh = target[name]
        if weights.shape == fresh.shape:
            out[name] = weights
            continue
        hidden_rows = name.startswith("mlp_extractor.")  # a hidden layer's units may be new
        hidden_cols = weights.dim() == 2 and name not in FIRST_LAYERS  # it reads hidden units, not the observation
        growable = (hidden_rows, hidden_cols)
        if weights.dim() != fresh.dim() or any(s > t or (s < t and not ok) for s, t, ok
                                               in zip(weights.shape, fresh.shape, growable)):
            raise PolicyError(f"warm start: {name} is {tuple(weights.shape)} in the source and {tuple(fresh.shape)} "
                              f"in this run's network; --net may only widen the source's hidden layers")
        wide = fresh.detach().clone()
        wide[tuple(slice(0, n) for n in weights.shape)] = weights
        if weights.dim() == 2:
            wide[: weights.shape[0], weights.shape[1]:] = 0.0
        out[name] = wide
    return out


def widen_statistics(mean: np.ndarray, var: np.ndarray, insert_at: int, new_var: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Running observation mean and variance ``(D,)`` with entries for ``len(new_var)`` new inputs at
    ``insert_at`` (mean 0, variance ``new_var``)."""
    new_var = np.asarray(new_var, dtype=var.dtype)
    return (np.insert(mean, insert_at, np.zeros_like(new_var)), np.insert(var, insert_at, new_var))


def action_mode_of(env_id: str) -> str:
    """The ``action_mode`` a registered mimic environment id is made with (``"key"`` unless its
    registration says otherwise)."""
    return gym.spec(env_id).kwargs.get("action_mode", "key")


ACTION_LAYERS = ("action_net.weight", "action_net.bias", "log_std")
"""Parameters of SB3's ``MlpPolicy`` with one row (or entry) per action component."""


def drive_more_hinges(state_dict: dict[str, torch.Tensor], mean: np.ndarray, var: np.ndarray,
                      source_driven: np.ndarray, target_driven: np.ndarray,
                      prev_action_at: int) -> tuple[dict[str, torch.Tensor], np.ndarray, np.ndarray]:
    """A policy driving the actuators ``source_driven (A,)`` carried to one driving ``target_driven
    (A',)``, a superset (``MimicIMU-v0``'s 8 key joints → every hinge of ``MimicFullAction-v0``).

    Returns the copied ``state_dict`` and the running observation ``mean`` and ``var`` ``(D,)`` →
    ``(D + A' − A,)``. Each source action row (:data:`ACTION_LAYERS`) moves to its actuator's place;
    a newly driven actuator gets a zero row (a zero offset: its PD target stays the reference's, as
    the source left it) and the source's mean log-std. The observation's previous action, ``A``
    values at ``prev_action_at``, becomes ``A'``: each source column moves with its actuator, a new
    one gets zero weights and the source's mean statistics. So the result acts as the source did
    for every observation, until training gives the new hinges a say. Raises :class:`PolicyError`
    when the source drives an actuator the target does not."""
    place = {int(a): k for k, a in enumerate(target_driven)}
    lost = [int(a) for a in source_driven if int(a) not in place]
    if lost:
        raise PolicyError(f"warm start: the source policy drives actuators {lost}, which this run's action space "
                          f"does not; it may only drive more hinges, not fewer")
    index = torch.as_tensor([place[int(a)] for a in source_driven])
    n_old, n_new = len(source_driven), len(target_driven)
    out = dict(state_dict)
    for name in FIRST_LAYERS:
        out[name] = move_block(state_dict[name], 1, prev_action_at, index, n_new, fill=0.0)
    for name in ACTION_LAYERS:
        rows = state_dict[name]
        out[name] = move_block(rows, 0, 0, index, n_new, fill=float(rows.mean()) if name == "log_std" else 0.0)
    mean_new, var_new = (move_block(torch.from_numpy(values), 0, prev_action_at, index, n_new,
                                    fill=float(values[prev_action_at:prev_action_at + n_old].mean())).numpy()
                         for values in (mean, var))
    return out, mean_new, var_new


def move_block(values: torch.Tensor, dim: int, start: int, index: torch.Tensor, n_new: int,
               fill: float) -> torch.Tensor:
    """``values`` with its block of ``len(index)`` entries along ``dim`` from ``start`` on replaced by
    a block of ``n_new`` entries: entry ``k`` of the old block lands at ``index[k]``, every other new
    entry is ``fill``. The entries before and after the block stay as they are."""
    n_old = len(index)
    shape = list(values.shape)
    shape[dim] = n_new
    moved = torch.full(shape, fill, dtype=values.dtype)
    moved.index_copy_(dim, index, values.narrow(dim, start, n_old))
    after = values.shape[dim] - start - n_old
    return torch.cat([values.narrow(dim, 0, start), moved, values.narrow(dim, start + n_old, after)], dim=dim)


def warm_start(model: PPO, venv: VecEnv, source: MimicPolicy, config: MimicConfig, gamma: float) -> VecNormalize:
    """Load ``source``'s weights into ``model`` (a new run on ``venv``, whose environments use
    ``config``) and return ``venv`` wrapped in ``source``'s observation statistics.

    The spaces must match, or differ only by ``dp_com`` and/or steps of the reference window: ``config``
    observes them and the source's environment did not (``dp_com``; the window, or some of its steps)
    (then the inputs are widened, see the module docstring). The frames must
    match too, or both be of :data:`envs.observations.SAME_LAYOUT_FRAMES` (world and reference
    axes: the weights carry over as they are, and a note says so). ``model``'s hidden layers may be
    wider than the source's (:func:`widen_hidden`)."""
    sizes = venv.observation_space.shape, source.model.observation_space.shape
    source_config = source.record.env.mimic_config()
    if not same_layout(source_config.obs_frame, config.obs_frame):  # heading vs world + dp_com: same sizes
        raise PolicyError(f"{source.name}: observed in the {source_config.obs_frame!r} frame; a warm start cannot "
                          f"change the frame to {config.obs_frame!r}")
    if config.obs_frame != source_config.obs_frame:
        print(f"note: {source.name} observes in the {source_config.obs_frame!r} frame; this run trains it in the "
              f"{config.obs_frame!r} frame (--obs-frame)", flush=True)
    span = observation_slices(1, 1, com_offset=True)["dp_com"]
    n_com = span.stop - span.start if config.observes_com_offset and not source_config.observes_com_offset else 0
    new_steps = added_window_steps(source_config.window_steps, config.window_steps, source.name)
    window = window_slice(venv.get_attr("obs_slices", indices=[0])[0])
    n_window = (window.stop - window.start) * len(new_steps) // len(config.window_steps) if new_steps else 0
    state, rms = source.model.policy.state_dict(), source.normalizer.obs_rms.copy()
    more_hinges = venv.action_space.shape != source.model.action_space.shape
    if more_hinges:
        if n_com or n_window:
            raise PolicyError(f"{source.name}: a warm start may drive more hinges or observe more, not both at once")
        target_driven = venv.get_attr("driven", indices=[0])[0]
        source_driven = driven_actuators(load_model(FOOT_MODELS[source.foot]), action_mode_of(source.env_id))
        prev_action_at = venv.get_attr("obs_slices", indices=[0])[0]["prev_action"].start
        state, rms.mean, rms.var = drive_more_hinges(state, rms.mean, rms.var, source_driven, target_driven,
                                                     prev_action_at)
        print(f"{source.name} drives {len(source_driven)} hinges, this run {len(target_driven)}: the new ones start "
              f"at zero offset (the reference's PD target)", flush=True)
    # new inputs with a changed action space were refused above
    widen = (n_com or n_window) and sizes[0][0] == sizes[1][0] + n_com + n_window
    if widen and n_com:
        state = widen_inputs(state, span.start, n_com)
        rms.mean, rms.var = widen_statistics(rms.mean, rms.var, span.start, np.full(n_com, COM_OFFSET_STD_M**2))
        print(f"widening {source.name}'s inputs by dp_com (zero weights at {span.start}:{span.stop})", flush=True)
    if widen and n_window:
        state, rms.mean, rms.var = widen_by_window(state, rms.mean, rms.var, venv,
                                                   source_steps=source_config.window_steps)
        print(f"widening {source.name}'s inputs by the reference window {describe_steps(new_steps)} (it saw "
              f"{describe_steps(source_config.window_steps)}; the new steps' inputs, among {window.start}:{window.stop}, "
              f"start at zero weight, their statistics from {LOOKAHEAD_SAMPLE_RESETS} resets)", flush=True)
    if not widen and not more_hinges:
        source.check_env(venv)  # raises PolicyError naming the mismatch, unless the spaces match
    fresh = model.policy.state_dict()
    wide = widen_hidden(state, fresh)
    if any(wide[name] is not state[name] for name in wide):
        print(f"widening {source.name}'s hidden layers (new units are not read until trained)", flush=True)
    model.policy.load_state_dict(wide)
    normalizer = observation_normalizer(venv, gamma)
    normalizer.obs_rms = rms
    return normalizer


PRIVILEGED_SAMPLE_RESETS = 16
"""Resets of the run's environments whose privileged features give their running mean and variance
(:func:`warm_start_privileged`)."""

PRIVILEGED_MIN_STD = 0.01
"""Smallest running std given to a privileged feature (rad, m, m/s or a factor's deviation from 1), so that
one the resets rarely show (a PD-target offset of a run without them, a clean run's hinge errors) is not
scaled up without bound."""


def warm_start_privileged(model: PPO, venv: PrivilegedObservation, source: MimicPolicy, config: MimicConfig,
                          gamma: float) -> VecNormalize:
    """:func:`warm_start` for a run with a privileged critic (``train_ppo.py --privileged-critic``):
    ``model`` (an :class:`agents.privileged_critic.PrivilegedCriticPolicy` on ``venv``) gets ``source``'s
    weights as :func:`warm_start` gives them to a plain network of the run's own observation, its critic
    reading the privileged columns with zero weights (:func:`agents.privileged_critic.widen_critic`); the
    returned statistics are ``source``'s for the observation and, for the privileged columns, their mean
    and variance over :data:`PRIVILEGED_SAMPLE_RESETS` resets of every env (:func:`sampled_statistics`;
    the std at least :data:`PRIVILEGED_MIN_STD`), counted as the source's: all but fixed from then on, as
    the source's are. A source trained with a privileged critic loads as its actor
    (:func:`agents.policy.load_policy`), so its critic's privileged weights start again from zero here;
    ``train_ppo.py --resume`` keeps them."""
    plain = plain_model(venv.venv.observation_space, venv.action_space, model.policy_kwargs, device="cpu")
    inner = warm_start(plain, venv.venv, source, config, gamma)
    widen_critic(model, plain)
    mean, var = sampled_statistics(venv, slice(venv.policy_inputs, None), PRIVILEGED_SAMPLE_RESETS)
    rms = RunningMeanStd(shape=venv.observation_space.shape)
    rms.mean = np.concatenate([inner.obs_rms.mean, mean])
    rms.var = np.concatenate([inner.obs_rms.var, np.maximum(var, PRIVILEGED_MIN_STD**2)])
    rms.count = inner.obs_rms.count
    normalizer = observation_normalizer(venv, gamma)
    normalizer.obs_rms = rms
    return normalizer
