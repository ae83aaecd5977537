"""Shared figure conventions: readable logarithmic axes."""

from __future__ import annotations

from typing import Any

from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

__all__ = ["plain_log_ticks", "pretty_units"]


def plain_log_ticks(axis: Any) -> None:
    """Label a logarithmic axis at 1, 2, 5 per decade with plain numbers, minor ticks unlabelled.

    Matplotlib's default labels the minor ticks of a short log axis as ``3x10^-1``,
    ``4x10^-1``, ... and they run into each other.
    """
    axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def pretty_units(text: str) -> str:
    """Write units compactly, micro as the Greek letter: ``'10 um / s'`` -> ``'10 µm/s'``."""
    import re

    return re.sub(r"(?<![A-Za-z])u(?=(m|N|s)\b)", "\u00b5", text).replace(" / ", "/")
