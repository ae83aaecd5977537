"""Bifurcation diagrams, regime maps and the criterion map."""

from __future__ import annotations

import itertools
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ..core.results import Regime
from ..units import VELOCITY_UNITS, readable_unit
from .style import plain_log_ticks, pretty_units, subplots

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..bifurcation.regimes import RegimeDiagram

__all__ = ["REGIME_COLORS", "plot_bifurcation", "plot_criterion_map", "plot_regime_map"]

#: a map's attribute holding a physical set-up's beta (s/m): its figures show v0 too
BETA_ATTR = "beta_s_per_m"
#: a map's attributes for a stretch of ``nu`` to mark at one value of its parameter (the
#: paper's experiment on the reproduction's maps), with its legend label
MARK_VALUE, MARK_NU_MIN, MARK_NU_MAX, MARK_LABEL = "mark_value", "mark_nu_min", "mark_nu_max", "mark_label"
_NOT_IN_TITLE = (BETA_ATTR, MARK_VALUE, MARK_NU_MIN, MARK_NU_MAX)

#: background colour of each regime (colour-blind safe, light)
REGIME_COLORS = {
    "stick-slip": "#fdd49e",
    "pure-slip": "#c6dbef",
    "slip-reversal": "#bcbddc",
    "bistable": "#d9d9d9",
    "multistable": "#b3b3b3",
    "steady-sliding": "#e5f5e0",
    "none": "#ffffff",
    "unknown": "#fcbba1",
}
_BRANCH_COLORS = {"steady-sliding": "C2", "pure-slip": "C0", "stick-slip": "C3"}
#: the words a figure's legend uses for the special points and lines (the code's names are the JSON's)
POINT_WORDS = {
    "hopf": "Hopf point",
    "fold": "fold of pure-slip orbits",
    "grazing": "grazing (pure slip reaches w = 0)",
    "stick-slip-onset": "onset of stick-slip",
}
#: a law parameter's symbol on an axis
_SYMBOLS = {"alpha": r"$\alpha$", "gamma": r"$\gamma$", "beta": r"$\beta$", "kappa": r"$\kappa$"}


def _law_words(law_name: str, params: dict[str, float]) -> str:
    """``cubic law (alpha = 0.5, gamma = 0.1667)``: the law, its parameters to four digits."""
    pars = ", ".join(f"{_SYMBOLS.get(k, k)} = {v:.4g}" for k, v in params.items())
    return f"{law_name} law" + (f" ({pars})" if pars else "")


def _breaks(x: np.ndarray, y: np.ndarray, jump: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """Return ``x, y`` with a NaN between neighbours whose ``x`` differ by more than ``jump`` relative.

    A boundary that jumps from one row of a map to the next (a fold where another branch
    takes over) is two pieces, not a line drawn across the gap.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(np.diff(x)) / np.maximum(np.abs(x[:-1]), np.abs(x[1:]))
    cut = np.flatnonzero(rel > jump) + 1
    return np.insert(x, cut, np.nan), np.insert(y, cut, np.nan)


def _segments(ax: Axes, x: np.ndarray, y: np.ndarray, stable: np.ndarray, color: str, label: str) -> None:
    """Draw a branch, solid where stable and dashed where not."""
    start = 0
    labelled = False
    for i in range(1, x.size + 1):
        if i == x.size or stable[i] != stable[start]:
            end = min(i + 1, x.size)  # overlap one point so the pieces join
            ls = "-" if stable[start] else "--"
            lab = None
            if not labelled:
                lab, labelled = label, True
            ax.plot(x[start:end], y[start:end], ls, color=color, lw=1.6, label=lab)
            start = i


#: hatches telling apart intervals of one multistable regime with different attractors
_HATCHES = ("", "//", "\\\\", "xx", "..", "++")


def _shade(diagram: RegimeDiagram, ax: Axes) -> tuple[list[Any], list[str]]:
    """Shade the intervals; return the legend's patches and labels, one per set of attractors.

    Two bistable intervals with different attractors (stick-slip + steady sliding, stick-slip +
    pure slip) get different hatches and labels; an interval narrower than half a percent of
    the axis gets a line of its colour as well, so that it shows.
    """
    combos: dict[tuple[str, tuple[str, ...]], str] = {}
    lo, hi = diagram.nu_min, diagram.nu_max
    logx = ax.get_xscale() == "log"
    width = math.log(hi / lo) if logx else hi - lo
    for iv in diagram.intervals:
        names = tuple(str(a) for a in iv.attractors) if len(iv.attractors) > 1 else ()
        key = (str(iv.regime), names)
        if key not in combos:
            used = sum(k[0] == key[0] for k in combos)
            combos[key] = _HATCHES[used % len(_HATCHES)]
        color = REGIME_COLORS.get(str(iv.regime), "#ffffff")
        ax.axvspan(iv.nu_min, iv.nu_max, facecolor=color, hatch=combos[key], edgecolor="0.55", lw=0)
        span = math.log(iv.nu_max / iv.nu_min) if logx else iv.nu_max - iv.nu_min
        if span < 0.005 * width:
            mid = math.sqrt(iv.nu_min * iv.nu_max) if logx else 0.5 * (iv.nu_min + iv.nu_max)
            ax.axvline(mid, color=color, lw=3.0, zorder=1, alpha=0.9)
            ax.axvline(mid, color="0.55", lw=0.6, ls=(0, (2, 2)), zorder=1)
    patches = [
        Patch(facecolor=REGIME_COLORS.get(r, "#ffffff"), hatch=h, edgecolor="0.55")
        for (r, _), h in combos.items()
    ]
    labels = [f"regime: {r}" + (f" ({' + '.join(n)})" if n else "") for r, n in combos]
    return patches, labels


def _v0_axis(ax: Axes, beta: float, nu_min: float, nu_max: float) -> None:
    """Put the driving velocity ``v0 = nu / beta`` on the top axis, in um/s, mm/s or m/s as suits."""
    unit, size = readable_unit([math.sqrt(nu_min * nu_max) / beta], VELOCITY_UNITS)
    per_nu = 1.0 / (beta * size)  # v0 in the unit per unit of nu

    def forward(nu: Any) -> Any:
        return np.asarray(nu, dtype=float) * per_nu

    def back(v: Any) -> Any:
        return np.asarray(v, dtype=float) / per_nu

    top = ax.secondary_xaxis("top", functions=(forward, back))
    top.set_xlabel(f"driving velocity $v_0$ [{pretty_units(unit)}]")
    if ax.get_xscale() == "log":
        plain_log_ticks(top.xaxis)


def plot_bifurcation(diagram: RegimeDiagram, *, log: bool | None = None, beta: float | None = None) -> Figure:
    """Plot amplitude against ``nu``: branches (stable solid, unstable dashed), regimes shaded.

    Parameters
    ----------
    diagram : RegimeDiagram
        From :func:`stickslip.bifurcation.regimes.regimes`.
    log : bool, optional
        Logarithmic ``nu`` axis; default when the range spans more than a factor 20.
    beta : float, optional
        A physical set-up's ``beta`` (s/m): the top axis gives the driving velocity
        ``v0 = nu / beta`` in a unit that suits the range.

    """
    fig, ax = subplots(figsize=(6.4, 4.8), constrained_layout=True)
    if log if log is not None else diagram.nu_max / diagram.nu_min > 20:
        ax.set_xscale("log")
        plain_log_ticks(ax.xaxis)
    regime_patches, regime_labels = _shade(diagram, ax)
    grid = diagram.branches[0].nu
    named: set[str] = set()  # one legend entry a kind (a law with two Hopf points has two pure-slip branches)
    for b in diagram.branches:
        if b.nu.size == 0:
            continue
        kind = b.kind if b.kind not in named else "_nolegend_"
        named.add(b.kind)
        if b.kind == "stick-slip":
            # the orbit through breakaway exists on pieces of the range: no line across a gap
            inside = np.searchsorted(grid, b.nu[1:], side="left") - np.searchsorted(
                grid, b.nu[:-1], side="right"
            )
            cuts = np.flatnonzero(inside > 0) + 1
            for k, (i0, i1) in enumerate(itertools.pairwise([0, *cuts, b.nu.size])):
                sel = slice(i0, i1)
                label = kind if k == 0 else "_nolegend_"
                _segments(ax, b.nu[sel], b.amplitude[sel], b.stable[sel], _BRANCH_COLORS[b.kind], label)
            continue
        _segments(ax, b.nu, b.amplitude, b.stable, _BRANCH_COLORS[b.kind], kind)
    markers = {
        "hopf": ("o", "k"),
        "fold": ("s", "C1"),
        "grazing": ("v", "C4"),
        "stick-slip-onset": ("x", "C3"),
    }
    # slip-reversal orbits (never sticking, velocity changing sign): not continued, shown where
    # the engine reached them, from rest or from a probe
    grid = diagram.branches[0].nu
    rev_amp: list[float] = []
    for rows in (diagram.rest, *diagram.probes):
        if len(rows) != grid.size:
            continue
        rev = rows.is_regime(Regime.PURE_SLIP) & (rows.n_backward > 0)
        if rev.any():
            ax.plot(
                grid[rev],
                rows.amplitude[rev],
                ".",
                color="C5",
                ms=3,
                label=None if rev_amp else "slip reversal (engine)",
            )
            rev_amp.append(float(np.max(rows.amplitude[rev])))
    seen = set()
    for p in diagram.points:
        if not np.isfinite(p.amplitude):  # a boundary of an attractor that no branch follows
            word = None if p.kind in seen else POINT_WORDS.get(p.kind, p.kind)
            ax.axvline(p.nu, color="0.3", ls=":", lw=1.0, label=word, zorder=4)
            seen.add(p.kind)
            continue
        m, c = markers.get(p.kind, ("+", "k"))
        ax.plot(
            [p.nu],
            [p.amplitude],
            m,
            color=c,
            ms=6,
            mfc="none" if m in "os" else c,
            label=None if p.kind in seen else POINT_WORDS.get(p.kind, p.kind),
            zorder=5,
        )
        seen.add(p.kind)
    ax.set_xlim(diagram.nu_min, diagram.nu_max)
    if beta:
        _v0_axis(ax, beta, diagram.nu_min, diagram.nu_max)
    top = max([float(np.nanmax(b.amplitude)) for b in diagram.branches if b.nu.size] + rev_amp, default=1.0)
    ax.set_ylim(-0.03 * top, 1.08 * top)
    ax.set_xlabel(r"dimensionless driving velocity $\nu = \beta v_0$")
    ax.set_ylabel(r"amplitude of the spring force [$\mu_s W$]")
    law = diagram.law
    ax.set_title(_law_words(law.name, dict(law.params)), fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    # a branch's entry in its colour, solid; the line style is said once (a branch's first piece
    # set it: steady sliding read dashed where it is stable)
    handles = [
        Line2D([], [], color=h.get_color(), ls="-", lw=h.get_linewidth())
        if isinstance(h, Line2D) and h.get_linestyle() in ("--", "-")
        else h
        for h in handles
    ]
    handles += [Line2D([], [], color="0.3", ls="-", lw=1.6), Line2D([], [], color="0.3", ls="--", lw=1.6)]
    labels += ["stable", "unstable"]
    handles += regime_patches
    labels += regime_labels
    _legend_below(fig, handles, labels)
    return fig


def _legend_below(fig: Figure, handles: list[Any], labels: list[str]) -> None:
    """Put the legend under the axes, in rows of four (beside them, it took a third of the width)."""
    fig.legend(
        handles, labels, fontsize=7, loc="outside lower center", ncols=min(4, len(labels)), frameon=False
    )


def _map_axes(ds: Any, variable: str, codes: dict[str, int], colors: dict[str, str], title: str) -> Figure:
    param = next(d for d in ds[variable].dims if d != "nu")
    names = list(codes)
    values = [codes[n] for n in names]
    order = np.argsort(values)
    names = [names[i] for i in order]
    values = [values[i] for i in order]
    cmap = ListedColormap([colors[n] for n in names])
    bounds = [v - 0.5 for v in values] + [values[-1] + 0.5]
    norm = BoundaryNorm(bounds, cmap.N)
    fig, ax = subplots(figsize=(6.4, 4.8), constrained_layout=True)
    ax.pcolormesh(
        ds.nu.values, ds[param].values, ds[variable].values, cmap=cmap, norm=norm, shading="nearest"
    )
    styles = {
        "hopf": ("k", "-"),
        "grazing": ("C4", "--"),
        "stick_slip_onset": ("C3", ":"),
        "fold": ("C1", "-."),
    }
    for key, (c, ls) in styles.items():
        if key in ds and np.any(np.isfinite(ds[key].values)):
            # in the bifurcation figure's words
            label = POINT_WORDS[key.replace("stick_slip", "stick-slip").replace("_", "-")]
            ax.plot(*_breaks(ds[key].values, ds[param].values), ls, color=c, lw=1.4, label=label)
    nu = ds.nu.values
    if MARK_VALUE in ds.attrs:  # where the paper's experiment lies (clipped to the map)
        lo, hi = max(float(ds.attrs[MARK_NU_MIN]), nu[0]), min(float(ds.attrs[MARK_NU_MAX]), nu[-1])
        if lo < hi:
            y = float(ds.attrs[MARK_VALUE])
            ax.plot([lo, hi], [y, y], "-", color="w", lw=5.0, solid_capstyle="butt")
            ax.plot([lo, hi], [y, y], "-", color="k", lw=2.5, solid_capstyle="butt",
                    label=str(ds.attrs.get(MARK_LABEL, "marked")))  # fmt: skip
    if nu[-1] / nu[0] > 20:
        ax.set_xscale("log")
    ax.set_xlim(nu[0], nu[-1])
    if ds.attrs.get(BETA_ATTR):  # a physical set-up's map
        _v0_axis(ax, float(ds.attrs[BETA_ATTR]), float(nu[0]), float(nu[-1]))
    ax.set_xlabel(r"dimensionless driving velocity $\nu = \beta v_0$")
    ax.set_ylabel(f"{ds.attrs.get('law', '')} law: {_SYMBOLS.get(param, param)}")
    ax.set_title(title, fontsize=10)
    present = [n for n in names if np.any(ds[variable].values == codes[n])]
    handles, labels = ax.get_legend_handles_labels()
    handles += [Patch(color=colors[n]) for n in present]
    labels += present
    _legend_below(fig, handles, labels)
    return fig


def plot_regime_map(ds: Any) -> Figure:
    """Plot the regimes over (``nu``, law parameter).

    ``ds`` comes from :func:`~stickslip.bifurcation.regime_map.regime_map`.
    """
    from ..bifurcation.regime_map import REGIME_CODES

    fixed = ", ".join(
        f"{_SYMBOLS.get(k, k)} = {v:.4g}"
        for k, v in ds.attrs.items()
        if isinstance(v, float) and k not in _NOT_IN_TITLE
    )
    return _map_axes(ds, "regime", {**REGIME_CODES}, REGIME_COLORS, f"regimes ({fixed})")


def plot_criterion_map(trial: Any) -> Figure:
    """Plot where the amplitude criterion is right or wrong.

    ``trial`` comes from :func:`~stickslip.bifurcation.regime_map.criterion_trial`.
    """
    codes = {"not judged": -1, "wrong": 0, "right": 1}
    colors = {"not judged": "#f0f0f0", "wrong": "#d7301f", "right": "#74c476"}
    fixed = ", ".join(
        f"{_SYMBOLS.get(k, k)} = {v:.4g}"
        for k, v in trial.attrs.items()
        if isinstance(v, float) and k not in _NOT_IN_TITLE
    )
    return _map_axes(
        trial, "right", codes, colors, f"the criterion (sign of dA/dv0) against the regime reached ({fixed})"
    )
