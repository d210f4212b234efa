"""How the benchmarks name a :class:`agents.clean.CleanConfig` on the command line and in their reports.

``REWINDxRETRIES`` (e.g. ``0.5x4``): the policy alone, then that many stochastic retries from
``REWIND`` s before a failure (``--search off``). ``REWIND:search:BEAMxSAMPLES[xNOISE[xWEIGHT]]``
(e.g. ``1:search:16x64``): the policy alone, the policy-guided search (:mod:`agents.search`) after
a failure (``--search retries``). ``REWIND:searchall:...``: every stretch searched (``--search all``,
clean.py's default). ``NOISE`` is :attr:`agents.search.SearchConfig.noise` (default 1),
``WEIGHT`` its ``position_weight`` (default 0).
"""

from __future__ import annotations

import argparse

from agents.clean import CleanConfig
from agents.search import SearchConfig


def setting(text: str) -> CleanConfig:
    """The :class:`CleanConfig` ``text`` names (the module's forms); ``argparse.ArgumentTypeError``
    naming the forms when it is none of them."""
    try:
        if ":search" in text:
            rewind, mode, sizes = (text.lower().split(":") + [""])[:3]
            if mode not in ("search", "searchall"):
                raise ValueError(mode)
            beam, samples, *rest = (sizes or "16x64").split("x")
            if len(rest) > 2:
                raise ValueError(sizes)
            noise, weight = [float(x) for x in rest] + [1.0, 0.0][len(rest):]
            search = SearchConfig(beam=int(beam), samples=int(samples), noise=noise, position_weight=weight)
            return CleanConfig(rewind_s=float(rewind), search=search, search_retries_only=mode == "search")
        rewind, retries = text.lower().split("x")
        return CleanConfig(rewind_s=float(rewind), retries=int(retries), search=None)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected REWIND_SxRETRIES (e.g. 0.5x4) or "
                                         "REWIND_S:search[all]:BEAMxSAMPLES[xNOISE[xWEIGHT]] (e.g. 1:searchall:16x64)") from None


def label(config: CleanConfig) -> str:
    """How a setting is printed: ``0.5 s x 4`` or ``1 s searchall 16x64 σ×1 w0``."""
    if config.search is None:
        return f"{config.rewind_s:g} s x {config.retries}"
    s = config.search
    mode = "search" if config.search_retries_only else "searchall"
    return f"{config.rewind_s:g} s {mode} {s.beam}x{s.samples} σ×{s.noise:g} w{s.position_weight:g}"
