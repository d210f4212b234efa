"""Prototype: each hinge's slow variation read by a moving mean over exactly one stride (the gait's own
motion averages out over a stride), and the part of it a suit's drift most likely added taken out."""
import numpy as np
from reference_motion.humanoid.model import load_model


def stride_frames(motion, low_s=0.5, high_s=2.0):
    """The stride period (frames) of ``motion``: the autocorrelation peak of the legs' pitch hinges."""
    model = load_model(motion.model)
    cols = [model.qpos_index(n) for n in ("l_thigh_y", "r_thigh_y", "l_shin_y", "r_shin_y")]
    x = motion.qpos[:, cols] - motion.qpos[:, cols].mean(axis=0)
    n = len(x)
    lo, hi = int(low_s * motion.fps), min(int(high_s * motion.fps), n // 2)
    if hi <= lo:
        return None
    ac = np.array([np.sum(x[:-lag] * x[lag:]) / (n - lag) for lag in range(lo, hi + 1)])
    return lo + int(np.argmax(ac))


def stride_mean(values, period):
    """``(T, n)`` moving mean over ``period`` frames, held at the first/last full window near the ends."""
    T = len(values)
    c = np.cumsum(np.vstack([np.zeros((1, values.shape[1])), values]), axis=0)
    full = (c[period:] - c[:-period]) / period  # windows starting at 0 .. T - period
    out = np.empty_like(values)
    half = period // 2
    out[half:half + len(full)] = full
    out[:half] = full[0]
    out[half + len(full):] = full[-1]
    return out


def slow_variation(motion, cols):
    period = stride_frames(motion)
    if period is None:
        return np.zeros((motion.n_frames, len(cols)))
    m = stride_mean(motion.qpos[:, cols], period)
    return m - m.mean(axis=0)


def detrended(motion, cols, k):
    q = motion.qpos.copy()
    q[:, cols] -= k * slow_variation(motion, cols)
    return motion.with_qpos(q)
