"""The ``diagram`` command: a two-parameter bifurcation diagram, its checks, and a lab's plane."""

from __future__ import annotations

import warnings
from typing import Any

import click

from ..io.jsonable import dumps as dumps_json
from ..models.parameters import PhysicalParameters
from .errors import handle_errors
from .options import (
    OutPath,
    build_parameters,
    law_command,
    overwrite_option,
    params_of,
    scale_options,
    warn_unwritten,
)

__all__ = ["diagram", "register"]


def _axis(text: str | None, option: str) -> tuple[str, tuple[float, float]] | None:
    """Parse ``NAME=A..B`` (numbers in the axis' unit, or with a unit after B: ``v0=10..1e4 um/s``)."""
    if text is None:
        return None
    name, sep, rng = text.partition("=")
    parts = rng.split("..")
    if not sep or len(parts) != 2 or not all(p.strip() for p in parts):
        raise click.UsageError(f"{option}={text!r}: expected NAME=A..B, e.g. 'nu=0.05..2' or 'v0=10..1e4'")
    name = name.strip()
    lo_t, hi_t = parts[0].strip(), parts[1].strip()
    unit = ""
    bits = hi_t.split(None, 1)
    if len(bits) == 2:
        hi_t, unit = bits
    try:
        lo, hi = float(lo_t), float(hi_t)
    except ValueError:
        raise click.UsageError(f"{option}={text!r}: A and B must be numbers (a unit may follow B)") from None
    if not lo < hi:  # nan fails this too
        raise click.UsageError(f"{option}={text!r}: expected A < B, a range from low to high")
    if unit:
        from ..bifurcation.planes import SHOWN
        from ..units import Q_

        shown = SHOWN.get(name, ("",))[0]
        if not shown:
            raise click.UsageError(f"{option}={text!r}: give {name} in SI numbers (no unit)")
        try:
            lo, hi = (float(Q_(v, unit).to(shown).magnitude) for v in (lo, hi))
        except Exception as exc:  # pint's errors: an unknown unit, a wrong dimension
            raise click.UsageError(f"{option}={text!r}: {exc}") from None
    return name, (lo, hi)


@law_command()
@click.option(
    "--x",
    "x_axis",
    default=None,
    metavar="NAME=A..B",
    help="Horizontal axis: 'nu=0.05..2' (dimensionless), or 'v0=10..1e4' (um/s) with a physical "
    "set-up; default nu over 0.05..2.",
)
@click.option(
    "--y",
    "y_axis",
    default=None,
    metavar="NAME=A..B",
    help="Vertical axis: a law parameter ('c=2..20'), or 'stiffness=10..1e4' (N/m), 'mass=..' (kg), "
    "'load=..' (N) with a physical set-up.",
)
@click.option(
    "--records",
    "source",
    default=None,
    type=click.Path(exists=True),
    help="A folder of force records (as for 'stickslip analyze'): the model's (V, k) plane around "
    "them, with their measured regimes on it; needs --model.",
)
@click.option(
    "--name-pattern",
    default=None,
    help="With --records: the set-up in the file names, e.g. 'k{stiffness}Nm_v{v0}'.",
)
@click.option(
    "--model",
    "model_law",
    default=None,
    help="With --records: the paper's law 'mu_s=0.35, a=30 s/m, b=20 s/m' or a fit.json.",
)
@click.option(
    "--ratestate",
    default=None,
    metavar="SPEC",
    help="The inertial rate-and-state slider instead of a friction law: 'law=aging, a=0.01, b=0.015, "
    "dc=10 um, sigma=10 MPa, mass=1e5 kg/m^2' (per unit area); its Hopf curve over --x V=LO..HI (m/s) "
    "and --y k=LO..HI (Pa/m), with its Bautin points.",
)
@click.option(
    "--check",
    "check_n",
    type=click.IntRange(min=2, max=2000),
    default=None,
    metavar="N",
    help="Check the diagram by direct simulation on an N x N grid (several starts per cell).",
)
@click.option(
    "--step",
    type=click.FloatRange(min=1e-4, max=0.2),
    default=0.02,
    show_default=True,
    help="Largest continuation step, as a fraction of the plane.",
)
@click.option(
    "--seed-lines",
    type=click.IntRange(min=1, max=200),
    default=5,
    show_default=True,
    help="Lines of the plane on which the curves are seeded.",
)
@click.option(
    "--raster",
    type=click.IntRange(min=10, max=2000),
    default=200,
    show_default=True,
    help="Cells per axis of the regions' raster.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the curves, points and regions as JSON.")
@click.option(
    "--out",
    "out_dir",
    type=OutPath(file_okay=False),
    default=None,
    help="Write diagram.nc, diagram.json and diagram.png/.svg (with --check, the check is in "
    "diagram.json under 'check').",
)
@scale_options
@overwrite_option
@handle_errors
def diagram(
    x_axis: str | None,
    y_axis: str | None,
    source: str | None,
    model_law: str | None,
    name_pattern: str | None,
    ratestate: str | None,
    check_n: int | None,
    step: float,
    seed_lines: int,
    raster: int,
    as_json: bool,
    out_dir: str | None,
    store: str | None,
    scheduler: str | None,
    workers: int | None,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Continue the Hopf, fold-of-cycles and grazing curves in two parameters; find codimension-2 points.

    The law is given as for 'stickslip regimes'. Regions between the curves are named by
    their attractors (stick-slip, pure slip, steady sliding, bistable); Bautin points
    (super- to subcritical Hopf), fold-grazing points, cusps of folds (the return map's
    P''(A) = 0) and the ends of curves are located and classified. A Hopf and a grazing
    curve meet only as nu goes to 0 (an end point where they run into each other).
    --check runs the exact engine on a grid and says where it disagrees; --records draws
    the model's (V, k) plane around a folder of lab records.
    """
    from ..bifurcation.diagram import two_parameter_diagram
    from ..bifurcation.planes import Plane

    if out_dir is None:
        warn_unwritten(("overwrite",), "without --out")
    if check_n is None and (store or scheduler or workers):
        raise click.UsageError("--store, --scheduler and --workers go with --check (the brute-force grid)")
    options: dict[str, Any] = {"seed_lines": seed_lines, "step": step, "raster": raster}
    measured: list[tuple[float, float, str]] = []
    if ratestate is not None:
        if source is not None or model_law is not None:
            raise click.UsageError("--ratestate draws the slider's own (V, k) plane: drop --records/--model")
        if check_n is not None:
            raise click.UsageError("--check runs the one-block engine: not for --ratestate")
        d = _ratestate_diagram(ratestate, x_axis, y_axis, options)
    elif source is not None:
        if model_law is None:
            raise click.UsageError("--records needs --model (the law whose plane is drawn)")
        if x_axis or y_axis:
            raise click.UsageError(
                "--records sets the axes (v0 and stiffness around the records): drop --x/--y"
            )
        d, measured = _records_diagram(source, model_law, name_pattern, opts, options)
    else:
        if model_law is not None:
            raise click.UsageError("--model goes with --records")
        x = _axis(x_axis, "--x") or ("nu", (0.05, 2.0))
        y = _axis(y_axis, "--y")
        if y is None:
            raise click.UsageError("--y: give the vertical axis, e.g. --y c=2..20 (a law parameter)")
        from ..bifurcation.planes import SHOWN

        user_law = opts.get("f") is not None or opts.get("mu") is not None
        for axis, option in ((x, "--x"), (y, "--y")):  # a parameter on an axis need not be given as well
            name, (lo, _) = axis
            if name in opts and opts.get(name) is None:
                opts[name] = repr(lo)
            elif user_law and name not in opts and name not in SHOWN and name != "nu":
                given = params_of(opts)
                if name not in given:  # an expression's name: the axis gives its value
                    opts["param"] = (*(opts.get("param") or ()), f"{name}={lo!r}")
            elif name not in opts and name not in SHOWN and name != "nu":
                raise click.UsageError(
                    f"{option}={x_axis if option == '--x' else y_axis!r}: {name!r} is no parameter of the "
                    f"set-up (nu, {', '.join(sorted(SHOWN))}, or a parameter of the law such as "
                    f"{_law_names(opts)})"
                )
        physical = any(opts.get(k) is not None for k in ("mass", "beta", "stiffness", "load", "preset", "mu"))
        if physical or opts.get("v0") is not None:
            opts["v0"] = opts.get("v0") or "1 um/s"  # the axes replace it where they name it
        elif opts.get("nu") is None:
            opts["nu"] = 1.0
        params = build_parameters(opts)
        try:
            if isinstance(params, PhysicalParameters):
                plane = Plane.physical(params, x, y)
            else:
                plane = Plane.dimensionless(
                    params.law, x, y, nu=params.nu if "nu" not in (x[0], y[0]) else None
                )
        except ValueError as exc:
            raise click.UsageError(str(exc)) from None
        d = two_parameter_diagram(plane, **options)
    chk = None
    if check_n is not None:
        from ..bifurcation.diagram_check import check_diagram

        chk = check_diagram(d, (check_n, check_n), store=store, scheduler=scheduler, workers=workers)
    result = d.as_dict()
    if chk is not None:
        result["check"] = chk.as_dict()
    if measured:
        result["measured"] = [{"v0_um_per_s": x, "stiffness_N_per_m": y, "regime": r} for x, y, r in measured]
    if out_dir is not None:
        from ..bifurcation.diagram_io import diagram_dataset
        from ..io.netcdf import save_dataset
        from ..io.output import OutputFolder, json_writer
        from ..plots.diagram import plot_diagram
        from ..plots.figures import save_figure

        with OutputFolder(out_dir, "diagram", overwrite=overwrite) as out:
            save_dataset(diagram_dataset(d), "diagram.nc", kind="diagram", out=out)
            out.write("diagram.json", "diagram", json_writer(result, "diagram"))
            save_figure(plot_diagram(d, check=chk, measured=measured), "diagram", out=out)
    if as_json:
        click.echo(dumps_json(result, indent=2))
        return
    _print(d, chk, measured)
    if out_dir is not None:
        click.echo(f"wrote {out_dir}/diagram.nc, diagram.json and diagram.png/.svg")


def _law_names(opts: dict[str, Any]) -> str:
    """Return the parameters of the law that ``opts`` names, for a message."""
    from ..laws import registry

    try:
        names = [p.name for p in registry.get(str(opts.get("law") or "")).spec.parameters]
    except ValueError:
        names = []
    return "/".join(names) or "its parameters"


def _ratestate_diagram(spec: str, x_axis: str | None, y_axis: str | None, options: dict[str, Any]) -> Any:
    from ..ratestate.inertia import InertialSlider
    from ..ratestate.inertia_diagram import inertial_diagram

    values: dict[str, str] = {}
    for item in spec.split(","):
        name, sep, value = item.partition("=")
        if not sep or name.strip() not in ("law", "a", "b", "dc", "sigma", "mass") or name.strip() in values:
            raise click.UsageError(
                f"--ratestate={spec!r}: expected 'law=aging, a=0.01, b=0.015, dc=10 um, sigma=10 MPa, "
                "mass=1e5 kg/m^2' (each once)"
            )
        values[name.strip()] = value.strip()
    missing = [k for k in ("a", "b", "dc", "sigma", "mass") if k not in values]
    if missing:
        raise click.UsageError(f"--ratestate={spec!r}: give {', '.join(missing)}")
    x = _axis(x_axis, "--x") or ("V", (1e-6, 1e-1))
    y = _axis(y_axis, "--y")
    if x[0] != "V" or y is None or y[0] != "k":
        raise click.UsageError("--ratestate: the axes are --x V=LO..HI (m/s) and --y k=LO..HI (Pa/m)")
    try:
        slider = InertialSlider(
            a=float(values["a"]), b=float(values["b"]), dc=values["dc"], sigma=values["sigma"],
            mass=values["mass"], law=values.get("law", "aging"),
        )  # fmt: skip
    except ValueError as exc:
        raise click.UsageError(f"--ratestate: {exc}") from None
    return inertial_diagram(slider, x[1], y[1], step=options["step"], raster=options["raster"],
                            seed_lines=options["seed_lines"])  # fmt: skip


def _records_diagram(
    folder: str, model_law: str, pattern: str | None, opts: dict[str, Any], options: dict[str, Any]
) -> tuple[Any, list[tuple[float, float, str]]]:
    from ..data.model_plane import read_model_law, records_diagram
    from ..data.records import analyze_records
    from ..io.formats import RecordOptions
    from ..io.records import UnreadableRecord, read_records

    law = read_model_law(model_law)
    mass, load = opts.get("mass"), opts.get("load")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        recs = read_records(
            folder,
            on_error="warn",
            mass=mass,
            load=load,
            options=RecordOptions(None, None, None, None, None, pattern),
        )
    for w in caught:
        if not isinstance(w.message, UnreadableRecord):
            warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    table, _ = analyze_records(recs)
    return records_diagram(table, law, **options)


def _print(d: Any, chk: Any, measured: list[tuple[float, float, str]]) -> None:
    pl = d.plane
    click.echo(f"plane: {pl.describe}")
    for c in d.curves:
        click.echo(
            f"{c.kind:<8} curve: {len(c.x)} points, {pl.x.name} {min(c.x):.6g}..{max(c.x):.6g}, "
            f"{pl.y.name} {min(c.y):.6g}..{max(c.y):.6g}; ends: {c.ends[0]}, {c.ends[1]}"
        )
    for p in d.points:
        click.echo(
            f"{p.kind:<13} {pl.x.name} = {p.x:.10g}, {pl.y.name} = {p.y:.10g} (nu = {p.nu:.10g}); "
            f"{p.coefficient} = {p.value:.6g}: {p.detail}"
        )
    for names, regime in zip(d.region_names, d.region_regime, strict=True):
        click.echo(f"region  {regime:<15} {names}")
    for x, y, r in measured:
        click.echo(f"record  v0 = {x:.6g} um/s, k = {y:.6g} N/m: measured {r}; model {d.regime_at(x, y)}")
    for note in d.notes:
        click.echo(f"note: {note}")
    if chk is not None:
        click.echo(chk.report())


def register(main: click.Group) -> None:
    """Add ``diagram`` to ``main``."""
    main.add_command(diagram)
