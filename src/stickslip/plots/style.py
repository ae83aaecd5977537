"""Shared figure conventions: figures without pyplot, readable logarithmic axes."""

from __future__ import annotations

from typing import Any

from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

__all__ = ["envelope", "plain_log_ticks", "pretty_units", "subplots"]


def subplots(
    nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float], **kwargs: Any
) -> tuple[Figure, Any]:
    """Return a new figure and its axes, made without pyplot.

    No backend is chosen and no global figure list grows: importing stickslip leaves
    matplotlib as the user set it up, and a figure is freed when it is no longer used.
    ``layout="constrained"`` (the default) and the keywords of
    :meth:`matplotlib.figure.Figure.subplots` (``sharex``, ``sharey``, ``gridspec_kw``)
    are accepted.
    """
    layout = kwargs.pop("layout", "constrained")
    if kwargs.pop("constrained_layout", False):
        layout = "constrained"
    fig = Figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(nrows, ncols, **kwargs)


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


def envelope(x: Any, y: Any, max_points: int = 20_000) -> tuple[Any, Any]:
    """Decimate a series for drawing: per bin, its minimum and its maximum, in time order.

    A figure shows at most a few thousand pixels across; a series of millions of
    samples is drawn as the envelope of ``max_points / 2`` bins, which keeps every
    drop and every peak visible (a stride would skip them) and keeps the figure small.
    """
    import numpy as np

    x = np.asarray(x)
    y = np.asarray(y)
    n = y.size
    if n <= max_points:
        return x, y
    # bins of equal width covering every sample (the last one padded with the last value)
    width = -(-n // max(1, max_points // 2))
    bins = -(-n // width)
    yb = np.concatenate([y, np.full(bins * width - n, y[-1])]).reshape(bins, width)
    lo = np.argmin(yb, axis=1)
    hi = np.argmax(yb, axis=1)
    base = np.arange(bins) * width
    idx = np.empty(2 * bins, dtype=np.int64)
    idx[0::2] = base + np.minimum(lo, hi)
    idx[1::2] = base + np.maximum(lo, hi)
    idx = np.unique(np.append(np.minimum(idx, n - 1), [0, n - 1]))
    return x[idx], y[idx]
