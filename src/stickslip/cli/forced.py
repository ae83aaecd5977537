"""The ``forced`` command: the harmonically forced friction oscillator."""

from __future__ import annotations

import math
from typing import Any

import click

from ..io.jsonable import dumps as dumps_json
from .errors import handle_errors
from .options import OutPath, build_parameters, law_command, overwrite_option, scale_options, warn_unwritten

__all__ = ["forced", "register"]

_MODES = ("trajectory", "section", "response", "diagram", "lyapunov")
_PHYSICAL = ("mass", "beta", "stiffness", "load", "preset", "mu", "v0")


def _range(text: str | None, physical: bool, default: tuple[str, float, float]) -> tuple[str, float, float]:
    """Parse ``NAME=A..B`` as the diagram command's axes (``frequency=1..5`` in Hz, physical set-ups)."""
    from .diagram import _axis

    axis = _axis(text, "--range")
    if axis is None:
        return default
    name, (lo, hi) = axis
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise click.UsageError(f"--range={text!r}: expected finite A < B")
    if name == "frequency" and not physical:
        raise click.UsageError("--range frequency=A..B (Hz) needs --mass, --stiffness, --load")
    return name, lo, hi


def _system(opts: dict[str, Any], forcing: dict[str, Any]) -> tuple[Any, bool]:
    """Return the forced system of the options, and whether it is physical."""
    from ..forced import ForcedSystem, PhysicalForcedSystem

    system: ForcedSystem | PhysicalForcedSystem
    from ..models.parameters import PhysicalParameters

    physical = any(opts.get(k) is not None for k in _PHYSICAL) or any(
        forcing[k] is not None for k in ("frequency", "force", "damping", "drive_amplitude", "base_amplitude")
    )
    nu0 = opts.get("nu")
    if physical:
        v0 = opts.get("v0")
        opts = {**opts, "v0": v0 or "1 um/s"}
        params = build_parameters(opts)
        if not isinstance(params, PhysicalParameters):
            raise click.UsageError(
                "a physical forcing (--frequency, --force, ...) needs --mass, --stiffness, --load"
            )
        if forcing["frequency"] is None:
            raise click.UsageError("--frequency: give the forcing frequency, e.g. '2 Hz'")
        for k in ("omega", "q", "nu1", "delta"):
            if forcing[k] is not None:
                raise click.UsageError(
                    f"--{k} is dimensionless: with a physical set-up give --frequency, --force, "
                    "--drive-amplitude or --base-amplitude, --damping"
                )
        system = PhysicalForcedSystem(
            mass=params.mass,
            stiffness=params.stiffness,
            load=params.load,
            law=params.law,
            frequency=forcing["frequency"],
            force=forcing["force"] or "0 N",
            v0=v0 or "0 m/s",
            drive_amplitude=forcing["drive_amplitude"],
            base_amplitude=forcing["base_amplitude"],
            phase=forcing["phase"],
            damping=forcing["damping"] or "0 N*s/m",
        )
        return system, True
    for k in ("frequency", "force", "damping", "drive_amplitude", "base_amplitude"):
        if forcing[k] is not None:
            raise click.UsageError(
                f"--{k.replace('_', '-')} needs a physical set-up (--mass, --stiffness, --load)"
            )
    if forcing["omega"] is None:
        raise click.UsageError("--omega: give the forcing frequency Omega sqrt(m/k), e.g. --omega 1.2")
    params = build_parameters({**opts, "nu": nu0 if nu0 else 1.0})
    phase = forcing["phase"]
    try:
        phi = float(phase)
    except ValueError:
        raise click.UsageError(
            f"--phase={phase!r}: expected a number of rad (dimensionless set-up)"
        ) from None
    if isinstance(params, PhysicalParameters):
        raise click.UsageError("a physical set-up needs --frequency (the forcing in physical units)")
    system = ForcedSystem(
        params.law,
        omega=forcing["omega"],
        q=forcing["q"] or 0.0,
        nu0=nu0 or 0.0,
        nu1=forcing["nu1"] or 0.0,
        phi=phi,
        delta=forcing["delta"] or 0.0,
    )
    return system, False


def _start(text: str) -> tuple[float, float]:
    try:
        s, w = (float(v) for v in text.split(","))
    except ValueError:
        raise click.UsageError(
            f"--start={text!r}: expected 'S,W' (spring force and velocity, dimensionless)"
        ) from None
    return s, w


@law_command(name="forced")
@click.option(
    "--mode",
    type=click.Choice(_MODES),
    default="trajectory",
    show_default=True,
    help="What to compute: a trajectory, a Poincaré section, a response curve (periodic orbits "
    "continued, with their bifurcations), a bifurcation diagram, the Lyapunov exponents.",
)
@click.option("--omega", type=float, default=None, help="Forcing frequency Omega sqrt(m/k) (dimensionless).")
@click.option("--q", type=float, default=None, help="Force amplitude F0/(mu_s W) (dimensionless).")
@click.option("--nu1", type=float, default=None, help="Drive velocity amplitude beta V1 (dimensionless).")
@click.option("--delta", type=float, default=None, help="Viscous damping c/sqrt(k m) (dimensionless).")
@click.option("--frequency", default=None, help="Forcing frequency, e.g. '2 Hz' or '12 rad/s' (physical).")
@click.option("--force", default=None, help="Force amplitude F0, e.g. '0.5 N' (physical).")
@click.option("--drive-amplitude", default=None, help="Drive velocity amplitude V1, e.g. '5 mm/s'.")
@click.option("--base-amplitude", default=None, help="Support displacement amplitude Y, e.g. '1 mm'.")
@click.option("--damping", default=None, help="Viscous damping c, e.g. '0.5 N*s/m' (physical).")
@click.option(
    "--phase", default="0", show_default=True, help="Phase of the drive modulation (rad, or '90 deg')."
)
@click.option(
    "--range",
    "range_",
    default=None,
    metavar="NAME=A..B",
    help="Response curve / diagram: the parameter and its range ('omega=0.5..2.5', 'q=0.1..2', "
    "'frequency=1..5' in Hz for a physical set-up).",
)
@click.option(
    "--values",
    "n_values",
    type=click.IntRange(2, 10**6),
    default=400,
    show_default=True,
    help="Diagram: parameter values.",
)
@click.option(
    "--periods",
    type=click.FloatRange(min=1e-3, max=1e6),
    default=20.0,
    show_default=True,
    help="Trajectory: forcing periods shown; section and Lyapunov: periods recorded.",
)
@click.option(
    "--transient",
    type=click.IntRange(0, 10**7),
    default=500,
    show_default=True,
    help="Periods run before recording.",
)
@click.option(
    "--record",
    type=click.IntRange(1, 10**6),
    default=200,
    show_default=True,
    help="Diagram: sections recorded per value.",
)
@click.option(
    "--period",
    "resp_period",
    type=click.IntRange(1, 64),
    default=1,
    show_default=True,
    help="Response: forcing periods per response period.",
)
@click.option(
    "--lyapunov", "with_lyapunov", is_flag=True, help="Diagram: the largest Lyapunov exponent per value."
)
@click.option(
    "--backend",
    type=click.Choice(["cpu", "cuda", "auto"]),
    default="cpu",
    show_default=True,
    help="Diagram: numba's threads, a CUDA GPU (a thread per value), or the GPU where one is usable.",
)
@click.option("--start", default="0,0", show_default=True, help="Start state 'S,W' at the first section.")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option(
    "--out",
    "out_dir",
    type=OutPath(file_okay=False),
    default=None,
    help="Write the result as NetCDF (and JSON) and its figure (.png/.svg).",
)
@scale_options
@overwrite_option
@handle_errors
def forced(
    mode: str,
    omega: float | None,
    q: float | None,
    nu1: float | None,
    delta: float | None,
    frequency: str | None,
    force: str | None,
    drive_amplitude: str | None,
    base_amplitude: str | None,
    damping: str | None,
    phase: str,
    range_: str | None,
    n_values: int,
    periods: float,
    transient: int,
    record: int,
    resp_period: int,
    with_lyapunov: bool,
    backend: str,
    start: str,
    as_json: bool,
    out_dir: str | None,
    store: str | None,
    scheduler: str | None,
    workers: int | None,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Run the forced oscillator: harmonic drive, support displacement or force, with exact stick.

    The law is given as for 'stickslip cycle'; --nu is the mean drive (0: the spring's far
    end is fixed, Den Hartog's oscillator). Dimensionless forcing: --omega, --q, --nu1,
    --delta; physical: --frequency, --force, --drive-amplitude or --base-amplitude,
    --damping with --mass, --stiffness, --load. Response curves and diagrams are in the
    dimensionless parameters (a frequency range in Hz is converted).
    """
    from ..forced import lyapunov, lyapunov_two_trajectories, poincare_section, response_curve, trajectory
    from ..forced.diagram import bifurcation_diagram

    if out_dir is None:
        warn_unwritten(("overwrite",), "without --out")
    if mode != "diagram" and (store or scheduler or workers or backend != "cpu"):
        raise click.UsageError("--store, --scheduler, --workers and --backend go with --mode diagram")
    forcing = {
        "omega": omega,
        "q": q,
        "nu1": nu1,
        "delta": delta,
        "frequency": frequency,
        "force": force,
        "drive_amplitude": drive_amplitude,
        "base_amplitude": base_amplitude,
        "damping": damping,
        "phase": phase,
    }
    if opts.get("nu") is not None and opts["nu"] < 0:
        raise click.UsageError(f"--nu={opts['nu']}: the mean drive must be >= 0")
    system, physical = _system(opts, forcing)
    dp = system.dimensionless() if physical else system
    s0w0 = _start(start)
    result: dict[str, Any] = {"system": dp.describe(), "mode": mode}
    figure = None
    dataset = None
    lines: list[str] = []
    if mode == "trajectory":
        tr = trajectory(system, periods, start=s0w0, transient=transient)
        st = tr.stats
        result.update(
            stops=st.stops, reversals=st.reversals, stick_time=st.stick_time, s_min=st.s_min, s_max=st.s_max
        )
        unit = "N" if physical else "mu_s W"
        lines.append(
            f"{dp.describe()}: {periods:g} periods after {transient}: {st.stops} stops, "
            f"{st.reversals} reversals, spring force {tr.s.min():.6g}..{tr.s.max():.6g} {unit}"
        )
        dataset = tr.to_dataset()
        if out_dir is not None:
            from ..plots.forced import plot_forced_trajectory

            figure = plot_forced_trajectory(tr)
    elif mode == "section":
        sec = poincare_section(system, max(1, round(periods)), transient=transient, start=s0w0)
        distinct = len({(round(a, 7), round(b, 7)) for a, b in zip(sec.s, sec.w, strict=True)})
        result.update(
            points=int(sec.s.size),
            distinct=distinct,
            stops_per_period=sec.stops_per_period,
            stick_fraction=sec.stick_fraction,
        )
        lines.append(
            f"{dp.describe()}: {sec.s.size} sections, {distinct} distinct (to 1e-7); "
            f"{sec.stops_per_period:.4g} stops per period, stuck {100 * sec.stick_fraction:.3g} % of the time"
        )
        import xarray as xr

        dataset = xr.Dataset(
            {"s": ("section", sec.s), "w": ("section", sec.w)}, attrs={"system": dp.describe()}
        )
        if out_dir is not None:
            from ..plots.forced import plot_section

            figure = plot_section(sec)
    elif mode == "lyapunov":
        n = max(1, round(periods))
        ly = lyapunov(system, n, transient=transient, start=s0w0)
        two = lyapunov_two_trajectories(system, n, transient=transient, start=s0w0)
        unit = "1/s" if physical else "per sqrt(m/k)"
        result.update(
            exponents=[float(v) for v in ly.exponents],
            running=[float(v) for v in ly.running],
            two_trajectories=two,
            chaotic=ly.chaotic,
            unit=unit,
        )
        lines.append(
            f"{dp.describe()}: Lyapunov exponents {ly.exponents[0]:.6g}, {ly.exponents[1]:.6g} {unit} "
            f"over {n} periods (saltation matrices); two nearby trajectories: {two:.6g}; "
            f"{'chaotic' if ly.chaotic else 'not chaotic'}"
        )
    else:
        name, lo, hi = _range(range_, physical, ("omega", 0.5 * dp.omega, 2.0 * dp.omega))
        if name == "frequency":
            scale = math.sqrt(system.mass.to("kg").magnitude / system.stiffness.to("N/m").magnitude)
            name, lo, hi = "omega", 2 * math.pi * lo * scale, 2 * math.pi * hi * scale
        if mode == "response":
            value = getattr(dp, name) if hasattr(dp, name) else dp.law.params.get(name, lo)
            base = dp if lo <= value <= hi else dp.with_(**{name: lo})
            rc = response_curve(base, name, (lo, hi), period=resp_period, start=s0w0, transient=transient)
            result["bifurcations"] = [
                {"kind": b.kind, "value": b.value, "detail": b.detail} for b in rc.bifurcations
            ]
            result["points"] = len(rc.values)
            lines.append(
                f"{dp.describe()}: period-{rc.period} response over {name} {rc.values.min():.6g}.."
                f"{rc.values.max():.6g}, {len(rc.values)} points; ends: {rc.ends[0]}, {rc.ends[1]}"
            )
            lines += [f"{b.kind:<16} {name} = {b.value:.10g}: {b.detail}" for b in rc.bifurcations]
            dataset = rc.to_dataset()
            if out_dir is not None:
                from ..plots.forced import plot_response

                figure = plot_response(rc)
        else:
            import numpy as np

            values = np.linspace(lo, hi, n_values)
            ds = bifurcation_diagram(
                dp,
                values,
                parameter=name,
                transient=transient,
                record=record,
                start=s0w0,
                lyapunov=with_lyapunov,
                backend=backend,
                store=store,
                scheduler=scheduler,
                workers=workers,
            )
            per_value = [len(np.unique(np.round(r[np.isfinite(r)], 6))) for r in np.asarray(ds["s"].values)]
            result.update(values=n_values, parameter=name, distinct_per_value=per_value)
            if with_lyapunov:
                result["lyapunov"] = [float(v) for v in ds["lyapunov"].values]
            lines.append(
                f"{dp.describe()}: bifurcation diagram over {name} {lo:.6g}..{hi:.6g}, {n_values} values x "
                f"{record} sections after {transient} periods"
            )
            lines.append(
                f"periodic (1 point per value): {sum(d == 1 for d in per_value)}; "
                f"period 2-16: {sum(1 < d <= 16 for d in per_value)}; more: {sum(d > 16 for d in per_value)}"
            )
            if with_lyapunov:
                lyap = np.asarray(ds["lyapunov"].values)
                lines.append(
                    f"positive largest Lyapunov exponent at {int(np.sum(lyap > 0))} of {n_values} values"
                )
            dataset = ds
            if out_dir is not None:
                from ..plots.forced import plot_bifurcation

                figure = plot_bifurcation(ds)
    if out_dir is not None:
        from ..io.netcdf import save_dataset
        from ..io.output import OutputFolder, json_writer
        from ..plots.figures import save_figure

        with OutputFolder(out_dir, "forced", overwrite=overwrite) as out:
            if dataset is not None:
                save_dataset(dataset, f"{mode}.nc", kind="forced", out=out)
            out.write(f"{mode}.json", "forced", json_writer(result, "forced"))
            if figure is not None:
                save_figure(figure, mode, out=out)
    if as_json:
        click.echo(dumps_json(result, indent=2))
        return
    for line in lines:
        click.echo(line)
    if out_dir is not None:
        click.echo(
            f"wrote {out_dir}/{mode}.json"
            + (f", {mode}.nc" if dataset is not None else "")
            + (f" and {mode}.png/.svg" if figure is not None else "")
        )


def register(main: click.Group) -> None:
    """Add ``forced`` to ``main``."""
    main.add_command(forced)
