"""The paper's figures, drawn only from the reproduction dataset (as read from NetCDF)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..models import zv_parameters
from ..plots.figures import draw_phases, figure_bytes, phase_legend
from ..plots.regimes import plot_criterion_map, plot_regime_map
from ..plots.style import plain_log_ticks, pretty_units, subplots

__all__ = ["FIGURES", "TRIAL_PLOTS", "make_figures", "render_figures", "render_trial_figures"]

#: the two figures of each criterion trial: ``<kind>_<trial key>``
TRIAL_PLOTS: tuple[tuple[str, Callable[[xr.Dataset], Figure]], ...] = (
    ("regimes", plot_regime_map),
    ("criterion", plot_criterion_map),
)


def _v0_axis(ax: Axes, ds: xr.Dataset, coord: str) -> None:
    ax.set_xscale("log")
    ax.set_xlabel(f"driving velocity $v_0$ [{pretty_units(ds[coord].attrs.get('units', ''))}]")


def fig1_spring_force(ds: xr.Dataset) -> Figure:
    """Fig. 1: spring force against time, zv set-up; slip phases marked, one magnified beside it."""
    zoom = "fig1_zoom_time" in ds
    fig, axes = subplots(
        1,
        2 if zoom else 1,
        figsize=(9.0 if zoom else 6.4, 3.8),
        layout="constrained",
        width_ratios=[3, 1.1] if zoom else None,
        squeeze=False,
    )
    ax = axes[0, 0]
    t = ds["fig1_time"].values
    f = ds["fig1_spring_force"].values * 1e3
    draw_phases(ax, t, f, ds["fig1_phase"].values)
    ax.set_xlim(t[0], t[-1])
    ax.set_xlabel("time [s]")
    ax.set_ylabel("spring force [mN]")
    ax.set_title(pretty_units(f"Fig. 1: zv set-up, F1, $v_0$ = {ds.attrs.get('fig1_v0', '')}"), fontsize=10)
    phase_legend(fig, ax)
    if zoom:
        tz = ds["fig1_zoom_time"].values
        fz = ds["fig1_zoom_spring_force"].values * 1e3
        phase = ds["fig1_zoom_phase"].values
        t0 = float(tz[phase != 0][0])
        duration = float(tz[phase != 0][-1]) - t0
        right = axes[0, 1]
        draw_phases(right, tz - t0, fz, phase)
        right.set_xlim(tz[0] - t0, tz[-1] - t0)
        right.set_ylim(ax.get_ylim())
        right.set_xlabel("time from breakaway [s]")
        right.set_title(f"one slip, magnified ({1e3 * duration:.0f} ms)", fontsize=10)
    return fig


def _fig2_curves(ds: xr.Dataset, var: str, scale: float, ylabel: str, title: str) -> Figure:
    """One zv curve per b against v0: b = 0 solid, b = 100 s/m dotted, log-log."""
    fig, ax = subplots(figsize=(6.4, 4.0), layout="constrained")
    v = ds["fig2_v0"].values
    for i, b in enumerate(ds["fig2_b"].values):
        ax.plot(
            v, ds[var].values[i] * scale, ls="-" if b == 0 else ":", lw=1.8, color="k", label=f"b = {b:g} s/m"
        )
    _v0_axis(ax, ds, "fig2_v0")
    ax.set_yscale("log")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.legend(frameon=False)
    return fig


def fig2_amplitude_v0(ds: xr.Dataset) -> Figure:
    """Fig. 2: amplitude against v0 for b = 0 (solid) and b = 100 s/m (dotted)."""
    return _fig2_curves(
        ds,
        "fig2_amplitude",
        1e3,
        "amplitude of the spring force [mN]",
        r"Fig. 2: zv set-up, $\beta$ = 42 s/m, a = 160 s/m",
    )


def fig3_amplitude_v0(ds: xr.Dataset) -> Figure:
    """Fig. 3: amplitude (units of mu0 W) against v0 for a = 250 s/m, three betas."""
    fig, ax = subplots(figsize=(6.4, 4.0), layout="constrained")
    v = ds["fig3_v0"].values
    for i, beta in enumerate(ds["fig3_beta"].values):
        ax.plot(v, ds["fig3_amplitude_au"].values[i], lw=1.8, label=rf"$\beta$ = {beta:g} s/m")
    _v0_axis(ax, ds, "fig3_v0")
    ax.set_yscale("log")
    ax.set_ylabel(r"amplitude [units of $\mu_0 W$]")
    ax.set_title(f"Fig. 3: a = {ds.attrs.get('fig3_a', '')}, b = 0", fontsize=10)
    ax.legend(frameon=False)
    return fig


def period_v0(ds: xr.Dataset) -> Figure:
    """Period against v0 (zv set-up), b = 0 and b = 100 s/m."""
    return _fig2_curves(ds, "fig2_period", 1.0, "period [s]", "Period against driving velocity, zv set-up")


def load_dependence(ds: xr.Dataset) -> Figure:
    """Amplitude and period against the normal load, at three driving velocities."""
    fig, axes = subplots(1, 2, figsize=(10, 4.0), layout="constrained")
    w = ds["load_W"].values
    for j, v in enumerate(ds["load_v0"].values):
        label = pretty_units(f"$v_0$ = {v:g} {ds['load_v0'].attrs.get('units', '')}")
        axes[0].plot(w, ds["load_amplitude"].values[j] * 1e3, lw=1.8, label=label)
        axes[1].plot(w, ds["load_period"].values[j], lw=1.8, label=label)
    for ax, ylabel in zip(axes, ("amplitude [mN]", "period [s]"), strict=True):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(pretty_units(f"normal load W [{ds['load_W'].attrs.get('units', '')}]"))
        plain_log_ticks(ax.xaxis)
        ax.set_ylabel(ylabel)
        ax.legend(frameon=False, fontsize=8)
    # which law and mass: named in the title, not left to be inferred by matching the numbers
    zv = zv_parameters()
    fig.suptitle(
        f"Dependence on the normal load: the zv set-up otherwise (F1, a = {zv.law.params['a']:~P}, "
        f"m = {zv.mass.to('g'):.4g~P}, k = {zv.stiffness:~P}, mu0 = {zv.law.mu_s:g}; beta falls as 1/W)",
        fontsize=10,
    )
    return fig


def mass_dependence(ds: xr.Dataset) -> Figure:
    """Relative change of the amplitude against v0 for masses from 0.1 g to 1 kg, one panel per law.

    The change ``A(v0)/A(v0_min) - 1`` spans six orders of magnitude and changes sign (F2 at
    small masses): it is drawn with its sign on an asinh axis, logarithmic away from zero and
    smooth through it (falling curves below zero), solid where the amplitude rises and dashed
    where it falls. Its magnitude on a log axis drew the falling curves going up, as the
    rising ones; a symlog axis kinked every curve where it crossed the linear threshold.
    """
    v = ds["mass_v0"].values
    unit = ds["mass_mass"].attrs.get("units", "")
    amp = ds["mass_amplitude"].values  # (b, mass, v0)
    b_values = ds["mass_b"].values
    fig, axes = subplots(1, len(b_values), figsize=(11, 4.2), sharey=True, layout="constrained")
    changes = amp[:, :, 1:] / amp[:, :, :1] - 1.0
    small = np.abs(changes[np.isfinite(changes) & (changes != 0)])
    # the axis is linear below the smallest change, held to within 1e-6 of the largest (a change at
    # rounding, 2e-16, made the axis span 16 decades: the review)
    linear = 10.0 ** np.floor(np.log10(max(small.min(), 1e-6 * small.max()))) if small.size else 1e-6
    for ax, i in zip(np.atleast_1d(axes), range(len(b_values)), strict=True):
        for j, m in enumerate(ds["mass_mass"].values):
            change = changes[i, j]
            falling = np.median(change) < 0
            ax.plot(
                v[1:],
                change,
                ls="--" if falling else "-",
                color=f"C{j}",
                lw=1.8,
                label=f"m = {m:g} {unit}" + (" (falls)" if falling else ""),
            )
        ax.set_yscale("asinh", linear_width=linear)  # smooth through zero: symlog kinked at +-linear
        ax.axhline(0.0, color="0.6", lw=0.8)
        _v0_axis(ax, ds, "mass_v0")
        b = float(b_values[i])
        ax.set_title("F1 (b = 0)" if b == 0 else f"F2 (b = {b:g} s/m)", fontsize=10)
        # below the curves where all rise, about the zero line (clear of both kinds) where some fall
        some_fall = bool(np.any(np.median(changes[i], axis=-1) < 0))
        ax.legend(frameon=False, fontsize=8, loc="center right" if some_fall else "lower right")
    lowest = pretty_units(f"{v[0]:g} {ds['mass_v0'].attrs.get('units', '')}")
    np.atleast_1d(axes)[0].set_ylabel(f"amplitude / amplitude at {lowest} - 1 (asinh scale)")
    fig.suptitle(
        "Dependence on the mass (zv set-up otherwise): above 0 the amplitude rises with $v_0$, below it "
        "falls (dashed)",
        fontsize=10,
    )
    return fig


def appendix_phase_portraits(ds: xr.Dataset) -> Figure:
    """Phase portraits of the appendix's system for kappa above, below and at B - A."""
    fig, axes = subplots(1, 3, figsize=(12, 3.8), layout="constrained")
    b_minus_a = float(ds.attrs["appendix_B"]) - float(ds.attrs["appendix_A"])
    for ax, k in zip(axes, range(ds.sizes["kappa"]), strict=True):
        kappa = float(ds["kappa"].values[k])
        for j in range(ds.sizes["orbit"]):
            x, y = ds["portrait_alpha"].values[k, j], ds["portrait_phi"].values[k, j]
            ok = np.isfinite(x) & np.isfinite(y)
            x, y = x[ok], y[ok]
            (line,) = ax.plot(x, y, lw=0.8)
            if x.size < 3:
                continue
            # where each orbit starts, and which way it runs: the plot shows whether orbits spiral
            # in or out, not only the titles
            ax.plot(x[0], y[0], "o", ms=4, color=line.get_color())
            arrow = {"arrowstyle": "-|>", "color": line.get_color(), "lw": 0.8, "mutation_scale": 12}
            for m in (x.size // 8, (3 * x.size) // 4):  # early and late: a spiral in or out shows both
                ax.annotate("", xy=(x[m + 1], y[m + 1]), xytext=(x[m], y[m]), arrowprops=arrow)
        rel = "=" if abs(kappa - b_minus_a) < 1e-12 else (">" if kappa > b_minus_a else "<")
        ax.set_title(rf"$\kappa$ = {kappa:g} {rel} B - A", fontsize=10)
        ax.set_xlabel(r"$\alpha - \alpha^*$")
        ax.set_ylabel(r"$\phi$")
    fig.suptitle(
        "Quasi-static Rice-Ruina model (aging law), derived dimensionless system: each orbit from its dot, "
        "the arrow its direction",
        fontsize=10,
    )
    return fig


def appendix_critical_stiffness(ds: xr.Dataset) -> Figure:
    """Growth rate of small perturbations against k/k_c: simulation and linear theory."""
    fig, ax = subplots(figsize=(6.4, 4.0), layout="constrained")
    r = ds["stiffness_ratio"].values
    ax.plot(r, ds["growth_linear"].values, "k-", lw=1.2, label="linear theory")
    ax.plot(r, ds["growth_simulated"].values, "o", color="C3", label="simulated (peak envelope)")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.axvline(1, color="0.6", lw=0.8, ls=":")
    ax.set_xlabel(r"stiffness $k / k_c$, $k_c = (B - A) W / D_0$")
    ax.set_ylabel("growth rate [1/s]")
    ax.legend(frameon=False)
    ax.set_title("Critical stiffness: simulations against the linearisation", fontsize=10)
    return fig


def appendix_inertia(ds: xr.Dataset) -> Figure:
    """Inertia: the critical stiffness against the mass, and a limit cycle below it."""
    fig, axes = subplots(1, 2, figsize=(11, 4.0), layout="constrained")
    eps = ds["inertia_eps"].values
    axes[0].loglog(eps, ds["inertia_kc_ratio"].values - 1.0, "o-", ms=3)
    axes[0].set_xlabel(r"$m v_0^2 / (W A D_0)$")
    axes[0].set_ylabel(r"$k_c(m) / k_c(0) - 1$")
    axes[0].set_title("critical stiffness with inertia (linearised)", fontsize=10)
    axes[1].semilogy(ds["cycle_time"].values, ds["cycle_velocity"].values, lw=1.0)
    axes[1].axhline(
        float(ds.attrs["appendix_inertia_v0"]), color="0.5", ls=":", lw=0.8, label="load-point velocity"
    )
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("slip velocity [m/s]")
    axes[1].set_title("k = 0.8 k_c with inertia: a bounded stick-slip cycle", fontsize=10)
    axes[1].legend(frameon=False)
    return fig


FIGURES: dict[str, tuple[Callable[[xr.Dataset], Figure], str]] = {
    "fig1_spring_force": (
        fig1_spring_force,
        "Fig. 1: spring force against time, zv set-up (F1, beta = 42 s/m, 10 um/s); slip phases in "
        "red, one of them magnified in the inset.",
    ),
    "fig2_amplitude_v0": (
        fig2_amplitude_v0,
        "Fig. 2: amplitude against driving velocity, zv set-up, b = 0 (solid) and b = 100 s/m (dotted).",
    ),
    "fig3_amplitude_v0": (
        fig3_amplitude_v0,
        "Fig. 3: amplitude (units of mu0 W) against driving velocity, a = 250 s/m, b = 0, "
        "beta = 42, 158, 418 s/m.",
    ),
    "period_v0": (period_v0, "Period against driving velocity, zv set-up."),
    "load_dependence": (
        load_dependence,
        "Amplitude and period against the normal load at three driving velocities.",
    ),
    "mass_dependence": (
        mass_dependence,
        "Relative change of the amplitude against driving velocity for masses from 0.1 g to 1 kg, "
        "F1 and F2 (b = 100 s/m); dashed where the amplitude falls with v0.",
    ),
}


FIGURES.update(
    {
        "appendix_phase_portraits": (
            appendix_phase_portraits,
            "Appendix: phase portraits of the quasi-static "
            "Rice-Ruina model for kappa above (spiral in), below (spiral out, run "
            "away) and at B - A (closed orbits).",
        ),
        "appendix_critical_stiffness": (
            appendix_critical_stiffness,
            "Appendix: growth rate of small perturbations against stiffness, simulated and linearised.",
        ),
        "appendix_inertia": (
            appendix_inertia,
            "Beyond the appendix: the critical stiffness with inertia, "
            "and a bounded stick-slip cycle below it where the quasi-static slider runs away.",
        ),
    }
)


def make_figures(ds: xr.Dataset) -> dict[str, Figure]:
    """Draw every figure from the dataset (the appendix's only when its data are there)."""
    return {
        name: func(ds)
        for name, (func, _) in FIGURES.items()
        if not name.startswith("appendix") or "kappa" in ds.dims
    }


def render_trial_figures(path: str, key: str) -> dict[str, dict[str, bytes]]:
    """Draw the regime map and the criterion map of the trial saved at ``path``, as bytes.

    For a second process (``reproduce(parallel=True)``): the figures ``regimes_<key>``
    and ``criterion_<key>`` as the first process draws them from the same file.
    """
    from ..dynamics.sweep import load_sweep

    trial = load_sweep(path)
    return {f"{kind}_{key}": figure_bytes(plot(trial)) for kind, plot in TRIAL_PLOTS}


def render_figures(ds: xr.Dataset, names: list[str]) -> dict[str, dict[str, bytes]]:
    """Draw the figures ``names`` from the dataset and render each as PNG and SVG bytes.

    For a second process (``reproduce(parallel=True)``): the bytes are what
    :func:`~stickslip.plots.figures.save_figure` would write.
    """
    return {name: figure_bytes(FIGURES[name][0](ds)) for name in names}
