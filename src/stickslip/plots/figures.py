"""Figures for papers: labelled axes with units, PNG and vector output."""

from __future__ import annotations

import contextlib
import io
import math
import os
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..io.output import OutputFolder, emit, generator
from ..io.tables import unit_of
from .style import envelope, plain_log_ticks, pretty_units, subplots

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..dynamics.trajectory import Trajectory

__all__ = ["figure_bytes", "plot_spring_force", "save_figure", "save_figure_bytes"]


def draw_phases(ax: Any, t: np.ndarray, f: np.ndarray, phase: np.ndarray) -> None:
    """Draw a spring-force record with its slip phases marked (stick in blue, slip in red).

    Stick phases usually fill almost the whole period, so shading them tells nothing; the
    slip phases, short and steep, are drawn thicker in their own colour instead.
    """
    ax.plot(*envelope(t, f), color="C0", lw=1.2, label="stick (block at rest)")
    slip = phase != 0
    if slip.any():
        # a slip run with the samples just before and after it, so that it joins the ramps
        near = slip | np.roll(slip, 1) | np.roll(slip, -1)
        near[0] = slip[0]
        near[-1] = slip[-1]
        idx = np.flatnonzero(near)
        if idx.size > 20_000:  # many slips: their envelope, gaps kept as gaps
            idx = idx[:: int(np.ceil(idx.size / 20_000))]
        ts, fs = t[idx], f[idx]
        gaps = np.flatnonzero(np.diff(idx) > 1) + 1
        ax.plot(
            np.insert(ts, gaps, np.nan),
            np.insert(fs, gaps, np.nan),
            color="C3",
            lw=2.4,
            label="slip (block moving)",
        )


def phase_legend(fig: Figure, ax: Any) -> None:
    """Name the stick and slip lines of :func:`draw_phases` below the figure.

    A saw-tooth fills its axes corner to corner, so a legend inside would hide a drop or a
    ramp (the lower right corner held the last drop's bottom); outside it hides nothing.
    """
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=len(labels), fontsize=8, frameon=False)


def plot_spring_force(traj: Trajectory, *, title: str | None = None) -> Figure:
    """Plot the spring force against time, slip phases marked.

    Parameters
    ----------
    traj : Trajectory
        A simulated (or measured) trajectory.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    """
    fig, ax = subplots(figsize=(6.4, 3.6), layout="constrained")
    if traj.physical:
        draw_phases(ax, traj.time, traj.spring_force * 1e3, traj.phase)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("spring force [mN]")
    else:
        draw_phases(ax, traj.time, traj.spring_force, traj.phase)
        ax.set_xlabel(r"time $\tau$ [$\sqrt{m/k}$]")
        ax.set_ylabel(r"spring force $s$ [$\mu_s W$]")
    if (traj.phase == 0).any():
        phase_legend(fig, ax)
    ax.set_xlim(traj.time[0], traj.time[-1])
    if title:
        ax.set_title(pretty_units(title))
    return fig


def save_figure(
    fig: Figure,
    stem: str | os.PathLike[str],
    formats: Sequence[str] = ("png", "svg"),
    *,
    out: OutputFolder | None = None,
    overwrite: bool = False,
) -> list[str]:
    """Save ``fig`` as ``stem.png`` and ``stem.svg`` (or the given formats); return the paths.

    Each file is written atomically and marked as stickslip's (PNG ``Software``,
    SVG ``Creator``); an existing file that is not a stickslip figure is kept unless
    ``overwrite``. With ``out`` (an :class:`~stickslip.io.output.OutputFolder`)
    ``stem`` is a name inside it and the files are staged with the run's others.
    The figure is laid out for the first format; the others reuse that layout.
    """
    stem = os.fspath(stem)
    paths = []
    with _layout_once(fig) as drawn:
        for fmt in formats:

            def write(path: str, fmt: str = fmt) -> None:
                _savefig(fig, path, fmt)
                drawn()

            paths.append(emit(f"{stem}.{fmt}", "figure", write, out=out, overwrite=overwrite))
    return paths


@contextlib.contextmanager
def _layout_once(fig: Figure) -> Iterator[Callable[[], None]]:
    """Lay ``fig`` out for its first file only: the other formats reuse those positions.

    Constrained layout measures every label's text again at each save (a quarter
    of the time of a PNG and SVG pair, measured); call the callback after a save
    has drawn the figure. Its layout engine is restored at the end, so a figure
    changed later is laid out again.
    """
    engine = fig.get_layout_engine()

    def drawn() -> None:
        if engine is not None and fig.get_layout_engine() is engine:
            fig.set_layout_engine("none")

    try:
        yield drawn
    finally:
        if engine is not None:
            fig.set_layout_engine(engine)


def _savefig(fig: Figure, target: Any, fmt: str) -> None:
    """Write ``fig`` to a path or a binary file in ``fmt``, marked as stickslip's figure."""
    key = {"png": "Software", "svg": "Creator", "pdf": "Creator"}.get(fmt)
    metadata: dict[str, Any] | None = {key: generator("figure")} if key else None
    if fmt == "pdf" and metadata is not None:
        metadata["CreationDate"] = None  # the same figure, the same bytes (as the SVG below)
    if fmt == "svg" and metadata is not None:
        # the same figure, the same bytes: no date, and ids from a fixed salt, so that two
        # identical reproductions write identical SVGs
        metadata["Date"] = None
        import matplotlib

        with matplotlib.rc_context({"svg.hashsalt": "stickslip"}):
            fig.savefig(target, dpi=200, format=fmt, metadata=metadata)
        return
    fig.savefig(target, dpi=200, format=fmt, metadata=metadata)


def figure_bytes(fig: Figure, formats: Sequence[str] = ("png", "svg")) -> dict[str, bytes]:
    """Return ``fig`` rendered in each format, the bytes :func:`save_figure` would write."""
    blobs = {}
    with _layout_once(fig) as drawn:
        for fmt in formats:
            buf = io.BytesIO()
            _savefig(fig, buf, fmt)
            drawn()
            blobs[fmt] = buf.getvalue()
    return blobs


def save_figure_bytes(
    blobs: dict[str, bytes],
    stem: str | os.PathLike[str],
    *,
    out: OutputFolder | None = None,
    overwrite: bool = False,
) -> list[str]:
    """Write figures rendered by :func:`figure_bytes` as ``stem.<format>``, as :func:`save_figure` does."""
    stem = os.fspath(stem)
    paths = []
    for fmt, data in blobs.items():

        def write(path: str, data: bytes = data) -> None:
            with open(path, "wb") as f:
                f.write(data)

        paths.append(emit(f"{stem}.{fmt}", "figure", write, out=out, overwrite=overwrite))
    return paths


def plot_sweep(ds: Any, *, log: bool = False) -> Figure:
    """Plot amplitude and period of a sweep against its first dimension.

    One line per value of the second dimension; further dimensions are fixed at
    their first value (say so in the title).
    """
    # x: the longest dimension (the range), lines: the next longest
    dims = sorted(ds.amplitude.dims, key=lambda d: -ds.sizes[d])
    x = dims[0]
    fig, axes = subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    sel = {d: 0 for d in dims[2:]}
    sub = (ds.isel(sel) if sel else ds).transpose(*dims[:2]) if len(dims) > 1 else ds
    series = (
        [(None, sub)]
        if len(dims) == 1
        else [(float(v), sub.isel({dims[1]: i})) for i, v in enumerate(sub[dims[1]].values)]
    )
    for ax, var in zip(axes, ("amplitude", "period"), strict=True):
        for value, part in series:
            label = (
                None
                if value is None
                else pretty_units(f"{dims[1]} = {value:g} {sub[dims[1]].attrs.get('units', '')}")
            )
            y = np.asarray(part[var].values, dtype=float)
            if log:  # steady sliding's amplitude 0 has no place on a log axis (it drew lines off it)
                y = np.where(y > 0, y, np.nan)
            ax.plot(part[x].values, y, marker="o", ms=3, lw=1.2, label=label)
        ax.set_xlabel(pretty_units(f"{x} [{unit_of(ds[x]) or '1'}]"))
        ax.set_ylabel(pretty_units(f"{var} [{unit_of(ds[var]) or '1'}]"))
        if log:
            ax.set_xscale("log")
            ax.set_yscale("log")
            plain_log_ticks(ax.xaxis)
        if len(dims) > 1:
            ax.legend(frameon=False, fontsize=8)
    if sel:
        fig.suptitle(", ".join(f"{d} = {float(ds[d].values[0]):g}" for d in sel), fontsize=9)
    return fig


def plot_rate_state(ds: Any) -> Figure:
    """Plot a rate-and-state run: friction, slip velocity and state against time."""
    fig, axes = subplots(3, 1, figsize=(7.0, 7.5), sharex=True, layout="constrained")
    t = ds.time.values
    axes[0].plot(*envelope(t, ds.friction.values), lw=1.2)
    axes[0].set_ylabel("friction coefficient")
    axes[1].semilogy(*envelope(t, ds.slip_velocity.values), lw=1.2, label="slider")
    vlp = ds.load_point_velocity.values
    if np.any(vlp > 0):
        # each sample's load-point velocity holds until the next sample: a step, not a ramp
        axes[1].semilogy(
            t, np.where(vlp > 0, vlp, np.nan), "k:", lw=1.0, drawstyle="steps-post", label="load point"
        )
    # holds: a load-point velocity of zero has no place on the log axis, so shade them
    held = np.flatnonzero(np.diff(np.concatenate([[0], (vlp <= 0).astype(np.int8), [0]])))
    for k, (i, j) in enumerate(zip(held[::2], held[1::2], strict=True)):
        for ax in axes:
            label = "hold (load point at rest)" if k == 0 and ax is axes[1] else None
            ax.axvspan(t[i], t[min(j, t.size - 1)], color="0.9", lw=0, zorder=0, label=label)
    axes[1].set_ylabel("velocity [m/s]")
    axes[1].legend(frameon=False, fontsize=8)
    states = [n for n in ds.data_vars if n == "state" or n.startswith("state_")]
    for i, name in enumerate(states):
        axes[2].semilogy(*envelope(t, ds[name].values), lw=1.2, label=rf"$\Phi_{i + 1}$")
    if len(states) > 1:
        axes[2].legend(frameon=False, fontsize=8)
    axes[2].set_ylabel(r"state $\Phi$ [s]")
    axes[2].set_xlabel("time [s]")
    laws = list(dict.fromkeys(str(ds.attrs.get("state_law", "")).split(",")))
    fig.suptitle(
        f"rate and state ({ds.attrs.get('model', '')}, {', '.join(laws)} law{'s' if len(laws) > 1 else ''})",
        fontsize=10,
    )
    return fig


def plot_rate_state_fit(fit: Any) -> Figure:
    """Overlay a rate-and-state fit on its record, with the residuals below."""
    fig, axes = subplots(
        2, 1, figsize=(7.5, 5.5), sharex=True, layout="constrained", gridspec_kw={"height_ratios": [3, 1]}
    )
    t = fit.time
    axes[0].plot(t, fit.friction, ".", ms=1.5, color="0.55", label="record")
    axes[0].plot(t, fit.model, "-", lw=1.2, color="C3", label="fit")
    axes[0].set_ylabel("friction coefficient")
    text = ", ".join(
        f"{n} = {fit.values[n] * (1e6 if n.startswith('dc') else 1):.4g}"
        f"{' um' if n.startswith('dc') else (' 1/m' if n == 'stiffness_per_load' else '')}"
        for n in fit.names
    )
    axes[0].set_title(f"{text}; reduced chi2 = {fit.reduced_chi2:.3g}", fontsize=8)
    axes[0].legend(frameon=False, fontsize=8, markerscale=6)
    axes[1].plot(t, fit.residuals, ".", ms=1.5, color="0.35")
    axes[1].axhline(0.0, color="C3", lw=0.8)
    for sgn in (-1, 1):
        axes[1].axhline(
            sgn * 2 * fit.noise, color="C3", lw=0.6, ls=":", label="±2σ (the noise)" if sgn > 0 else None
        )
    axes[1].legend(frameon=False, fontsize=8, loc="upper right")
    axes[1].set_ylabel("residual")
    axes[1].set_xlabel("time [s]")
    return fig


def plot_records(table: Any) -> dict[str, Figure]:
    """Amplitude and period of measured records against driving velocity and against load."""
    figs: dict[str, Figure] = {}
    for key, label, scale, unit in (
        ("v0 [m/s]", "driving velocity", 1e6, "um/s"),
        ("load [N]", "normal load", 1e3, "mN"),
    ):
        x = table[key].to_numpy(dtype=float)
        if not np.isfinite(x).any() or np.unique(x[np.isfinite(x)]).size < 2:
            continue
        fig, axes = subplots(1, 2, figsize=(10, 3.8), layout="constrained")
        order = np.argsort(x)
        for ax, col, ylabel, yscale in (
            (axes[0], "amplitude", "amplitude [mN]", 1e3),
            (axes[1], "period", "period [s]", 1.0),
        ):
            y = table[f"{col} [{'N' if col == 'amplitude' else 's'}]"].to_numpy(dtype=float)
            e = table[f"{col}_spread [{'N' if col == 'amplitude' else 's'}]"].to_numpy(dtype=float)
            ax.errorbar(
                x[order] * scale, y[order] * yscale, yerr=e[order] * yscale, fmt="o-", ms=4, capsize=2
            )
            ax.set_xscale("log")
            plain_log_ticks(ax.xaxis)
            ax.set_xlabel(f"{label} [{pretty_units(unit)}]")
            ax.set_ylabel(ylabel)
        figs[f"records_vs_{'v0' if key.startswith('v0') else 'load'}"] = fig
    return figs


#: a marker and colour for each observed regime of the (V, k) plane
REGIME_STYLE = {
    "periodic stick-slip": ("s", "C3"),
    "irregular stick-slip": ("D", "C1"),
    "mixed": ("^", "C4"),
    "pure slip": ("o", "C0"),
    "steady sliding": ("v", "C2"),
    "undetermined": ("x", "0.5"),
}


def plot_regime_plane(table: Any, model: Any = None) -> dict[str, Figure]:
    """Draw the measured regime diagram: each record in the (V, k) plane, and amplitude against V per k.

    Left, each record at its driving velocity and stiffness (the stated one, else the
    measured), marked by its observed regime and labelled with its stick fraction; right,
    the paper's criterion: the amplitude against the driving velocity, one line per
    stiffness. Empty (no figure) without records whose motion was measured.

    With ``model`` (a :class:`~stickslip.data.model_plane.ModelPlane`), the left panel
    is shaded by the regime the model computes over the plane, at the records' median
    mass and load, with contours of the model's stick fraction (0.25, 0.5, 0.75, 0.9),
    and its title says how many records it agrees with.
    """
    if "regime" not in table.columns:
        return {}
    rows = table[table["regime"].notna() & np.isfinite(table["v0 [m/s]"].to_numpy(dtype=float))]
    if rows.empty:
        return {}
    k = rows["stiffness_nominal [N/m]"].to_numpy(dtype=float)
    k = np.where(np.isfinite(k), k, rows["stiffness [N/m]"].to_numpy(dtype=float))
    v = rows["v0 [m/s]"].to_numpy(dtype=float) * 1e6
    fig, (ax, ax2) = subplots(1, 2, figsize=(10, 4.0), layout="constrained")
    title = "observed regime (stick fraction)"
    if model is not None and model.plane is not None:
        _shade_model(ax, model)
        title = (
            "observed regime (stick fraction) over the model's;\n"
            f"the model's regime agrees with {model.agree} of {model.compared} compared"
        )
    for regime, (marker, color) in REGIME_STYLE.items():
        sel = (rows["regime"] == regime).to_numpy()
        if sel.any():
            ax.scatter(v[sel], k[sel], marker=marker, color=color, s=60, label=regime, zorder=3)
    for x, y, sf in zip(v, k, rows["stick_fraction"].to_numpy(dtype=float), strict=True):
        if np.isfinite(sf):
            ax.annotate(f"{sf:.2f}", (x, y), textcoords="offset points", xytext=(6, 6), fontsize=8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("driving velocity V [µm/s]")
    ax.set_ylabel("stiffness k [N/m]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7, loc="best")
    amp = rows["amplitude [N]"].to_numpy(dtype=float) * 1e3
    for i, kk in enumerate(np.unique(k[np.isfinite(k)])):
        sel = k == kk
        order = np.argsort(v[sel])
        ax2.plot(v[sel][order], amp[sel][order], "o-", color=f"C{i}", label=f"k = {kk:.4g} N/m")
    ax2.set_xscale("log")
    ax2.set_xlabel("driving velocity V [µm/s]")
    ax2.set_ylabel("amplitude [mN]")
    ax2.set_title("the criterion: amplitude against V", fontsize=10)
    ax2.legend(fontsize=8)
    return {"regime_plane": fig}


#: the regimes a sweep's point can reach, shaded in the regime maps' colours
MODEL_REGIMES = ("stick-slip", "pure-slip", "slip-reversal", "steady-sliding")


def _shade_model(ax: Any, model: Any) -> None:
    """Shade ``ax`` (V in um/s, k in N/m) by the model's regime over ``model.plane``."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    from .regimes import REGIME_COLORS

    plane = model.plane
    names = [r for r in MODEL_REGIMES if (plane["regime"] == r).any()]
    codes = np.full(plane["regime"].shape, np.nan)
    for i, r in enumerate(names):
        codes[(plane["regime"] == r).to_numpy()] = i
    v, k = plane["v0"].to_numpy(), plane["stiffness"].to_numpy()
    if names:
        ax.pcolormesh(
            v,
            k,
            codes.T,
            cmap=ListedColormap([REGIME_COLORS[r] for r in names]),
            vmin=-0.5,
            vmax=len(names) - 0.5,
            shading="nearest",
            zorder=0,
        )
    sf = np.asarray(plane["stick_fraction"], dtype=float).T
    if np.isfinite(sf).sum() > 3 and np.nanmax(sf) > np.nanmin(sf):
        lines = ax.contour(v, k, sf, levels=[0.25, 0.5, 0.75, 0.9], colors="0.45", linewidths=0.6, zorder=1)
        ax.clabel(lines, fontsize=6, fmt="%.2g")
    ax.set_xlim(v[0], v[-1])
    ax.set_ylim(k[0], k[-1])
    ax.add_artist(
        ax.legend(
            handles=[Patch(color=REGIME_COLORS[r], label=f"model: {r}") for r in names],
            fontsize=7,
            loc="lower left",
            title=f"m = {1e3 * model.mass:.3g} g, W = {1e3 * model.load:.3g} mN",
            title_fontsize=7,
        )
    )


def plot_fit_overlay(record: Any, fit: Any, *, cycles: int = 3, max_points: int = 20_000) -> Figure:
    """Overlay a record and the fitted model over a few cycles, with the residuals underneath.

    Parameters
    ----------
    record : Record
        The measured record.
    fit : FitResult
        From :func:`stickslip.data.fitting.fit_record`; its ``model_force`` gives the
        model on the record's clock.
    cycles : int, optional
        Cycles shown, from the middle of the record.
    max_points : int, optional
        Samples drawn at most (decimated beyond).

    """
    t = record.time
    period = float(fit.summary.period)
    mid = 0.5 * (t[0] + t[-1])
    lo = max(t[0], mid - 0.5 * cycles * period)
    sel = (t >= lo) & (t <= lo + cycles * period)
    # a uniform stride, not an envelope: the residuals' spread must stay the noise's
    idx = np.flatnonzero(sel)
    if idx.size > max_points:
        idx = idx[:: int(np.ceil(idx.size / max_points))]
    tt, ff = t[idx], record.force[idx]
    model = fit.model_force(tt)
    fig, (ax, ax_r) = subplots(
        2, 1, figsize=(7.2, 5.0), sharex=True, height_ratios=[3, 1.3], layout="constrained"
    )
    ax.plot(tt, ff * 1e3, color="0.6", lw=0.7, label="measured")
    ax.plot(tt, model * 1e3, color="C3", lw=1.3, label="fitted model")
    ax.set_ylabel("force [mN]")
    ax.legend(frameon=False, fontsize=8, loc="lower right")
    chi2 = getattr(fit, "reduced_chi2", float("nan"))
    ax.set_title(
        f"{record.name}: data and fitted model ({fit.method} fit, reduced chi2 = {chi2:.2f})", fontsize=10
    )
    resid = (ff - model) * 1e3
    ax_r.plot(tt, resid, color="0.6", lw=0.4)
    # a running mean shows a systematic misfit that the noise hides
    width = max(1, resid.size // 200)
    ax_r.plot(
        tt, np.convolve(resid, np.ones(width) / width, mode="same"), color="C3", lw=1.0, label="running mean"
    )
    noise = getattr(fit, "noise", float("nan"))
    if np.isfinite(noise):
        for sign in (-1, 1):
            ax_r.axhline(sign * noise * 1e3, color="C0", ls=":", lw=1.0, label="noise" if sign > 0 else None)
    ax_r.legend(frameon=False, fontsize=7, loc="upper right", ncols=2)
    ax_r.axhline(0.0, color="0.5", lw=0.6)
    ax_r.set_ylabel("residual [mN]")
    ax_r.set_xlabel("time [s]")
    return fig


def plot_earthquake_cycles(runs: Sequence[Any], estimate: dict[str, float] | None = None) -> Figure:
    """Slip rate and shear stress over the cycles, and the slip rate through one event, per run."""
    fig, axes = subplots(3, 1, figsize=(8.0, 8.5), layout="constrained")
    year = 365.25 * 24 * 3600.0
    for k, run in enumerate(runs):
        s = run.series
        t = s.time.values / year
        label = run.model
        axes[0].semilogy(*envelope(t, s.slip_rate.values), lw=0.9, color=f"C{k}", label=label)
        axes[1].plot(*envelope(t, s.shear_stress.values / 1e6), lw=0.9, color=f"C{k}", label=label)
        cat = run.catalog
        if cat.sizes["event"] > 2:
            i = cat.sizes["event"] // 2
            tp = float(cat.t_peak.values[i])
            sel = (s.time.values > tp - 60.0) & (s.time.values < tp + 60.0)
            axes[2].semilogy(
                s.time.values[sel] - tp, s.slip_rate.values[sel], ".-", ms=2, lw=0.8, color=f"C{k}",
                label=f"{label}: event {i}",
            )  # fmt: skip
    if not axes[2].lines:  # no run has an event to show: say so rather than leave a blank frame
        axes[2].text(0.5, 0.5, "no event to show: fewer than 3 reached v_event", ha="center", va="center",
                     transform=axes[2].transAxes)  # fmt: skip
        axes[2].set_xticks([])
        axes[2].set_yticks([])
    vpl = runs[0].fault.plate_rate.to("m/s").magnitude
    for ax in axes[:1]:
        ax.axhline(vpl, color="k", ls=":", lw=0.8, label="plate rate")
    axes[0].set_ylabel("slip rate [m/s]")
    axes[1].set_ylabel("shear stress [MPa]")
    axes[1].set_xlabel("time [years]")
    axes[2].set_xlabel("time from the peak slip rate [s] (dots: accepted steps)")
    axes[2].set_ylabel("slip rate [m/s]")
    for ax in axes:
        if ax.get_legend_handles_labels()[0]:  # an axis with nothing labelled (no event) has none
            ax.legend(frameon=False, fontsize=7, loc="upper right")
    shown = ("stress_drop", "slip", "recurrence")
    if estimate is not None and all(math.isfinite(estimate[k]) for k in shown):
        # inside the stress panel, whose numbers it estimates (a title between the panels would
        # read as the slip-rate panel's caption), in headroom above
        # the curves so that it hides none of them
        lo, hi = axes[1].get_ylim()
        axes[1].set_ylim(lo, hi + 0.22 * (hi - lo))
        axes[1].text(
            0.01,
            0.97,
            f"spring-slider estimate: stress drop {estimate['stress_drop'] / 1e6:.3g} MPa, "
            f"slip {estimate['slip']:.3g} m, recurrence >= {estimate['recurrence'] / year:.3g} yr",
            transform=axes[1].transAxes,
            fontsize=7,
            va="top",
            bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "0.7", "alpha": 0.9},
        )
    return fig
