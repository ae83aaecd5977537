"""Commands of the bifurcation family: ``regimes`` (branches, intervals, regime maps)."""

from __future__ import annotations

from typing import Any

import click
import numpy as np

from ..io.jsonable import dumps as dumps_json
from ..models.parameters import PhysicalParameters
from ..units import VELOCITY_UNITS, readable_unit
from .errors import handle_errors
from .options import (
    OutPath,
    build_parameters,
    law_command,
    overwrite_option,
    parse_axis,
    scale_options,
    scale_report,
    warn_unwritten,
)

__all__ = ["regimes", "register"]


@law_command()
@click.option("--nu-min", type=float, default=0.01, show_default=True, help="Lower end of the nu range.")
@click.option("--nu-max", type=float, default=3.0, show_default=True, help="Upper end of the nu range.")
@click.option("--n", "n_grid", type=int, default=201, show_default=True, help="Grid points along nu.")
@click.option("--json", "as_json", is_flag=True, help="Print hopf, intervals, points and branches as JSON.")
@click.option(
    "--check", is_flag=True, help="Confirm every interval by direct simulation from several starts."
)
@click.option(
    "--map",
    "map_spec",
    default=None,
    metavar="NAME=A..B",
    help="Also a two-parameter regime map over a law parameter, e.g. 'p=0.05..1.5' (weakening: c, p; "
    "cubic: alpha, gamma; a formula: its parameters), with the criterion on trial.",
)
@click.option("--map-n", type=int, default=25, show_default=True, help="Values of the --map parameter.")
@click.option(
    "--out",
    "out_dir",
    type=OutPath(file_okay=False),
    default=None,
    help="Write regimes.json, bifurcation.png/.svg (and regime_map.nc, regime_map.png, "
    "criterion_map.png with --map) to this folder.",
)
@scale_options
@overwrite_option
@handle_errors
def regimes(
    nu_min: float,
    nu_max: float,
    n_grid: int,
    as_json: bool,
    check: bool,
    map_spec: str | None,
    map_n: int,
    out_dir: str | None,
    store: str | None,
    scheduler: str | None,
    workers: int | None,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Find every branch (steady sliding, pure slip, stick-slip) over a range of nu and the regimes.

    Hopf points and their criticality, pure-slip orbits continued by shooting
    (stable and unstable), folds, grazing, the onset of stick-slip, and the
    intervals where each attractor exists (bistable where two coexist, multistable where more). The law
    is given as for 'stickslip cycle', without --nu; a physical set-up gives its
    law in dimensionless form (beta from --mass or --beta) and the intervals also
    in v0.
    """
    from ..bifurcation.regimes import confirm
    from ..bifurcation.regimes import regimes as compute_regimes
    from ..io.jsonable import json_clean

    if map_spec is None and (store or scheduler or workers):
        raise click.UsageError("--store, --scheduler and --workers go with --map (the regime map)")
    if out_dir is None:
        warn_unwritten(("overwrite",), "without --out")

    if opts.get("nu") is not None:
        raise click.UsageError("--nu: 'regimes' scans nu; give --nu-min and --nu-max instead")
    ctx = click.get_current_context()
    given = [
        f"--{k}"
        for k in ("rtol", "atol", "v0")
        if ctx.get_parameter_source(k) is click.core.ParameterSource.COMMANDLINE
    ]
    if map_spec is None and ctx.get_parameter_source("map_n") is click.core.ParameterSource.COMMANDLINE:
        raise click.UsageError("--map-n goes with --map (the points of the mapped parameter)")
    unused = [g for g in given if g != "--v0"]
    if unused:  # they reached nothing: the continuation sets its own tolerances
        raise click.UsageError(f"{', '.join(unused)}: 'regimes' sets its own tolerances")
    if given:
        click.echo("warning: --v0 does nothing in 'regimes' (it scans nu; only beta is used)", err=True)
    physical = any(
        opts.get(k) is not None for k in ("v0", "mass", "beta", "stiffness", "load", "preset", "mu", "table")
    )
    if not physical:
        opts["nu"] = 1.0  # placeholder: only the law is used
    elif opts.get("v0") is None:
        opts["v0"] = "1 m/s"  # placeholder: only the law and beta are used
    try:
        params = build_parameters(opts)
    except click.UsageError as exc:
        # the mapped parameter need not be given as well (--map alpha=0.3..0.7 needs no --alpha):
        # the diagram is drawn at the map's first value, and says so
        name, _, rng = (map_spec or "").partition("=")
        key = name.strip().replace("-", "_")
        if not (key and opts.get(key, 0) is None and ".." in rng and f"needs --{name.strip()}" in str(exc)):
            raise
        opts[key] = rng.split("..", 1)[0].strip()
        click.echo(
            f"note: --{name.strip()} not given: the diagram is at {key} = {opts[key]}, the map's first value",
            err=True,  # stdout may be the JSON
        )
        params = build_parameters(opts)
    beta = None
    if isinstance(params, PhysicalParameters):
        beta = params.beta.to("s/m").magnitude
        law = params.dimensionless().law
    else:
        law = params.law
    d = compute_regimes(law, nu_min, nu_max, n_grid=n_grid)
    result = d.as_dict()
    if beta is not None:
        result["beta_s_per_m"] = beta
        for iv in result["intervals"]:
            iv["v0_min_m_per_s"] = iv["nu_min"] / beta
            iv["v0_max_m_per_s"] = iv["nu_max"] / beta
    checks = confirm(d) if check else []
    if check:
        result["check"] = [
            {
                "regime": c.interval.regime,
                "nu": c.nu,
                "expected": list(c.expected),
                "found": list(c.found),
                "pure_slip_amplitude_error": c.pure_slip_amplitude_error,
                "agree": c.agree,
            }
            for c in checks
        ]
    trial = None
    if map_spec is not None:
        from ..bifurcation.regime_map import criterion_table, criterion_trial, regime_map

        name, sep, rng = map_spec.partition("=")
        name = name.strip()
        if not sep:
            raise click.UsageError(f"--map={map_spec!r}: expected NAME=A..B, e.g. 'p=0.05..1.5'")
        try:
            p = law.spec.parameter(name)
        except KeyError:
            raise click.UsageError(
                f"--map: param={name!r} is not a parameter of the {law.name} law "
                f"(it has {', '.join(law.params)})"
            ) from None
        if ".." not in rng:  # one value would make a map of one row: refused
            raise click.UsageError(f"--map={map_spec!r}: expected a range NAME=A..B, e.g. 'p=0.05..1.5'")
        if map_n < 2:
            raise click.UsageError(f"--map-n={map_n}: a map needs at least 2 values")
        try:
            values = [float(v) for v in parse_axis(p, name, rng.strip(), map_n, False)]
        except ValueError as exc:
            raise click.UsageError(f"--map: {exc}") from None
        if not values[0] < values[-1]:  # reversed, or one value repeated
            raise click.UsageError(f"--map={map_spec!r}: expected A < B (a range from low to high)")
        ds = regime_map(
            law,
            name,
            values,
            nu_min,
            nu_max,
            n_nu=n_grid,
            store=store,
            scheduler=scheduler,
            workers=workers,
        )
        if store is not None:
            scale_report(ds)
            del ds.attrs["run"]
        trial = criterion_trial(ds)
        if beta is not None:  # the map of a physical set-up says which: v0 = nu / beta
            trial.attrs["beta_s_per_m"] = beta
        result["criterion"] = criterion_table(trial)
    result = json_clean(result)  # NaN (no pure-slip attractor, no criterion verdict) -> null
    if out_dir is not None:
        from ..io.netcdf import save_dataset
        from ..io.output import OutputFolder, json_writer
        from ..plots.figures import save_figure
        from ..plots.regimes import plot_bifurcation, plot_criterion_map, plot_regime_map

        with OutputFolder(out_dir, "regimes", overwrite=overwrite) as out:
            out.write("regimes.json", "regimes", json_writer(result, "regimes"))
            save_figure(plot_bifurcation(d, beta=beta), "bifurcation", out=out)
            if trial is not None:
                save_dataset(trial, "regime_map.nc", kind="regime-map", out=out)
                save_figure(plot_regime_map(trial), "regime_map", out=out)
                save_figure(plot_criterion_map(trial), "criterion_map", out=out)
    if as_json:
        click.echo(dumps_json(result, indent=2))
    else:
        _print_regimes(d, result, checks, trial, beta, out_dir)
    if checks and not all(c.agree for c in checks):
        click.echo("stickslip: some intervals were not confirmed by direct simulation", err=True)
        raise SystemExit(1)


def _print_regimes(
    d: Any, result: dict[str, Any], checks: list[Any], trial: Any, beta: float | None, out_dir: str | None
) -> None:
    """Print the diagram as text: Hopf points, special points, intervals, checks, the criterion."""
    # velocities in a unit that suits them (100 um/s, not 0.0001 m/s; the JSON stays SI)
    unit, size = readable_unit([nu / beta for nu in (d.nu_min, d.nu_max)] if beta else [], VELOCITY_UNITS)
    for h in d.hopf:
        why = f"l1 = {h.l1:.4g}" if not h.kink else f"on a row: f'' jumps by {h.kink:+.4g}"
        at = _at_v0(h.nu, beta, size, unit)
        click.echo(f"Hopf point      nu = {h.nu:.10g}{at}  {h.criticality} ({why})")
    for pt in d.points:
        if pt.kind == "hopf":
            continue
        what = f"amplitude {pt.amplitude:.6g}" if np.isfinite(pt.amplitude) else pt.detail
        click.echo(f"{pt.kind:<15} nu = {pt.nu:.10g}{_at_v0(pt.nu, beta, size, unit)}  {what}")
    for iv in d.intervals:
        v0 = f"   v0 {iv.nu_min / beta / size:.4g} .. {iv.nu_max / beta / size:.4g} {unit}" if beta else ""
        att = " + ".join(iv.attractors) if len(iv.attractors) > 1 else ""
        click.echo(f"{iv.regime:<15} nu {iv.nu_min:.8g} .. {iv.nu_max:.8g}{v0}  {att}".rstrip())
    for c in checks:
        mark = "confirmed" if c.agree else "NOT CONFIRMED"
        click.echo(
            f"check at nu = {c.nu:.6g}: expected {', '.join(c.expected)}; "
            f"simulations reached {', '.join(c.found)}: {mark}"
        )
    if trial is not None:
        for row in result["criterion"]:
            click.echo(f"criterion on {row['regime']}: right at {row['right']} of {row['judged']} points")
    if out_dir is not None:
        click.echo(f"wrote {out_dir}/regimes.json and figures")


def _at_v0(nu: float, beta: float | None, size: float, unit: str) -> str:
    """Return `` (v0 = ...)`` for a driving velocity ``nu`` of a physical set-up (empty without beta)."""
    return f" (v0 = {nu / beta / size:.6g} {unit})" if beta else ""


def register(main: click.Group) -> None:
    """Add ``regimes`` (a module-level click command) to ``main``."""
    main.add_command(regimes)
