"""Figures of the forced oscillator: bifurcation diagram with its Lyapunov exponent, response curve, section.

:func:`plot_bifurcation` draws the stroboscopic samples against the parameter
(one dot per section) and, below on the same axis, the largest Lyapunov exponent
where it was computed: period doubling shows as a branch splitting in two, chaos
as a band of dots where the exponent is positive. :func:`plot_response` draws a
continued response curve, stable branches solid and unstable dashed, with its
bifurcations marked; :func:`plot_section` the stroboscopic section in the plane
of the spring force and the velocity; :func:`plot_forced_trajectory` a sampled
motion with its stick phases.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .style import subplots

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_bifurcation", "plot_forced_trajectory", "plot_response", "plot_section"]

_BIF_MARKERS = {
    "fold": ("o", "#2166ac"),
    "branch": ("s", "#762a83"),
    "period-doubling": ("D", "#b2182b"),
    "torus": ("^", "#1b7837"),
    "stick-change": ("v", "#555555"),
}


def _name(parameter: str) -> str:
    return {"omega": r"forcing frequency $\Omega\sqrt{m/k}$", "q": r"force amplitude $F_0/\mu_s W$"}.get(
        parameter, parameter
    )


def plot_bifurcation(ds: Any, *, variable: str = "s", title: str | None = None) -> Figure:
    """Draw a bifurcation diagram (:func:`stickslip.forced.diagram.bifurcation_diagram`).

    Parameters
    ----------
    ds : xarray.Dataset
        The diagram: ``s``, ``w`` (value x sample) and ``lyapunov`` per value.
    variable : str
        ``s`` (the spring force at the sections) or ``w`` (the velocity).
    title : str, optional
        The figure's title (default: what it shows).

    """
    values = np.asarray(ds["value"].values, dtype=float)
    y = np.asarray(ds[variable].values, dtype=float)
    lyap = np.asarray(ds["lyapunov"].values, dtype=float)
    with_lyap = bool(np.any(np.isfinite(lyap)))
    if with_lyap:
        fig, (ax, ax2) = subplots(
            2, 1, figsize=(7.0, 6.0), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]}
        )
    else:
        fig, ax = subplots(figsize=(7.0, 4.5))
        ax2 = None
    xs = np.repeat(values, y.shape[1])
    ax.plot(xs, y.ravel(), ",", color="k", alpha=0.6, rasterized=True)
    ax.set_ylabel("spring force at the sections" if variable == "s" else "velocity at the sections")
    ax.set_title(title or f"stroboscopic bifurcation diagram ({y.shape[1]} sections per value)")
    if ax2 is not None:
        ax2.axhline(0.0, color="0.6", lw=0.8)
        ax2.plot(values, lyap, color="#b2182b", lw=1.0)
        pos = lyap > 0
        ax2.fill_between(values, 0.0, np.where(pos, lyap, 0.0), color="#b2182b", alpha=0.25, lw=0)
        ax2.set_ylabel(r"$\lambda_1$ per $\sqrt{m/k}$")
        ax2.set_xlabel(_name(str(ds["value"].attrs.get("long_name", "parameter"))))
    else:
        ax.set_xlabel(_name(str(ds["value"].attrs.get("long_name", "parameter"))))
    return fig


def plot_response(curve: Any, *, title: str | None = None) -> Figure:
    """Draw a response curve (:func:`stickslip.forced.response_curve`): amplitude against the parameter."""
    fig, ax = subplots(figsize=(7.0, 4.5))
    v, a, stable = curve.values, curve.amplitude, curve.stable
    for flag, style, label in ((True, "-", "stable"), (False, "--", "unstable")):
        y = np.where(stable == flag, a, np.nan)
        # join each run to its neighbour so that a branch changing stability stays one line
        edge = np.flatnonzero(np.diff(stable.astype(int)) != 0)
        for i in edge:
            y[i if stable[i] != flag else i + 1] = a[i if stable[i] != flag else i + 1]
        ax.plot(v, y, style, color="k", lw=1.4, label=label)
    seen = set()
    for b in curve.bifurcations:
        marker, color = _BIF_MARKERS.get(b.kind, ("x", "k"))
        j = int(np.argmin(np.abs(v - b.value)))
        ax.plot(
            [b.value], [a[j]], marker, color=color, ms=7, label=None if b.kind in seen else b.kind, zorder=5
        )
        seen.add(b.kind)
    ax.set_xlabel(_name(curve.parameter))
    ax.set_ylabel(r"response amplitude (half the spring force's range) [$\mu_s W$]")
    ax.set_title(title or f"period-{curve.period} response")
    ax.legend(loc="best", fontsize=8)
    return fig


def plot_section(section: Any, *, title: str | None = None) -> Figure:
    """Draw a stroboscopic section (:func:`stickslip.forced.poincare_section`)."""
    fig, ax = subplots(figsize=(5.5, 4.5))
    ax.plot(section.s, section.w, ".", ms=2, color="k")
    unit = ("N", "m/s") if section.physical else (r"$\mu_s W$", r"$\mu_s W/\sqrt{km}$")
    ax.set_xlabel(f"spring force [{unit[0]}]")
    ax.set_ylabel(f"velocity [{unit[1]}]")
    ax.set_title(title or f"Poincaré section ({section.s.size} periods)")
    return fig


def plot_forced_trajectory(traj: Any, *, title: str | None = None) -> Figure:
    """Draw a sampled forced motion: spring force and velocity against time, stick shaded."""
    fig, (ax, ax2) = subplots(2, 1, figsize=(7.0, 5.0), sharex=True)
    ax.plot(traj.t, traj.s, color="k", lw=1.0)
    ax2.plot(traj.t, traj.w, color="#2166ac", lw=1.0)
    stuck = traj.mode == 0
    for a in (ax, ax2):
        lo, hi = a.get_ylim()
        a.fill_between(traj.t, lo, hi, where=stuck, color="0.85", lw=0, step="mid", label="stick")
        a.set_ylim(lo, hi)
    unit = ("s", "N", "m/s") if traj.physical else (r"$\sqrt{m/k}$", r"$\mu_s W$", r"$\mu_s W/\sqrt{km}$")
    ax.set_ylabel(f"spring force [{unit[1]}]")
    ax2.set_ylabel(f"velocity [{unit[2]}]")
    ax2.set_xlabel(f"time [{unit[0]}]")
    ax.set_title(title or f"forced motion: {traj.stats.stops} stops, {traj.stats.reversals} reversals")
    return fig
