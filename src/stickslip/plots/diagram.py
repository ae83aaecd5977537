"""The two-parameter diagram: regions shaded and named, curves, codimension-2 points, and overlays.

:func:`plot_diagram` draws a :class:`~stickslip.bifurcation.diagram.Diagram`: each
region in the colour of its regime (:data:`~.regimes.REGIME_COLORS`) with its attractors
written at its innermost cell; the Hopf curve solid where supercritical and dashed where
subcritical; the fold-of-cycles and grazing curves; the codimension-2 points with their
names. A brute-force check (:func:`~stickslip.bifurcation.diagram_check.check_diagram`)
adds its disagreeing cells as crosses; measured points (records) are drawn with their
measured regime.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.colors import ListedColormap

from .regimes import REGIME_COLORS
from .style import subplots

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_diagram"]

_CURVE_STYLE = {
    "hopf": {"color": "k", "lw": 1.6},
    "fold": {"color": "#2166ac", "lw": 1.6},
    "grazing": {"color": "#b2182b", "lw": 1.6},
    "reversal": {"color": "#762a83", "lw": 1.6, "ls": "-."},
}
_CURVE_WORDS = {
    "hopf": "Hopf (steady sliding)",
    "fold": "fold of pure-slip cycles",
    "grazing": "grazing (stick-slip born)",
    "reversal": "slip reversal (no stick left)",
}
_POINT_STYLE = {"bautin": ("*", 12), "fold-grazing": ("D", 7), "cusp": ("^", 8), "end": ("o", 5)}
_MEASURED = {
    "stick-slip": ("o", "#e6550d"),
    "pure-slip": ("s", "#3182bd"),
    "steady-sliding": ("^", "#31a354"),
    "undetermined": ("x", "0.3"),
}


def plot_diagram(
    diagram: Any,
    *,
    check: Any = None,
    measured: Sequence[tuple[float, float, str]] = (),
    title: str | None = None,
) -> Figure:
    """Return the figure of a two-parameter diagram.

    Parameters
    ----------
    diagram : Diagram
        From :func:`~stickslip.bifurcation.diagram.two_parameter_diagram`.
    check : DiagramCheck, optional
        Its disagreeing cells are marked.
    measured : sequence of (x, y, regime)
        Measured points in axis units with their regime (``stick-slip``, ``pure-slip``,
        ``steady-sliding``, anything else drawn as undetermined).
    title : str, optional
        The title (default: the plane in words).

    """
    fig, ax = subplots(figsize=(7.0, 5.2))
    names = list(diagram.region_regime)
    palette = [REGIME_COLORS.get(n, "#ffffff") for n in names] or ["#ffffff"]
    region = np.ma.masked_less(diagram.region, 0)
    ax.pcolormesh(
        diagram.raster_x,
        diagram.raster_y,
        region,
        shading="nearest",
        cmap=ListedColormap(palette),
        vmin=-0.5,
        vmax=len(palette) - 0.5,
        rasterized=True,
    )
    from scipy import ndimage

    dist = ndimage.distance_transform_edt(np.pad(diagram.region >= 0, 1))[1:-1, 1:-1]  # the frame is a wall
    for r, words in enumerate(diagram.region_names):
        cells = np.argwhere(diagram.region == r)
        if len(cells) < 0.004 * diagram.region.size:
            continue  # a sliver: its name would cover the curves
        i, j = cells[int(np.argmax(dist[cells[:, 0], cells[:, 1]]))]
        ax.text(
            diagram.raster_x[j],
            diagram.raster_y[i],
            words.replace(" + ", "\n+ "),
            ha="center",
            va="center",
            fontsize=8,
            color="0.2",
        )
    seen: set[str] = set()
    for c in diagram.curves:
        style = dict(_CURVE_STYLE.get(c.kind, {"color": "0.4"}))
        label = None if c.kind in seen else _CURVE_WORDS.get(c.kind, c.kind)
        seen.add(c.kind)
        if c.kind == "hopf" and "f3" in c.data:
            sub = np.asarray(c.data["f3"]) < 0
            if sub.all():
                label = None  # no supercritical part: the legend names only the dashed line
                seen.discard("hopf")
            sup = ~sub
            # each part reaches one point into the other: no gap where the criticality changes
            sup = sup | np.r_[sup[1:], False] | np.r_[False, sup[:-1]]
            sub = sub | np.r_[sub[1:], False] | np.r_[False, sub[:-1]]
            ax.plot(np.where(sup, c.x, np.nan), c.y, label=label, **style)
            ax.plot(
                np.where(sub, c.x, np.nan),
                c.y,
                ls="--",
                label=None if "sub" in seen else "Hopf, subcritical",
                **style,
            )
            seen.add("sub")
        else:
            ax.plot(c.x, c.y, label=label, **style)
    for p in diagram.points:
        m, size = _POINT_STYLE.get(p.kind, ("o", 5))
        label = None if p.kind in seen else p.kind
        seen.add(p.kind)
        ax.plot(p.x, p.y, m, ms=size, color="#fdb863" if p.kind == "bautin" else "k", mec="k", label=label)
    if check is not None and check.disagree:
        ax.plot(
            [d["x"] for d in check.disagree],
            [d["y"] for d in check.disagree],
            "x",
            color="m",
            ms=6,
            label=f"engine disagrees ({len(check.disagree)} cells)",
        )
    for regime, (marker, color) in _MEASURED.items():
        pts = [(x, y) for x, y, r in measured if (r if r in _MEASURED else "undetermined") == regime]
        if pts:
            xs, ys = zip(*pts, strict=True)
            ax.plot(xs, ys, marker, color=color, mec="k", ms=7, ls="none", label=f"measured: {regime}")
    pl = diagram.plane
    if pl.x.log:
        ax.set_xscale("log")
    if pl.y.log:
        ax.set_yscale("log")
    ax.set_xlim(pl.x.lo, pl.x.hi)
    ax.set_ylim(pl.y.lo, pl.y.hi)
    ax.set_xlabel(pl.x.label())
    ax.set_ylabel(pl.y.label())
    import textwrap

    ax.set_title("\n".join(textwrap.wrap(title or pl.describe, 90)), fontsize=9)
    ax.legend(fontsize=7, loc="best", framealpha=0.85)
    return fig
