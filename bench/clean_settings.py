"""How the benchmarks name a :class:`agents.clean.CleanConfig` on the command line and in their reports.

``REWINDxRETRIES`` (e.g. ``0.5x4``): the policy alone, then that many stochastic retries from
``REWIND`` s before a failure (``--search off``). ``REWIND:search:BEAMxSAMPLES[,KEY=VALUE...]``
(e.g. ``1:search:16x64``): the policy alone, the policy-guided search (:mod:`agents.search`) after
a failure (``--search retries``). ``REWIND:searchall:...``: every stretch searched (``--search all``,
clean.py's default). ``KEY`` is ``noise``, ``position``, ``value``, ``hold`` or ``drift``:
:class:`agents.search.SearchConfig`'s ``noise`` (default 1), ``position_weight`` and
``value_weight`` (defaults 0 and 1), ``hold_noise`` (0 or 1, default 1), ``max_drift_m``
(metres or ``none``, default 0.5), e.g.
``1:searchall:16x64,noise=1.5,value=0``.
"""

from __future__ import annotations

import argparse

from agents.clean import CleanConfig
from agents.search import SearchConfig


SEARCH_KEYS = {"noise": "noise", "position": "position_weight", "value": "value_weight", "hold": "hold_noise",
               "drift": "max_drift_m"}
"""The ``KEY=VALUE`` options of a search setting: the :class:`SearchConfig` field each sets."""


def setting(text: str) -> CleanConfig:
    """The :class:`CleanConfig` ``text`` names (the module's forms); ``argparse.ArgumentTypeError``
    naming the forms when it is none of them."""
    try:
        if ":search" in text:
            rewind, mode, spec = (text.lower().split(":") + [""])[:3]
            if mode not in ("search", "searchall"):
                raise ValueError(mode)
            sizes, *options = (spec or "16x64").split(",")
            beam, samples = sizes.split("x")
            fields = {}
            for option in options:
                key, value = option.split("=")
                if key == "hold":
                    fields["hold_noise"] = bool(int(value))
                else:
                    fields[SEARCH_KEYS[key]] = None if key == "drift" and value == "none" else float(value)
            search = SearchConfig(beam=int(beam), samples=int(samples), **fields)
            return CleanConfig(rewind_s=float(rewind), search=search, search_retries_only=mode == "search")
        rewind, retries = text.lower().split("x")
        return CleanConfig(rewind_s=float(rewind), retries=int(retries), search=None)
    except (ValueError, KeyError):
        raise argparse.ArgumentTypeError(f"{text!r}: expected REWIND_SxRETRIES (e.g. 0.5x4) or REWIND_S:search[all]:"
                                         "BEAMxSAMPLES[,noise=N][,position=W][,value=V] (e.g. 1:searchall:16x64)") from None


def label(config: CleanConfig) -> str:
    """How a setting is printed: ``0.5 s x 4`` or ``1 s searchall 16x64 σ×1 p0 v0``."""
    if config.search is None:
        return f"{config.rewind_s:g} s x {config.retries}"
    s = config.search
    mode = "search" if config.search_retries_only else "searchall"
    return (f"{config.rewind_s:g} s {mode} {s.beam}x{s.samples} σ×{s.noise:g} p{s.position_weight:g} "
            f"v{s.value_weight:g}{' held' if s.hold_noise else ''}"
            f"{'' if s.max_drift_m is None else f' drift<{s.max_drift_m:g}'}")
