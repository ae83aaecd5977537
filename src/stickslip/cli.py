"""Command line: a thin layer over the public API.

Parameters are given either dimensionless (``--nu`` and the law's
dimensionless options) or physical (``--v0 --mass --stiffness --load`` and the
law's physical options, values with units such as ``"196 mN"``), or from the
paper's zv set-up (``--preset zv``, each option overridable).
"""

from __future__ import annotations

import errno
import functools
import json
import os
import sys
from collections.abc import Callable
from typing import Any

import click
import numpy as np

from . import defaults
from .io.errors import DataError
from .models.friction import (
    CoulombLaw,
    CubicLaw,
    PhysicalCoulombLaw,
    PhysicalCubicLaw,
    PhysicalWeakeningLaw,
    WeakeningLaw,
)
from .models.parameters import (
    ZV_A,
    ZV_LOAD,
    ZV_MU0,
    ZV_STIFFNESS,
    DimensionlessParameters,
    PhysicalParameters,
    zv_parameters,
)
from .models.units import parse_quantity

LAW_DIMENSIONLESS = {"weakening": ("c", "p"), "cubic": ("alpha", "gamma"), "coulomb": ("kinetic",)}
LAW_PHYSICAL = {"weakening": ("mu0", "a", "b"), "cubic": ("mu_s", "k1", "k3"), "coulomb": ("mu_s", "mu_k")}
SETUP = ("v0", "mass", "stiffness", "load")


def _opt(name: str) -> str:
    return "--" + name.replace("_", "-")


def out_dir_option(help_text: str) -> Any:
    """Return the ``--out`` option (an output folder, default ``results``) of a command."""
    return click.option(
        "--out",
        "out_dir",
        type=click.Path(file_okay=False),
        default="results",
        show_default=True,
        help=help_text,
    )


def model_options(func: Callable[..., Any] | None = None, *, text: bool = False) -> Any:
    """Add the options that define a parameter set to a command.

    With ``text=True`` every value option is read as text (for sweep ranges).
    """
    if func is None:
        return functools.partial(model_options, text=text)
    num: Any = str if text else float
    opts = [
        click.option(
            "--law",
            type=click.Choice(["weakening", "cubic", "coulomb"]),
            default="weakening",
            show_default=True,
            help="Friction law.",
        ),
        click.option(
            "--preset",
            type=click.Choice(["zv"]),
            default=None,
            help="Physical set-up of the paper's zv experiment (beta = 42 s/m); other options override it.",
        ),
        click.option("--nu", type=num, default=None, help="Dimensionless driving velocity beta*v0."),
        click.option("--c", "c", type=num, default=None, help="weakening: c = a/beta."),
        click.option("--p", "p", type=num, default=None, help="weakening: p = b/beta (default 0)."),
        click.option("--alpha", type=num, default=None, help="cubic: alpha = k1/(mu_s beta)."),
        click.option("--gamma", type=num, default=None, help="cubic: gamma = k3/(mu_s beta^3)."),
        click.option(
            "--kinetic", type=num, default=None, help="coulomb: kinetic/static friction ratio, in (0, 1)."
        ),
        click.option("--v0", default=None, help="Driving velocity, e.g. '5 um/s'."),
        click.option("--mass", default=None, help="Mass, e.g. '1 kg'."),
        click.option(
            "--beta", default=None, help="Instead of --mass: beta = sqrt(k m)/(mu_s W), e.g. '42 s/m'."
        ),
        click.option("--stiffness", default=None, help="Spring constant, e.g. '62 N/m'."),
        click.option("--load", default=None, help="Normal load W, e.g. '196 mN'."),
        click.option("--mu0", type=num, default=None, help="weakening: static coefficient mu0."),
        click.option("--a", "a", default=None, help="weakening: a, e.g. '160 s/m'."),
        click.option("--b", "b", default=None, help="weakening: b, e.g. '100 s/m' (default 0)."),
        click.option(
            "--mu-s", "mu_s", type=num, default=None, help="cubic/coulomb: static coefficient mu_s."
        ),
        click.option("--k1", default=None, help="cubic: k1, e.g. '0.5 s/m'."),
        click.option("--k3", default=None, help="cubic: k3, e.g. '0.01 s**3/m**3'."),
        click.option(
            "--mu-k", "mu_k", type=num, default=None, help="coulomb: kinetic coefficient mu_k < mu_s."
        ),
        click.option(
            "--rtol",
            type=float,
            default=defaults.RTOL,
            show_default=True,
            help="Relative tolerance of the integration.",
        ),
        click.option(
            "--atol",
            type=float,
            default=defaults.ATOL,
            show_default=True,
            help="Absolute tolerance of the integration.",
        ),
    ]
    for o in reversed(opts):
        func = o(func)
    return func


def build_parameters(
    opts: dict[str, Any], *, default_preset: bool = False
) -> DimensionlessParameters | PhysicalParameters:
    """Build a parameter set from command-line options.

    Raises
    ------
    click.UsageError
        For a missing, conflicting or invalid option.

    """
    law = opts["law"]
    dim_keys = ["nu", "c", "p", "alpha", "gamma", "kinetic"]
    phys_keys = [*SETUP, "beta", "mu0", "a", "b", "mu_s", "k1", "k3", "mu_k"]
    dim_given = [k for k in dim_keys if opts.get(k) is not None]
    phys_given = [k for k in phys_keys if opts.get(k) is not None]
    preset = opts.get("preset")
    if dim_given and (phys_given or preset):
        raise click.UsageError(
            f"options {', '.join(map(_opt, dim_given))} are dimensionless and "
            f"{', '.join(map(_opt, phys_given)) or '--preset'} physical: give one kind only"
        )
    if not dim_given and not phys_given and not preset:
        if not default_preset:
            raise click.UsageError(
                "no parameters: give --nu with the law's dimensionless options "
                "(e.g. --nu 0.01 --c 3.8), or --v0 --mass --stiffness --load with the law's "
                "physical options, or --preset zv"
            )
        preset = "zv"
    try:
        if dim_given:
            opts = {k: (_to_float(k, v) if k in dim_keys else v) for k, v in opts.items()}
            return _dimensionless(law, opts, dim_given)
        return _physical(law, opts, phys_given, preset)
    except ValueError as exc:
        raise click.UsageError(f"invalid value: {exc}") from None


def _to_float(name: str, value: Any) -> Any:
    if value is None or isinstance(value, float):
        return value
    try:
        return float(value)
    except ValueError:
        raise ValueError(f"{name}={value!r}: expected a number") from None


def _check_law_options(law: str, given: list[str], table: dict[str, tuple[str, ...]]) -> None:
    own = set(table[law])
    for k in given:
        for other, keys in table.items():
            if other != law and k in keys and k not in own:
                raise click.UsageError(f"{_opt(k)} belongs to --law {other}, not --law {law}")


def _require(opts: dict[str, Any], names: tuple[str, ...], context: str) -> None:
    missing = [n for n in names if opts.get(n) is None]
    if missing:
        raise click.UsageError(f"{context} needs {', '.join(map(_opt, missing))}")


def _dimensionless(law: str, opts: dict[str, Any], given: list[str]) -> DimensionlessParameters:
    _check_law_options(law, given, LAW_DIMENSIONLESS)
    _require(opts, ("nu",), "a dimensionless set-up")
    if law == "weakening":
        _require(opts, ("c",), "--law weakening")
        dlaw: Any = WeakeningLaw(c=opts["c"], p=opts["p"] if opts["p"] is not None else 0.0)
    elif law == "cubic":
        _require(opts, ("alpha", "gamma"), "--law cubic")
        dlaw = CubicLaw(alpha=opts["alpha"], gamma=opts["gamma"])
    else:
        _require(opts, ("kinetic",), "--law coulomb")
        dlaw = CoulombLaw(kinetic=opts["kinetic"])
    return DimensionlessParameters(nu=opts["nu"], law=dlaw)


def _physical(law: str, opts: dict[str, Any], given: list[str], preset: str | None) -> PhysicalParameters:
    _check_law_options(law, [k for k in given if k not in (*SETUP, "beta")], LAW_PHYSICAL)
    o = {k: (_to_float(k, v) if k in ("mu0", "mu_s", "mu_k") else v) for k, v in opts.items()}
    if o.get("beta") is not None and o.get("mass") is not None:
        raise click.UsageError("give --mass or --beta, not both: beta sets the mass")
    if preset == "zv":
        base = zv_parameters()
        for key, value in (
            ("v0", "10 um/s"),
            ("mass", base.mass),
            ("stiffness", ZV_STIFFNESS),
            ("load", ZV_LOAD),
        ):
            if o.get(key) is None:
                o[key] = value
        if law == "weakening":
            o["mu0"] = ZV_MU0 if o.get("mu0") is None else o["mu0"]
            o["a"] = ZV_A if o.get("a") is None else o["a"]
    if o.get("beta") is not None:
        _require(o, ("stiffness", "load"), "--beta")
        mu = o.get("mu0") if law == "weakening" else o.get("mu_s")
        if mu is None:
            raise click.UsageError("--beta needs the static coefficient (--mu0 or --mu-s)")
        beta = parse_quantity(o["beta"], "beta", "[time] / [length]", "42 s/m")
        k = parse_quantity(o["stiffness"], "stiffness", "[mass] / [time] ** 2", "62 N/m")
        w = parse_quantity(o["load"], "load", "[force]", "196 mN")
        o["mass"] = ((beta * float(mu) * w) ** 2 / k).to("kg")
    _require(o, SETUP, "a physical set-up")
    if law == "weakening":
        _require(o, ("mu0", "a"), "--law weakening")
        plaw: Any = PhysicalWeakeningLaw(
            mu0=o["mu0"], a=o["a"], b=o["b"] if o.get("b") is not None else "0 s/m"
        )
    elif law == "cubic":
        _require(o, ("mu_s", "k1", "k3"), "--law cubic")
        plaw = PhysicalCubicLaw(mu_s=o["mu_s"], k1=o["k1"], k3=o["k3"])
    else:
        _require(o, ("mu_s", "mu_k"), "--law coulomb")
        plaw = PhysicalCoulombLaw(mu_s=o["mu_s"], mu_k=o["mu_k"])
    return PhysicalParameters(mass=o["mass"], stiffness=o["stiffness"], load=o["load"], v0=o["v0"], law=plaw)


def describe_parameters(params: DimensionlessParameters | PhysicalParameters) -> dict[str, Any]:
    """Return a JSON-ready description of a parameter set (with the dimensionless form)."""
    if isinstance(params, DimensionlessParameters):
        return {"nu": params.nu, "law": params.law.name, **_law_fields(params.law)}
    d = params.dimensionless()
    law = params.law
    out: dict[str, Any] = {
        "v0": f"{params.v0:~P}",
        "mass": f"{params.mass:~P}",
        "stiffness": f"{params.stiffness:~P}",
        "load": f"{params.load:~P}",
        "law": law.name,
    }
    for k, v in _law_fields(law).items():
        out[k] = v if isinstance(v, float) else f"{v:~P}"
    out["beta"] = f"{params.beta:.6g~P}"
    out["dimensionless"] = {"nu": d.nu, "law": d.law.name, **_law_fields(d.law)}
    return out


def _law_fields(law: Any) -> dict[str, Any]:
    import dataclasses

    return {f.name: getattr(law, f.name) for f in dataclasses.fields(law)}


class _DataProblem(click.ClickException):
    """A file or record that cannot be used: one ``Error:`` line, no usage text, exit code 2."""

    exit_code = 2


def _os_message(exc: OSError) -> str:
    where = exc.filename or ""
    what = exc.strerror or str(exc)
    if exc.errno == errno.ENOSPC:
        what += " (the previous file, if any, is untouched)"
    return f"{where}: {what}" if where else what


def _handle_errors(func: Callable[..., Any]) -> Callable[..., Any]:
    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except DataError as exc:  # a file or record: the options were fine, the data were not
            raise _DataProblem(str(exc)) from None
        except ValueError as exc:
            raise click.UsageError(f"invalid value: {exc}") from None
        except RuntimeError as exc:  # a computation that failed (not a user mistake)
            raise click.ClickException(str(exc)) from None
        except OSError as exc:  # a file that cannot be read or written: name it
            raise click.ClickException(_os_message(exc)) from None

    return wrapper


def _figure_names(stem: str) -> dict[str, str]:
    return {f"{stem}.png": "figure", f"{stem}.svg": "figure"}


def overwrite_option(func: Callable[..., Any]) -> Any:
    """Add ``--overwrite``: replace existing outputs that stickslip did not write."""
    return click.option(
        "--overwrite",
        is_flag=True,
        help="Replace existing output files even if stickslip did not write them.",
    )(func)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="stickslip")
def main() -> None:
    """Friction oscillators: the one-block spring-slider, exact and fast."""


@main.command()
@model_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--no-probe", is_flag=True, help="Do not look for a second attractor.")
@_handle_errors
def cycle(as_json: bool, no_probe: bool, **opts: Any) -> None:
    """Compute the steady oscillation: regime, amplitude, period, stick fraction.

    Dimensionless input gives dimensionless output (force in units of the static
    friction force, time in units of sqrt(m/k)); physical input gives N and s.
    """
    from .dynamics.cycle import cycle as compute_cycle

    params = build_parameters(opts)
    res = compute_cycle(params, rtol=opts["rtol"], atol=opts["atol"], probe=not no_probe)
    if as_json:
        d = res.as_dict()
        d["parameters"] = describe_parameters(params)
        click.echo(json.dumps(d, indent=2))
        _fail_unless_ok(res.status)
        return
    u = res.units
    click.echo(f"regime          {res.regime}" + ("  (multistable)" if res.multistable else ""))
    click.echo(f"amplitude       {res.amplitude:.10g} [{u['force']}]")
    click.echo(f"period          {res.period:.10g} [{u['time']}]")
    click.echo(f"stick fraction  {res.stick_fraction:.6g}")
    click.echo(f"slip distance   {res.slip_distance:.10g} [{u['length']}]")
    click.echo(f"peak velocity   {res.peak_velocity:.10g} [{u['velocity']}]")
    click.echo(f"backward slips  {res.backward_slips}")
    click.echo(f"status          {res.status}")
    for a in res.attractors:
        click.echo(f"attractor       {a.regime} from {a.start}: amplitude {a.amplitude:.6g} ({a.status})")
    _fail_unless_ok(res.status)


def _fail_unless_ok(status: str) -> None:
    """Exit with status 1 (after the output) when the computation did not finish."""
    if status != "ok":
        hint = {
            "not-converged": "the oscillation could not be pinned down to the promised 1e-8: the "
            "transient did not settle and could not be solved as a periodic orbit to that accuracy "
            "(within about 1e-5 of a Hopf point the orbit's multiplier tends to 1)",
            "too-many-steps": "the slip phase needs more steps than allowed: the law is very "
            "stiff at these parameters",
        }.get(status, "")
        click.echo(f"stickslip: the computation did not finish: {status}; {hint}", err=True)
        raise SystemExit(1)


@main.command()
@model_options
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
@_handle_errors
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
    from .dynamics.trajectory import simulate as run

    params = build_parameters(opts, default_preset=True)
    dur: Any = duration
    if duration is not None and isinstance(params, DimensionlessParameters):
        try:
            dur = float(duration)
        except ValueError:
            raise click.UsageError(
                f"invalid value: duration={duration!r}: expected a number for dimensionless input"
            ) from None
    from .io.output import OutputFolder

    with OutputFolder(out_dir, "simulate", overwrite=overwrite) as out:
        out.expect({"trajectory.csv": "trajectory"} | ({} if no_plot else _figure_names("spring_force")))
        traj = run(params, duration=dur, cycles=cycles, n_points=points, rtol=opts["rtol"], atol=opts["atol"])
        written = [traj.to_csv("trajectory.csv", out=out)]
        if not no_plot:
            from .plots.figures import plot_spring_force, save_figure

            title = None
            if isinstance(params, PhysicalParameters):
                title = f"v0 = {params.v0:~P}, beta = {params.beta.to('s/m').magnitude:.3g} s/m"
            written += save_figure(plot_spring_force(traj, title=title), "spring_force", out=out)
    click.echo(f"wrote {written[0]} ({traj.time.size} samples)")
    if len(written) > 1:
        click.echo("wrote " + ", ".join(written[1:]))
    from .dynamics.cycle import cycle as compute_cycle

    n_stops = sum(1 for k in traj.event_kind if k == "stick")
    click.echo(f"{n_stops} stick phases simulated")
    # the steady oscillation, solved (not read off samples): polished into its periodic orbit
    res = compute_cycle(params, rtol=opts["rtol"], atol=opts["atol"], probe=False)
    u = res.units
    click.echo(
        f"steady cycle: {res.regime}, amplitude {res.amplitude:.10g} [{u['force']}], "
        f"period {res.period:.10g} [{u['time']}], Floquet multiplier {res.multiplier:.6g} ({res.status})"
    )


@main.command()
@out_dir_option("Output folder.")
@click.option("--quick", is_flag=True, help="A reduced version (fewer points per curve), for tests.")
@overwrite_option
@_handle_errors
def reproduce(out_dir: str, quick: bool, overwrite: bool) -> None:
    """Reproduce the paper: Figs. 1-3, parameter dependences, the criterion, a report.

    Writes reproduce.nc (every curve), each figure as PNG and SVG, report.md and a
    self-contained report.html into the output folder.
    """
    import time

    from .paper import reproduce as run

    t0 = time.perf_counter()
    res = run(out_dir, quick=quick, overwrite=overwrite)
    click.echo(f"wrote {res.netcdf}")
    for paths in res.figures.values():
        click.echo(f"wrote {', '.join(paths)}")
    click.echo(f"wrote {res.report_md}, {res.report_html}")
    for c in res.claims:
        click.echo(f"claim {c.number:2d}: {c.verdict}")
    click.echo(f"done in {time.perf_counter() - t0:.1f} s")


@main.command()
@click.option("--A", "a", type=float, default=None, help="Direct effect A (> 0).")
@click.option("--B", "b", type=float, default=None, help="Evolution effect B (>= 0).")
@click.option("--kappa", type=float, default=None, help="Stiffness kappa = k D0 / W (> 0).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@_handle_errors
def dulac(a: float | None, b: float | None, kappa: float | None, as_json: bool) -> None:
    """Dulac's criterion for the quasi-static Rice-Ruina model (the paper's appendix).

    Derives the dimensionless system and its divergence with sympy from the
    physical equations and prints them; with --A --B --kappa says whether
    periodic orbits are excluded for those values.
    """
    import sympy as sp

    from .ratestate.dulac import derive, excluded, sign_verdict

    given = [v is not None for v in (a, b, kappa)]
    if any(given) and not all(given):
        raise click.UsageError("give all of --A, --B and --kappa, or none")
    d = derive()
    out: dict[str, Any] = {
        "alpha_dot": sp.sstr(d.alpha_dot),
        "phi_dot": sp.sstr(d.phi_dot),
        "divergence": sp.sstr(d.divergence),
        "divergence_latex": sp.latex(d.divergence),
        "sign_factor": sp.sstr(d.sign_factor),
        "positive_factor": sp.sstr(d.positive_factor),
        "verdict": "no periodic orbits unless B - A - kappa = 0 (Dulac's criterion with g = 1 on "
        "the simply connected half-plane phi > 0)",
    }
    if all(given):
        assert a is not None and b is not None and kappa is not None
        out["values"] = {"A": a, "B": b, "kappa": kappa, "B - A - kappa": b - a - kappa}
        out["excluded"] = excluded(a, b, kappa)
        out["verdict"] = sign_verdict(a, b, kappa)
    if as_json:
        click.echo(json.dumps(out, indent=2))
        return
    click.echo(f"alpha' = {out['alpha_dot']}")
    click.echo(f"phi'   = {out['phi_dot']}")
    click.echo(f"divergence = {out['divergence']}")
    click.echo(f"LaTeX: {out['divergence_latex']}")
    click.echo(f"sign decided by: {out['sign_factor']}  (times {out['positive_factor']} > 0)")
    if "excluded" in out:
        click.echo(f"periodic orbits excluded: {'yes' if out['excluded'] else 'no'}")
    click.echo(f"verdict: {out['verdict']}")


@main.command()
@click.option("--a", "a", type=float, required=True, help="Direct effect A.")
@click.option("--b", "b", type=float, required=True, help="Evolution effect B.")
@click.option("--dc", required=True, help="Characteristic slip D0, e.g. '10 um'.")
@click.option("--v-ref", "v_ref", required=True, help="Reference velocity V_r, e.g. '1 um/s'.")
@click.option("--mu0", type=float, required=True, help="Steady friction at V_r.")
@click.option("--stiffness", default=None, help="Spring constant k (with --load), e.g. '1e4 N/m'.")
@click.option("--load", default=None, help="Normal load W, e.g. '10 N'.")
@click.option("--stiffness-per-load", "kw", default=None, help="k/W instead, e.g. '1 1/mm'.")
@click.option("--mass", default=None, help="Slider mass (inertial model), e.g. '1 kg'.")
@click.option(
    "--law",
    type=click.Choice(["aging", "slip"]),
    default="aging",
    show_default=True,
    help="State evolution law.",
)
@click.option("--steps", default=None, help="Velocity-step test: velocities, e.g. '1 um/s,10 um/s,1 um/s'.")
@click.option("--displacement", default=None, help="Load-point displacement per slide (default 20 D0).")
@click.option("--holds", default=None, help="Slide-hold-slide test: hold times, e.g. '1 s,10 s,100 s'.")
@click.option("--v-slide", "v_slide", default=None, help="Slide velocity of the slide-hold-slide test.")
@out_dir_option("Output folder for ratestate.nc and ratestate.png/.svg.")
@overwrite_option
@_handle_errors
def ratestate(
    a: float,
    b: float,
    dc: str,
    v_ref: str,
    mu0: float,
    stiffness: str | None,
    load: str | None,
    kw: str | None,
    mass: str | None,
    law: str,
    steps: str | None,
    displacement: str | None,
    holds: str | None,
    v_slide: str | None,
    out_dir: str,
    overwrite: bool,
) -> None:
    """Run a rate-and-state laboratory protocol: velocity steps or slide-hold-slide.

    Example: stickslip ratestate --a 0.01 --b 0.015 --dc "10 um" --v-ref "1 um/s" --mu0 0.6
    --stiffness-per-load "1 1/mm" --steps "1 um/s,10 um/s,1 um/s"
    """
    from .dynamics.sweep import save_sweep
    from .plots.figures import plot_rate_state, save_figure
    from .ratestate.model import RateStateParameters
    from .ratestate.protocols import slide_hold_slide, velocity_steps

    if (steps is None) == (holds is None):
        raise click.UsageError("give one protocol: --steps VELOCITIES or --holds TIMES (with --v-slide)")
    params = RateStateParameters(
        a=a,
        b=b,
        dc=dc,
        v_ref=v_ref,
        mu0=mu0,
        stiffness=stiffness,
        load=load,
        stiffness_per_load=kw,
        mass=mass,
        state_law=law,
    )
    if steps is not None:
        ds = velocity_steps(params, [v.strip() for v in steps.split(",")], displacement=displacement)
    else:
        if v_slide is None:
            raise click.UsageError("--holds needs --v-slide")
        assert holds is not None
        ds = slide_hold_slide(
            params, v_slide, [h.strip() for h in holds.split(",")], displacement=displacement
        )
    from .io.output import OutputFolder

    with OutputFolder(out_dir, "ratestate", overwrite=overwrite) as out:
        path = save_sweep(ds, "ratestate.nc", kind="ratestate", out=out)
        paths = save_figure(plot_rate_state(ds), "ratestate", out=out)
    click.echo(f"wrote {path}, {', '.join(paths)}")
    click.echo(f"friction from {float(ds.friction.min()):.6g} to {float(ds.friction.max()):.6g}")
    if "peak_friction_change" in ds:
        for t_h, dmu in zip(ds.hold_time.values, ds.peak_friction_change.values, strict=True):
            click.echo(f"hold {t_h:g} s: peak friction change {dmu:.6g}")


@main.command()
@click.argument("source", type=click.Path(exists=False))
@out_dir_option("Output folder: summary.csv and figures.")
@click.option("--json", "as_json", is_flag=True, help="Print the verdict and summary as JSON.")
@click.option("--no-plot", is_flag=True, help="Write summary.csv only.")
@overwrite_option
@_handle_errors
def analyze(source: str, out_dir: str, as_json: bool, no_plot: bool, overwrite: bool) -> None:
    """Measure a folder of force-time records (or one long table) and apply the criterion.

    SOURCE is a folder of CSV/TSV records (with index.csv giving 'file', 'v0 [unit]',
    'load [unit]', or '# v0 = ...' header lines in each file) or one table with a
    'record' column. Writes summary.csv (one row per record) and amplitude and
    period against driving velocity and load.
    """
    from .data.records import analyze_records
    from .io.output import OutputFolder
    from .io.records import read_records
    from .plots.figures import plot_records, save_figure

    with OutputFolder(out_dir, "analyze", overwrite=overwrite) as out:
        out.expect({"summary.csv": "records-summary"})
        records = read_records(source)
        table, verdict = analyze_records(records)
        written = [
            out.write(
                "summary.csv", "records-summary", lambda p: table.to_csv(p, index=False, float_format="%.10g")
            )
        ]
        if not no_plot:
            for name, fig in plot_records(table).items():
                written += save_figure(fig, name, out=out)
    if as_json:
        click.echo(
            json.dumps(
                {
                    "verdict": None if verdict is None else verdict.as_dict(),
                    "records": json.loads(table.to_json(orient="records")),
                },
                indent=2,
            )
        )
        return
    click.echo("wrote " + ", ".join(written))
    for name, note in zip(table["name"], table["warning"], strict=True):
        if isinstance(note, str) and note:
            click.echo(f"warning: {name}: {note}")
    cols = ["name", "n_cycles", "v0 [m/s]", "load [N]", "amplitude [N]", "period [s]", "stick_fraction"]
    click.echo(table[cols].to_string(index=False, float_format=lambda x: f"{x:.4g}"))
    if verdict is None:
        click.echo("criterion: no verdict (records need driving velocities)")
    else:
        click.echo(f"criterion: {verdict.verdict} ({verdict.reason})")


@main.command()
@click.argument("record_file", type=click.Path(exists=False, dir_okay=False))
@click.option("--v0", default=None, help="Driving velocity (overrides the file's '# v0 = ...').")
@click.option("--load", default=None, help="Normal load (overrides the file's '# load = ...').")
@click.option("--fit-b", is_flag=True, help="Also fit b (law F2); default F1 (b = 0).")
@click.option(
    "--method",
    type=click.Choice(["waveform", "features"]),
    default="waveform",
    show_default=True,
    help="Fit the force waveform (started from cycle features), or the cycle features only.",
)
@out_dir_option("Output folder: fit.json, fit.csv, fit_overlay.png/.svg.")
@click.option("--no-plot", is_flag=True, help="Do not draw the overlay figure.")
@click.option("--json", "as_json", is_flag=True, help="Print the fit as JSON.")
@overwrite_option
@_handle_errors
def fit(
    record_file: str,
    v0: str | None,
    load: str | None,
    fit_b: bool,
    method: str,
    out_dir: str,
    no_plot: bool,
    as_json: bool,
    overwrite: bool,
) -> None:
    """Fit mu0, a, k and the mass (and b) of the paper's model to a stick-slip record.

    By default the force waveform itself is fitted (residuals weighted by the record's
    noise, so the reduced chi-square says whether the model describes the record),
    starting from a fit on cycle features (peak and trough force, period, stick-ramp
    slope, drop time). Uncertainties, correlations and identifiability warnings.
    """
    from .data.fitting import fit_record
    from .io.output import OutputFolder, json_writer, text_writer
    from .io.records import read_record

    with OutputFolder(out_dir, "fit", overwrite=overwrite) as out:
        out.expect(
            {"fit.json": "fit", "fit.csv": "fit-parameters"}
            | ({} if no_plot else _figure_names("fit_overlay"))
        )
        rec = read_record(record_file, v0=v0, load=load)
        res = fit_record(rec, fit_b=fit_b, method=method)
        d = res.as_dict()
        rows = "".join(
            f"{name},{v['value']!r},{v['error']!r},{v['unit']}\n" for name, v in d["parameters"].items()
        )
        paths = [
            out.write("fit.json", "fit", json_writer(d, "fit")),
            out.write("fit.csv", "fit-parameters", text_writer("parameter,value,error,unit\n" + rows)),
        ]
        if not no_plot:
            from .plots.figures import plot_fit_overlay, save_figure

            paths += save_figure(plot_fit_overlay(rec, res), "fit_overlay", out=out)
    if as_json:
        click.echo(json.dumps(d, indent=2))
        return
    for name, v in d["parameters"].items():
        if v.get("at_bound"):
            click.echo(f"{name:4s} = 0 (at its bound; < {v['upper_limit_95']:.3g} {v['unit']} at 95%)")
        else:
            click.echo(f"{name:4s} = {v['value']:.6g} +- {v['error']:.2g} {v['unit']}")
    click.echo(
        f"reduced chi2 = {res.reduced_chi2:.3f} ({res.method} fit, {res.samples} "
        f"{'samples' if res.method == 'waveform' else 'features'}, noise {1e3 * res.noise:.3g} mN)"
    )
    for w in res.warnings:
        click.echo(f"warning: {w}")
    click.echo("wrote " + ", ".join(paths))


NUMBER_KEYS = {"nu", "c", "p", "alpha", "gamma", "kinetic", "mu0", "mu_s", "mu_k"}
VALUE_KEYS = NUMBER_KEYS | {*SETUP, "beta", "a", "b", "k1", "k3"}


def _plot_sweep(ds: Any, log: bool) -> Any:
    from .plots.figures import plot_sweep

    return plot_sweep(ds, log=log)


def parse_axis(name: str, text: str, num: int, log: bool) -> Any:
    """Parse a sweep axis: a range ``'A..B'`` (``num`` points) or a list ``'A,B,C'``.

    Physical values keep units (``'5 um/s..1000 um/s'``, or ``'5..1000 um/s'``);
    numbers are floats. Raises ValueError for a malformed axis.
    """
    import numpy as np

    from .models.units import Q_

    if ".." in text:
        parts = [t.strip() for t in text.split("..")]
        if len(parts) != 2 or not all(parts):
            raise ValueError(f"{name}={text!r}: expected a range 'A..B'")
        if num < 2:
            raise ValueError(f"--num={num}: a range needs at least 2 points")
        if name in NUMBER_KEYS:
            lo, hi = (_to_float(name, t) for t in parts)
            qlo = Q_(lo, "")
            qhi = Q_(hi, "")
        else:
            qhi = parse_quantity(
                parts[1], name, "[]" if False else _dimension_of(name), "1 um/s", allow_zero=name == "b"
            )
            lo_text = parts[0]
            try:
                float(lo_text)
                lo_text = f"{lo_text} {qhi.units:~}"
            except ValueError:
                pass
            qlo = parse_quantity(lo_text, name, _dimension_of(name), "1 um/s", allow_zero=name == "b")
            qlo = qlo.to(qhi.units)
        a, b = float(qlo.magnitude), float(qhi.magnitude)
        if log:
            if a <= 0 or b <= 0:
                raise ValueError(f"{name}={text!r}: a --log range needs positive ends")
            vals = np.geomspace(a, b, num)
        else:
            vals = np.linspace(a, b, num)
        return list(vals) if name in NUMBER_KEYS else Q_(vals, qhi.units)
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise ValueError(f"{name}={text!r}: expected values separated by commas")
    if name in NUMBER_KEYS:
        return [_to_float(name, t) for t in items]
    return items


def _dimension_of(name: str) -> str:
    from .dynamics.sweep import PHYSICAL_LAW
    from .dynamics.sweep import SETUP as SWEEP_SETUP

    if name in SWEEP_SETUP:
        return SWEEP_SETUP[name][0]
    for table in PHYSICAL_LAW.values():
        if name in table:
            return table[name][0]
    raise ValueError(f"{name}: not a sweepable parameter")


@main.command()
@model_options(text=True)
@click.option("--num", type=int, default=30, show_default=True, help="Points per range 'A..B'.")
@click.option("--log", "log_spacing", is_flag=True, help="Space the points of ranges logarithmically.")
@click.option(
    "--out",
    "out_path",
    type=click.Path(dir_okay=False),
    default="results/sweep.nc",
    show_default=True,
    help="NetCDF output; the plot goes beside it (.png, .svg).",
)
@click.option("--no-plot", is_flag=True, help="Write the NetCDF file only.")
@click.option("--quiet", is_flag=True, help="No progress bar.")
@overwrite_option
@_handle_errors
def sweep(
    num: int, log_spacing: bool, out_path: str, no_plot: bool, quiet: bool, overwrite: bool, **opts: Any
) -> None:
    """Sweep parameters over ranges ('A..B') or lists ('A,B,C'); write NetCDF and a plot.

    Any value option can be swept; the others are fixed as in 'stickslip cycle'.
    Example: stickslip sweep --preset zv --v0 "5 um/s..1000 um/s" --num 60 --log
    """
    from .dynamics.sweep import check_sweep_size, save_sweep
    from .dynamics.sweep import sweep as run_sweep
    from .plots.figures import save_figure

    axes: dict[str, Any] = {}
    fixed = dict(opts)
    ranged = {
        k: v for k, v in opts.items() if k in VALUE_KEYS and isinstance(v, str) and (".." in v or "," in v)
    }
    if num < 2:
        raise click.UsageError(f"invalid value: --num={num}: expected at least 2 points per range")
    # the grid's size from the options, before any axis is built
    sizes = [num if ".." in v else len([c for c in v.split(",") if c.strip()]) for v in ranged.values()]
    check_sweep_size(int(np.prod(sizes, dtype=np.float64)) if sizes else 0, "this sweep")
    for key, val in ranged.items():
        axes[key] = parse_axis(key, val, num, log_spacing)
        first = axes[key][0]
        fixed[key] = first if key in NUMBER_KEYS else (first if isinstance(first, str) else f"{first:~}")
    if not axes:
        raise click.UsageError(
            "nothing to sweep: give a range such as --v0 '5 um/s..1000 um/s' "
            "or a list such as --b '0 s/m,100 s/m'"
        )
    if opts.get("beta") is not None and "beta" not in axes and opts.get("nu") is None:
        # a fixed beta must hold at every point: sweep it as a one-value axis so that the
        # mass follows the swept load, stiffness or friction coefficient
        axes["beta"] = [opts["beta"]]
    fixed["rtol"] = _to_float("rtol", opts["rtol"])
    fixed["atol"] = _to_float("atol", opts["atol"])
    params = build_parameters(fixed)
    from .io.output import OutputFolder

    folder, name = os.path.split(out_path)
    stem = os.path.splitext(name)[0]
    with OutputFolder(folder or ".", f"sweep {stem}", overwrite=overwrite) as out:
        # the outputs are checked before the (possibly long) sweep starts
        out.expect({name: "sweep"} | ({} if no_plot else _figure_names(stem)))
        ds = run_sweep(
            params, axes, rtol=fixed["rtol"], atol=fixed["atol"], progress=False if quiet else None
        )
        written = save_sweep(ds, name, out=out)
        paths = [] if no_plot else save_figure(_plot_sweep(ds, log_spacing), stem, out=out)
    click.echo(f"wrote {written} ({ds.amplitude.size} points, dimensions {dict(ds.sizes)})")
    if paths:
        click.echo("wrote " + ", ".join(paths))
    counts = {str(k): int(v) for k, v in zip(*np.unique(ds.regime.values, return_counts=True), strict=True)}
    click.echo(f"regimes: {counts}")


@main.command()
@click.argument("file", type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option(
    "--confidence",
    type=float,
    default=0.95,
    show_default=True,
    help="Confidence level of the slope interval.",
)
@click.option("--min-points", type=int, default=4, show_default=True, help="Fewest points for a verdict.")
@_handle_errors
def classify(file: str, as_json: bool, confidence: float, min_points: int) -> None:
    """Apply the amplitude-velocity criterion to a CSV of measured amplitudes.

    The CSV needs columns 'velocity' and 'amplitude', optionally 'amplitude_err',
    with units in brackets: velocity [um/s],amplitude [mN],amplitude_err [mN].
    Verdict: stick-slip (amplitude rises with velocity), pure-slip (it falls) or
    inconclusive (too few points, slope consistent with zero, non-monotonic).
    """
    from .data.criterion import classify_file

    res = classify_file(file, confidence=confidence, min_points=min_points)
    if as_json:
        click.echo(json.dumps(res.as_dict(), indent=2))
        return
    lo, hi = res.slope_ci
    click.echo(f"verdict   {res.verdict}")
    click.echo(f"slope     {res.slope:.4g}  ({100 * res.confidence:g}% CI [{lo:.4g}, {hi:.4g}])")
    click.echo(f"points    {res.n_points}")
    click.echo(f"reason    {res.reason}")


@main.command()
@model_options
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
    "cubic: alpha, gamma), with the criterion on trial.",
)
@click.option("--map-n", type=int, default=25, show_default=True, help="Values of the --map parameter.")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="Write regimes.json, bifurcation.png/.svg (and regime_map.nc, regime_map.png, criterion_map.png "
    "with --map) to this folder.",
)
@overwrite_option
@_handle_errors
def regimes(
    nu_min: float,
    nu_max: float,
    n_grid: int,
    as_json: bool,
    check: bool,
    map_spec: str | None,
    map_n: int,
    out_dir: str | None,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Find every branch (steady sliding, pure slip, stick-slip) over a range of nu and the regimes.

    Hopf points and their criticality, pure-slip orbits continued by shooting
    (stable and unstable), folds, grazing, the onset of stick-slip, and the
    intervals where each attractor exists (bistable where two coexist). The law
    is given as for 'stickslip cycle', without --nu; a physical set-up gives its
    law in dimensionless form (beta from --mass or --beta) and the intervals also
    in v0.
    """
    from .bifurcation.regimes import confirm
    from .bifurcation.regimes import regimes as compute_regimes
    from .io.jsonable import json_clean

    if opts.get("nu") is not None:
        raise click.UsageError("--nu: 'regimes' scans nu; give --nu-min and --nu-max instead")
    dim_law_given = any(opts.get(k) is not None for k in ("c", "p", "alpha", "gamma", "kinetic"))
    if dim_law_given:
        opts["nu"] = 1.0  # placeholder: only the law is used
    elif opts.get("v0") is None:
        opts["v0"] = "1 m/s"  # placeholder: only the law and beta are used
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
        from .bifurcation.regime_map import criterion_table, criterion_trial, regime_map

        name, sep, rng = map_spec.partition("=")
        if not sep:
            raise click.UsageError(f"--map={map_spec!r}: expected NAME=A..B, e.g. 'p=0.05..1.5'")
        try:
            values = parse_axis(name.strip(), rng.strip(), map_n, False)
            values = [float(v) for v in values]
        except ValueError as exc:
            raise click.UsageError(f"--map: {exc}") from None
        ds = regime_map(law, name.strip(), values, nu_min, nu_max, n_nu=n_grid)
        trial = criterion_trial(ds)
        result["criterion"] = criterion_table(trial)
    result = json_clean(result)  # NaN (no pure-slip attractor, no criterion verdict) -> null
    if out_dir is not None:
        from .dynamics.sweep import save_sweep
        from .io.output import OutputFolder, json_writer
        from .plots.figures import save_figure
        from .plots.regimes import plot_bifurcation, plot_criterion_map, plot_regime_map

        with OutputFolder(out_dir, "regimes", overwrite=overwrite) as out:
            out.write("regimes.json", "regimes", json_writer(result, "regimes"))
            save_figure(plot_bifurcation(d), "bifurcation", out=out)
            if trial is not None:
                save_sweep(trial, "regime_map.nc", kind="regime-map", out=out)
                save_figure(plot_regime_map(trial), "regime_map", out=out)
                save_figure(plot_criterion_map(trial), "criterion_map", out=out)
    if as_json:
        click.echo(json.dumps(result, indent=2))
    else:
        for h in d.hopf:
            click.echo(f"Hopf point      nu = {h.nu:.10g}  {h.criticality} (l1 = {h.l1:.4g})")
        for p in d.points:
            if p.kind == "hopf":
                continue
            what = f"amplitude {p.amplitude:.6g}" if np.isfinite(p.amplitude) else p.detail
            click.echo(f"{p.kind:<15} nu = {p.nu:.10g}  {what}")
        for iv in d.intervals:
            v0 = f"   v0 {iv.nu_min / beta:.4g} .. {iv.nu_max / beta:.4g} m/s" if beta else ""
            att = " + ".join(iv.attractors) if iv.regime == "bistable" else ""
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
    if checks and not all(c.agree for c in checks):
        click.echo("stickslip: some intervals were not confirmed by direct simulation", err=True)
        raise SystemExit(1)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
