"""Commands of the dynamics family: ``cycle``, ``simulate``, ``sweep``."""

from __future__ import annotations

import os
from typing import Any

import click
import numpy as np

from ..io.jsonable import dumps as dumps_json
from ..models.parameters import DimensionlessParameters, PhysicalParameters
from .errors import fail_unless_ok, handle_errors
from .options import (
    OutPath,
    axis_count,
    axis_parameter,
    build_parameters,
    default_out,
    describe_parameters,
    figure_names,
    is_axis,
    law_command,
    out_dir_option,
    overwrite_option,
    parse_axis,
    scale_options,
    scale_report,
)

__all__ = ["cycle", "register", "simulate", "sweep"]


@law_command()
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--no-probe", is_flag=True, help="Do not look for a second attractor.")
@handle_errors
def cycle(as_json: bool, no_probe: bool, **opts: Any) -> None:
    """Compute the steady oscillation: regime, amplitude, period, stick fraction.

    Dimensionless input gives dimensionless output (force in units of the static
    friction force, time in units of sqrt(m/k)); physical input gives N and s.
    """
    from ..dynamics.cycle import cycle as compute_cycle

    params = build_parameters(opts)
    res = compute_cycle(params, rtol=opts["rtol"], atol=opts["atol"], probe=not no_probe)
    if as_json:
        d = res.as_dict()
        d["parameters"] = describe_parameters(params)
        click.echo(dumps_json(d, indent=2))
        fail_unless_ok(res.status)
        return
    u = res.units
    reversal = (
        "  (it slips backward without sticking: not the paper's pure slip)"
        if str(res.regime) == "slip-reversal"
        else ""
    )
    multi = "  (multistable)" if res.multistable else ""
    click.echo(f"regime          {res.regime}{reversal}{multi}")
    click.echo(f"amplitude       {res.amplitude:.6g} [{u['force']}]")
    click.echo(f"period          {res.period:.6g} [{u['time']}]")
    click.echo(f"stick fraction  {res.stick_fraction:.6g}")
    click.echo(f"slip distance   {res.slip_distance:.6g} [{u['length']}]")
    click.echo(f"peak velocity   {res.peak_velocity:.6g} [{u['velocity']}]")
    click.echo(f"backward slips  {res.backward_slips}")
    click.echo(f"status          {res.status}")
    for a in res.attractors:
        click.echo(f"attractor       {a.regime} from {a.start}: amplitude {a.amplitude:.6g} ({a.status})")
    fail_unless_ok(res.status)


@law_command()
@click.option(
    "--duration",
    default=None,
    help="Simulated time: with units for physical input ('600 s'), a number otherwise. "
    "Default: from rest to the end of --cycles steady cycles.",
)
@click.option(
    "--cycles",
    type=float,
    default=3.0,
    show_default=True,
    help="Steady cycles to simulate when --duration is not given.",
)
@click.option(
    "--points", type=int, default=4000, show_default=True, help="Uniform samples (event times are added)."
)
@out_dir_option("Output folder for trajectory.csv and spring_force.png/.svg.")
@click.option("--no-plot", is_flag=True, help="Write the CSV only.")
@overwrite_option
@handle_errors
def simulate(
    duration: str | None,
    cycles: float,
    points: int,
    out_dir: str,
    no_plot: bool,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Simulate the motion; write a CSV time series and plot spring force against time.

    With no parameters this is the paper's zv set-up at 10 um/s (its Fig. 1).
    """
    from ..dynamics.cycle import cycle as compute_cycle
    from ..dynamics.trajectory import simulate as run
    from ..io.output import OutputFolder

    given = click.get_current_context().get_parameter_source("cycles")
    if duration is not None and given is click.core.ParameterSource.COMMANDLINE:
        raise click.UsageError("give --duration or --cycles, not both")
    params = build_parameters(opts, default_preset=True)
    dur: Any = duration
    if duration is not None and isinstance(params, DimensionlessParameters):
        try:
            dur = float(duration)
        except ValueError:
            raise click.UsageError(
                f"invalid value: duration={duration!r}: expected a number for dimensionless input"
            ) from None
    with OutputFolder(out_dir, "simulate", overwrite=overwrite) as out:
        out.expect({"trajectory.csv": "trajectory"} | ({} if no_plot else figure_names("spring_force")))
        traj = run(
            params,
            duration=dur,
            cycles=None if dur is not None else cycles,
            n_points=points,
            rtol=opts["rtol"],
            atol=opts["atol"],
        )
        written = [traj.to_csv("trajectory.csv", out=out)]
        if not no_plot:
            from ..plots.figures import plot_spring_force, save_figure

            title = None
            if isinstance(params, PhysicalParameters):
                title = f"v0 = {params.v0:~P}, beta = {params.beta.to('s/m').magnitude:.3g} s/m"
            written += save_figure(plot_spring_force(traj, title=title), "spring_force", out=out)
    click.echo(f"wrote {written[0]} ({traj.time.size} samples)")
    if len(written) > 1:
        click.echo("wrote " + ", ".join(written[1:]))
    # the stick from a start at rest counts too (four stick phases, not three, in 3 cycles)
    n_stops = sum(1 for k in traj.event_kind if k == "stick") + int(traj.phase[0] == 0)
    click.echo(f"{n_stops} stick phases simulated")
    # the steady oscillation, solved (not read off samples): polished into its periodic orbit
    res = compute_cycle(params, rtol=opts["rtol"], atol=opts["atol"], probe=False)
    u = res.units
    click.echo(
        f"steady cycle: {res.regime}, amplitude {res.amplitude:.6g} [{u['force']}], "
        f"period {res.period:.6g} [{u['time']}], Floquet multiplier {res.multiplier:.6g} ({res.status})"
    )


@law_command(text=True)
@click.option("--num", type=int, default=30, show_default=True, help="Points per range 'A..B'.")
@click.option("--log", "log_spacing", is_flag=True, help="Space the points of ranges logarithmically.")
@click.option(
    "--out",
    "out_path",
    type=OutPath(dir_okay=False),
    default=None,
    help="NetCDF output (.nc), or a table (.csv: one row per point, units in the column "
    "names); the plot goes beside it (.png, .svg). Default results/sweep/sweep.nc, "
    "or none with --store (the store is the output).",
)
@click.option("--no-plot", is_flag=True, help="Write the NetCDF file only.")
@click.option("--quiet", is_flag=True, help="No progress bar.")
@click.option(
    "--block-points",
    type=click.IntRange(min=1),
    default=None,
    help="Points per block (one task, one chunk of the store); default 32768, 1048576 with --backend cuda.",
)
@click.option(
    "--backend",
    type=click.Choice(["cpu", "cuda", "auto"]),
    default="cpu",
    show_default=True,
    help="Integrate on this machine's cores, on a CUDA GPU (pip install 'stickslip[cuda]'), "
    "or on the GPU where one is usable.",
)
@scale_options
@overwrite_option
@handle_errors
def sweep(
    num: int,
    log_spacing: bool,
    out_path: str | None,
    no_plot: bool,
    quiet: bool,
    block_points: int | None,
    backend: str,
    store: str | None,
    scheduler: str | None,
    workers: int | None,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Sweep parameters over ranges ('A..B') or lists ('A,B,C'); write NetCDF and a plot.

    Any parameter of the set-up or the law can be swept (a formula's with --param
    'c=1..10'); the others are fixed as in 'stickslip cycle'. --store streams the
    result to a Zarr store, resumably; --workers/--scheduler run it on Dask.
    Example: stickslip sweep --preset zv --v0 "5 um/s..1000 um/s" --num 60 --log
    """
    from ..dynamics.sweep import check_sweep_size, load_sweep
    from ..dynamics.sweep import sweep as run_sweep
    from ..io.netcdf import save_dataset
    from ..io.output import OutputFolder
    from ..plots.figures import plot_sweep, save_figure
    from .options import params_of, warn_unwritten

    if num < 2:
        raise click.UsageError(f"invalid value: --num={num}: expected at least 2 points per range")
    skip = {"law", "preset", "f", "mu", "table", "interpolation", "param", "rtol", "atol"}
    ranged = {k: v for k, v in opts.items() if k not in skip and is_axis(v)}
    ranged.update({k: v for k, v in params_of(opts).items() if is_axis(v)})
    # the grid's size from the options, before any axis is built
    sizes = [axis_count(v, num) for v in ranged.values()]
    if store is None:  # a store streams: no grid in memory
        check_sweep_size(int(np.prod(sizes, dtype=np.float64)) if sizes else 0, "this sweep")
    if not ranged:
        raise click.UsageError(
            "nothing to sweep: give a range such as --v0 '5 um/s..1000 um/s' "
            "or a list such as --b '0 s/m,100 s/m'"
        )
    source = click.get_current_context().get_parameter_source("num")
    num_given = source is click.core.ParameterSource.COMMANDLINE
    if (num_given or log_spacing) and not any(".." in str(v) for v in ranged.values()):
        click.echo("warning: --num and --log space ranges 'A..B'; the axes here are lists", err=True)
    # each axis parsed once; its first value fixes the base set-up
    user = params_of(opts)
    grid: dict[str, Any] = {}
    for key, val in ranged.items():
        grid[key] = parse_axis(axis_parameter(key, val), key, val, num, log_spacing)
    fixed = dict(opts)
    fixed["param"] = tuple((k, grid[k][0] if k in grid else v) for k, v in user.items())
    for key in grid:
        if key not in user:
            fixed[key] = grid[key][0]
    params = build_parameters(fixed)
    if opts.get("beta") is not None and "beta" not in grid and isinstance(params, PhysicalParameters):
        # a fixed beta must hold at every point: a one-value axis, so that the mass follows the
        # swept load, stiffness or friction coefficient
        grid["beta"] = [opts["beta"]]
    kw: dict[str, Any] = dict(
        rtol=float(opts["rtol"]),
        atol=float(opts["atol"]),
        progress=False if quiet else None,
        store=store,
        scheduler=scheduler,
        workers=workers,
        block_points=block_points,
        backend=backend,
    )
    if store is not None and out_path is None:
        warn_unwritten(
            ("no_plot", "overwrite"), "with --store alone (the store is the output; add --out for files)"
        )
        ds = run_sweep(params, grid, **kw)
        scale_report(ds)
        _regime_counts(ds)
        return
    out_path = out_path or os.path.join(default_out("sweep"), "sweep.nc")
    folder, name = os.path.split(out_path)
    stem, ext = os.path.splitext(name)
    if ext.lower() not in (".nc", ".nc4", ".cdf", ".netcdf", ".csv"):  # p.xyz: refused, not NetCDF unsaid
        raise click.BadParameter(
            f"{out_path!r}: expected a .nc (NetCDF; or .nc4, .cdf, .netcdf) or .csv file name",
            param_hint="--out",
        )
    with OutputFolder(folder or ".", f"sweep {stem}", overwrite=overwrite) as out:
        # the outputs are checked before the (possibly long) sweep starts
        out.expect({name: "sweep"} | ({} if no_plot else figure_names(stem)))
        ds = run_sweep(params, grid, **kw)
        if store is not None:
            scale_report(ds)
            ds = load_sweep(store)
        written = save_dataset(ds, name, out=out)
        paths = [] if no_plot else save_figure(plot_sweep(ds, log=log_spacing), stem, out=out)
    click.echo(f"wrote {written} ({ds.amplitude.size} points, dimensions {dict(ds.sizes)})")
    if paths:
        click.echo("wrote " + ", ".join(paths))
    _regime_counts(ds)


def _regime_counts(ds: Any) -> None:
    """Print how many points reached each regime (counted block by block: a store may be large)."""
    from ..core.results import Regime

    codes: dict[str, int] = {}
    values = ds.regime
    step = max(1, values.shape[0] // 64) if values.ndim else 1
    for lo in range(0, values.shape[0] if values.ndim else 1, step):
        part = np.asarray(values[lo : lo + step].values if values.ndim else values.values)
        for k, v in zip(*np.unique(part, return_counts=True), strict=True):
            label = str(Regime.from_code(k)) if part.dtype.kind in "iu" else str(k)
            codes[label] = codes.get(label, 0) + int(v)
    click.echo(f"regimes: {dict(sorted(codes.items()))}")


def register(main: click.Group) -> None:
    """Add the family's commands (module-level click commands) to ``main``, in this order."""
    main.add_command(cycle)
    main.add_command(simulate)
    main.add_command(sweep)
