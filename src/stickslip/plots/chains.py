"""Figures of chain catalogues: magnitude-frequency, space-time, recurrence, Lyapunov exponents."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from ..chains.statistics import BValue, magnitude_frequency, recurrence_times
from .style import subplots

#: marks above which a cloud of points is drawn as an image inside vector files: a
#: space-time figure of 3000 events on 1000 blocks was 63 MB of SVG squares, 157 kB so
RASTER = 5000

__all__ = ["plot_lyapunov", "plot_magnitude_frequency", "plot_recurrence", "plot_space_time"]


def plot_magnitude_frequency(catalog: Any, fit: BValue, *, bin_width: float = 0.1) -> Figure:
    """Plot events per magnitude bin and cumulative (Gutenberg-Richter), with the b-value fit."""
    m = catalog["magnitude"].values
    centres, counts, cum = magnitude_frequency(m, bin_width)
    fig, ax = subplots(figsize=(6.0, 4.2))
    keep = counts > 0
    ax.semilogy(centres[keep], counts[keep], "o", ms=3.5, color="0.35", label="events per bin")
    ax.semilogy(centres - 0.5 * bin_width, cum, "s", ms=3.0, mfc="none", color="C0", label="N(≥ M)")
    if np.isfinite(fit.b):
        top = fit.m_max if np.isfinite(fit.m_max) else float(np.nanmax(m))
        mm = np.linspace(fit.mc, top, 50)
        line = fit.expected_cumulative(mm, int(np.sum(m > fit.m_max)))
        ax.semilogy(
            mm,
            np.where(line > 0.0, line, np.nan),  # 0 at m_max with no event above: not drawn
            "-",
            color="C3",
            label=f"b = {fit.b:.3f} ± {fit.error:.3f} (Aki-Utsu, {fit.n} events)",
        )
        span = f"{fit.mc:.2f} <= M" + (f" <= {fit.m_max:.2f}" if np.isfinite(fit.m_max) else "")
        law = "" if fit.power_law else f", {fit.verdict}"
        ax.axvline(fit.mc, color="C3", ls=":", lw=1.0, label=f"fitted over {span} ({fit.method}{law})")
        if np.isfinite(fit.m_max):
            ax.axvline(fit.m_max, color="C3", ls=":", lw=1.0)
    ax.set_xlabel("magnitude M = log10(moment)")
    ax.set_ylabel("number of events")
    ax.legend(frameon=False, fontsize=8)
    ax.set_title(f"{catalog.sizes['event']} events, {catalog.attrs.get('blocks', '?')} blocks", fontsize=10)
    return fig


def plot_space_time(catalog: Any, *, max_events: int = 3000) -> Figure:
    """Draw each event's ruptured blocks against its start time (space-time), and each block's slip."""
    n = int(catalog.attrs.get("blocks", catalog.sizes.get("block", 1)))
    k = min(int(catalog.sizes["event"]), max_events)
    t0 = catalog["t_start"].values[:k]
    lo = catalog["first_block"].values[:k]
    hi = catalog["last_block"].values[:k]
    mag = catalog["magnitude"].values[:k]
    rec = int(catalog.attrs.get("slip_recorded", 0))
    ncol = 2 if rec > 0 else 1
    fig, axes = subplots(1, ncol, figsize=(5.2 * ncol, 4.4), squeeze=False)
    ax = axes[0, 0]
    vmin = float(np.nanmin(mag)) if np.isfinite(mag).any() else 0.0
    if rec > 0:
        # the blocks that slipped (an event may join separate patches: never draw its whole extent)
        kk = min(rec, k)
        ev, blk = np.nonzero(catalog["slip"].values[:kk] != 0.0)
        # the largest events first, the small ones on top: at a fast drive ruptures of the
        # whole chain overlap in time and would hide the small events drawn before them
        order = _large_first(mag[ev])
        ev, blk = ev[order], blk[order]
        cloud = {"rasterized": blk.size > RASTER, "linewidths": 0, "cmap": "viridis"}
        sc = ax.scatter(blk, t0[ev], c=mag[ev], s=2.0, marker="s", **cloud)
        ax.set_title("blocks that slipped in each event", fontsize=10)
        t_top = t0[kk - 1] if kk else 1.0
    else:
        whole = np.flatnonzero((hi - lo + 1) == catalog["n_blocks"].values[:k])  # contiguous ruptures only
        whole = whole[_large_first(mag[whole])]
        segs = [((a - 0.4, t), (b + 0.4, t)) for a, b, t in zip(lo[whole], hi[whole], t0[whole], strict=True)]
        sc = LineCollection(segs, cmap="viridis", linewidths=1.2, rasterized=len(segs) > RASTER)
        sc.set_array(np.nan_to_num(mag[whole], nan=vmin))
        ax.add_collection(sc)
        ax.set_title("contiguous ruptures", fontsize=10)
        t_top = t0[-1] if k else 1.0
    ax.set_xlim(-0.5, n - 0.5)
    if k:
        ax.set_ylim(t0[0], t_top if t_top > t0[0] else t0[0] + 1.0)
    ax.set_xlabel("block")
    ax.set_ylabel(f"time [{catalog['t_start'].attrs.get('units', '1')}]")
    fig.colorbar(sc, ax=ax, label="magnitude")
    if rec > 0:
        ax2 = axes[0, 1]
        slip = catalog["slip"].values[: min(rec, k)]
        positive = slip[slip > 0.0]
        norm = LogNorm(vmin=float(positive.min()), vmax=float(positive.max())) if positive.size else None
        im = ax2.imshow(
            np.where(slip > 0.0, slip, np.nan),
            norm=norm,
            aspect="auto",
            origin="lower",
            cmap="magma_r",
            interpolation="nearest",
            extent=(-0.5, n - 0.5, -0.5, slip.shape[0] - 0.5),
        )
        ax2.set_xlabel("block")
        ax2.set_ylabel("event number")
        ax2.set_title("slip of each block in each event", fontsize=10)
        fig.colorbar(im, ax=ax2, label=f"slip [{catalog['slip'].attrs.get('units', '1')}]")
    return fig


def _large_first(mag: Any) -> Any:
    """Return the order that draws the largest magnitudes first (NaN last), ties in catalogue order."""
    return np.argsort(-np.nan_to_num(mag, nan=-np.inf), kind="stable")


def plot_recurrence(catalog: Any) -> Figure:
    """Plot the times between successive events (histogram, logarithmic bins) and moment against time."""
    t0 = catalog["t_start"].values
    dt = recurrence_times(t0)
    dt = dt[dt > 0]
    fig, (a1, a2) = subplots(1, 2, figsize=(10.0, 4.0))
    if dt.size:
        bins = np.logspace(np.log10(dt.min()), np.log10(dt.max()) + 1e-9, 40)
        a1.hist(dt, bins=bins, color="C0")
        a1.set_xscale("log")
        a1.axvline(float(np.mean(dt)), color="C3", ls="--", label=f"mean {np.mean(dt):.4g}")
        a1.legend(frameon=False, fontsize=8)
    unit = catalog["t_start"].attrs.get("units", "1")
    a1.set_xlabel(f"time between event starts [{unit}]")
    a1.set_ylabel("events")
    a2.semilogy(t0, catalog["moment"].values, ".", ms=2.0, color="0.3", rasterized=t0.size > RASTER)
    a2.set_xlabel(f"event start [{unit}]")
    a2.set_ylabel(f"moment [{catalog['moment'].attrs.get('units', '1')}]")
    return fig


def plot_lyapunov(
    weakening: Sequence[float],
    exponent: Sequence[float],
    error: Sequence[float],
    gap: Sequence[float],
    *,
    label: str = "c",
) -> Figure:
    """Plot the event map's largest Lyapunov exponent and the outer blocks' gap against the weakening."""
    fig, (a1, a2) = subplots(2, 1, figsize=(6.0, 6.0), sharex=True)
    w = np.asarray(weakening, float)
    lam = np.asarray(exponent, float)
    a1.errorbar(w, lam, yerr=np.asarray(error, float), fmt="o-", ms=4, color="C0")
    a1.axhline(0.0, color="0.5", lw=0.8)
    undefined = ~np.isfinite(lam)
    if undefined.any():
        a1.plot(w[undefined], np.zeros(undefined.sum()), "x", color="C3", label="no event end (sliding)")
        a1.legend(frameon=False, fontsize=8)
    a1.set_ylabel("largest Lyapunov exponent\n(per event)")
    a2.semilogy(w, np.maximum(np.asarray(gap, float), 1e-16), "s-", ms=4, color="C2")
    a2.set_ylabel("|u_1 - u_3| (outer blocks)")
    a2.set_xlabel(f"weakening {label}")
    return fig
