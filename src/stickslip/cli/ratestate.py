"""The rate-and-state commands: ``ratestate``, ``ratestate-fit``, ``earthquake-cycles``, ``dulac``."""

from __future__ import annotations

import math
import warnings
from typing import Any

import click

from ..io.jsonable import dumps as dumps_json
from ..ratestate.model import RateStateParameters
from .errors import handle_errors
from .options import OnceCommand, figure_names, out_dir_option, overwrite_option

__all__ = ["dulac", "earthquake_cycles", "ratestate", "ratestate_fit", "register"]

A_HELP = (
    "Rate-and-state direct effect a (dimensionless, typically 0.005-0.02; the paper's A): "
    "not the weakening law's a in s/m."
)
B_HELP = (
    "Rate-and-state evolution effect b (dimensionless, the paper's B): velocity weakening at steady "
    "state where b > a; not the weakening law's b in s/m."
)
DC_HELP = "Critical slip distance Dc (the paper's D0), e.g. '10 um'."


@click.command(cls=OnceCommand)
@click.option("--a", "a", type=float, default=None, help=A_HELP)
@click.option("--b", "b", type=float, default=None, help=B_HELP)
@click.option(
    "--kappa",
    type=float,
    default=None,
    help="Dimensionless stiffness kappa = k Dc / W (> 0), or --dc with --stiffness-per-load.",
)
@click.option("--dc", default=None, help=DC_HELP + " With --stiffness-per-load, instead of --kappa.")
@click.option("--stiffness-per-load", "kw", default=None, help="k/W, e.g. '1 1/mm' (with --dc).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@handle_errors
def dulac(
    a: float | None, b: float | None, kappa: float | None, dc: str | None, kw: str | None, as_json: bool
) -> None:
    """Dulac's criterion for the quasi-static Rice-Ruina model (the paper's appendix).

    Derives the dimensionless system and its divergence with sympy from the
    physical equations and prints them; with --a --b --kappa (or --dc and
    --stiffness-per-load instead of --kappa) says whether periodic orbits are
    excluded for those values. a and b are the rate-and-state direct and
    evolution effects (the paper's A and B), not the weakening law's a and b in s/m.
    """
    import sympy as sp

    from ..ratestate.dulac import derive, excluded, sign_verdict

    if (dc is None) != (kw is None):
        raise click.UsageError("--dc and --stiffness-per-load go together (kappa = k Dc / W)")
    if dc is not None:
        if kappa is not None:
            raise click.UsageError("give --kappa or --dc with --stiffness-per-load, not both")
        from ..units import parse_quantity

        d_c = parse_quantity(dc, "dc", "[length]", "10 um")
        k_w = parse_quantity(kw, "stiffness_per_load", "1 / [length]", "1 1/mm")
        kappa = float((d_c * k_w).to("").magnitude)
    given = [v is not None for v in (a, b, kappa)]
    if any(given) and not all(given):
        raise click.UsageError("give all of --a, --b and --kappa (or --dc --stiffness-per-load), or none")
    d = derive()
    out: dict[str, Any] = {
        "alpha_dot": sp.sstr(d.alpha_dot),
        "phi_dot": sp.sstr(d.phi_dot),
        "divergence": sp.sstr(d.divergence),
        "divergence_latex": sp.latex(d.divergence),
        "sign_factor": sp.sstr(d.sign_factor),
        "positive_factor": sp.sstr(d.positive_factor),
        "verdict": "no periodic orbits unless b - a - kappa = 0 (Dulac's criterion with g = 1 on "
        "the simply connected half-plane phi > 0)",
    }
    if all(given):
        assert a is not None and b is not None and kappa is not None
        out["values"] = {"a": a, "b": b, "kappa": kappa, "b - a - kappa": b - a - kappa}
        out["excluded"] = excluded(a, b, kappa)
        out["verdict"] = sign_verdict(a, b, kappa)
    if as_json:
        click.echo(dumps_json(out, indent=2))
        return
    click.echo(f"alpha' = {out['alpha_dot']}")
    click.echo(f"phi'   = {out['phi_dot']}")
    click.echo(f"divergence = {out['divergence']}")
    click.echo(f"LaTeX: {out['divergence_latex']}")
    click.echo(f"sign decided by: {out['sign_factor']}  (times {out['positive_factor']} > 0)")
    if "excluded" in out:
        click.echo(f"periodic orbits excluded: {'yes' if out['excluded'] else 'no'}")
    click.echo(f"verdict: {out['verdict']}")


@click.command(cls=OnceCommand)
@click.option("--a", "a", type=float, required=True, help=A_HELP)
@click.option(
    "--b",
    "b",
    type=float,
    multiple=True,
    required=True,
    help=B_HELP
    + " Repeat with --dc for several state variables: --b 0.0185 --dc '5 um' --b 0.0088 --dc '50 um'.",
)
@click.option("--dc", multiple=True, required=True, help=DC_HELP + " One per --b.")
@click.option("--v-ref", "v_ref", required=True, help="Reference velocity V_r, e.g. '1 um/s'.")
@click.option("--mu0", type=float, required=True, help="Steady friction at V_r.")
@click.option("--stiffness", default=None, help="Spring constant k (with --load), e.g. '1e4 N/m'.")
@click.option("--load", default=None, help="Normal load W, e.g. '10 N'.")
@click.option("--stiffness-per-load", "kw", default=None, help="k/W instead, e.g. '1 1/mm'.")
@click.option("--mass", default=None, help="Slider mass (inertial model), e.g. '1 kg'.")
@click.option(
    "--law",
    multiple=True,
    help="State evolution law: aging (default), slip, prz (Perrin-Rice-Zheng), nagata, or a formula "
    "for dPhi/dt in v, phi, dc, vr, mu_rate (e.g. '1 - (v*phi/dc)**2'); once for all state variables "
    "or once per --b.",
)
@click.option(
    "--nagata-c",
    "nagata_c",
    type=float,
    default=0.0,
    show_default=True,
    help="Nagata's coefficient c (with --law nagata).",
)
@click.option(
    "--radiation-damping",
    "eta",
    default=None,
    help="Damping eta/sigma added to friction as eta v (quasi-dynamic), e.g. '0.1 s/m'.",
)
@click.option(
    "--regularized",
    is_flag=True,
    help="Regularized friction A asinh(v/(2 V_r) exp(psi/A)) instead of the log form.",
)
@click.option("--steps", default=None, help="Velocity-step test: velocities, e.g. '1 um/s,10 um/s,1 um/s'.")
@click.option("--durations", default=None, help="Duration of each step, e.g. '10 s,30 s'.")
@click.option(
    "--displacements", default=None, help="Load-point displacement of each step, e.g. '100 um,300 um'."
)
@click.option("--displacement", default=None, help="Load-point displacement of every slide (default 20 Dc).")
@click.option("--holds", default=None, help="Slide-hold-slide test: hold times, e.g. '1 s,10 s,100 s'.")
@click.option("--v-slide", "v_slide", default=None, help="Slide velocity of the slide-hold-slide test.")
@click.option(
    "--history",
    "history",
    default=None,
    type=click.Path(dir_okay=False),
    help="Load-point history from a CSV: 'time [s]' and 'load-point velocity [um/s]' (held until the "
    "next row) or 'load-point displacement [um]' (linear between rows).",
)
@click.option(
    "--sample",
    default=None,
    help="Output at exactly 0, T, 2T, ... (e.g. '1 s') from the dense output, and at each change "
    "of the load-point velocity and the end (so that ratestate.csv changes it at its time); "
    "default 400 samples per step.",
)
@click.option(
    "--rtol",
    type=float,
    default=None,
    help="Relative tolerance (default 3e-13 quasi-static, 1e-10 inertial).",
)
@click.option(
    "--atol",
    type=float,
    default=None,
    help="Absolute tolerance on the spring friction and the log-states "
    "(default 1e-15 quasi-static; inertial 1e-12 on the friction, 1e-10 on the log-states).",
)
@out_dir_option("Output folder for ratestate.nc, ratestate.csv (a record) and ratestate.png/.svg.")
@overwrite_option
@handle_errors
def ratestate(
    a: float,
    b: tuple[float, ...],
    dc: tuple[str, ...],
    v_ref: str,
    mu0: float,
    stiffness: str | None,
    load: str | None,
    kw: str | None,
    mass: str | None,
    law: tuple[str, ...],
    nagata_c: float,
    eta: str | None,
    regularized: bool,
    steps: str | None,
    durations: str | None,
    displacements: str | None,
    displacement: str | None,
    holds: str | None,
    v_slide: str | None,
    history: str | None,
    sample: str | None,
    rtol: float | None,
    atol: float | None,
    out_dir: str,
    overwrite: bool,
) -> None:
    """Run a rate-and-state laboratory protocol: velocity steps, slide-hold-slide or a history.

    Several state variables: repeat --b and --dc. Example (rsfmodel's two-state test):
    stickslip ratestate --a 0.012 --b 0.0185 --dc "5 um" --b 0.0088 --dc "50 um" --v-ref "1 um/s"
    --mu0 0.6 --stiffness-per-load "3e-3 1/um" --steps "1 um/s,10 um/s" --durations "10 s,30 s"
    --sample "1 s"
    """
    from ..dynamics.sweep import save_sweep
    from ..plots.figures import plot_rate_state, save_figure
    from ..ratestate.protocols import simulate_rate_state, slide_hold_slide, step_history

    protocols = [x is not None for x in (steps, holds, history)]
    if sum(protocols) != 1:
        raise click.UsageError(
            "give one protocol: --steps VELOCITIES, --holds TIMES (with --v-slide) or --history FILE"
        )
    if len(b) != len(dc):
        raise click.UsageError(f"--b given {len(b)} time(s) and --dc {len(dc)}: give them in pairs")
    if law and len(law) not in (1, len(b)):
        raise click.UsageError(
            f"--law given {len(law)} times for {len(b)} state variables: give one or one each"
        )
    if steps is None and (durations or displacements):
        raise click.UsageError("--durations and --displacements go with --steps")
    # options of one protocol given to another reach nothing: refused, not dropped
    if holds is None and v_slide is not None:
        raise click.UsageError("--v-slide goes with --holds")
    if history is not None and displacement is not None:
        raise click.UsageError("--displacement goes with --steps or --holds, not --history")
    if (durations or displacements) and displacement is not None:
        raise click.UsageError("give --displacement (one for all) or --durations/--displacements")
    laws = law or ("aging",)
    if nagata_c != 0.0 and "nagata" not in laws:
        raise click.UsageError(f"--nagata-c goes with --law nagata (the laws here: {', '.join(laws)})")
    params = RateStateParameters(
        a=a,
        b=b if len(b) > 1 else b[0],
        dc=dc if len(dc) > 1 else dc[0],
        v_ref=v_ref,
        mu0=mu0,
        stiffness=stiffness,
        load=load,
        stiffness_per_load=kw,
        mass=mass,
        state_law=(law if len(law) > 1 else law[0]) if law else "aging",
        nagata_c=nagata_c,
        radiation_damping=eta,
        friction_form="regularized" if regularized else "log",
    )
    # with --sample, a row at each change of velocity too: ratestate.csv changes it at its time
    opts: dict[str, Any] = {"sample": sample, "at_changes": sample is not None}
    opts |= {"rtol": rtol, "atol": atol}
    if steps is not None:
        hist = step_history(
            _split(steps),
            durations=_split(durations) if durations else None,
            displacements=_split(displacements) if displacements else None,
            displacement=displacement,
            default_displacement=params.dc_max * 20,
        )
        ds = simulate_rate_state(params, hist, **opts)
    elif history is not None:
        from ..io.lab import read_lab_record

        rec = read_lab_record(history)
        if rec.velocity.size > 1 and rec.velocity[-1] != rec.velocity[-2]:
            warnings.warn(
                f"{history}: the last row's velocity ({rec.velocity[-1] * 1e6:g} um/s at "
                f"{rec.time[-1]:g} s) would hold after the end of the history: it is not used; "
                "add a row after it to give it a duration",
                stacklevel=1,
            )
        ds = simulate_rate_state(params, rec.history(), **opts)
    else:
        if v_slide is None:
            raise click.UsageError("--holds needs --v-slide")
        assert holds is not None
        ds = slide_hold_slide(params, v_slide, _split(holds), displacement=displacement, **opts)
    from ..io.lab import format_lab_record
    from ..io.output import OutputFolder, text_writer

    meta = {
        "mu0": repr(params.mu0),
        "v_ref": f"{params.v_ref.to('um/s').magnitude!r} um/s",
        "stiffness_per_load": f"{params.kw.to('1/um').magnitude!r} 1/um",
    }
    # the record says which law made it, the fit's or not: without it, ratestate-fit would fit
    # the aging law to a Nagata or formula law's record without a word
    distinct = list(dict.fromkeys(params.laws))
    meta["law"] = distinct[0] if len(distinct) == 1 else " + ".join(params.laws)
    if "nagata" in distinct:
        meta["nagata_c"] = repr(float(params.nagata_c))
    # with radiation damping or a mass the spring force is not the friction: the record holds
    # what a load cell measures (the spring force / W), and says what made it
    measured = ds.friction.values
    if params.radiation_damping is not None:
        meta["radiation_damping"] = f"{params.radiation_damping.to('s/m').magnitude!r} s/m"
    if params.mass is not None:
        meta["mass"] = f"{params.mass.to('kg').magnitude!r} kg"
    if params.radiation_damping is not None or params.mass is not None:
        measured = ds.spring_friction.values
    states = {
        f"{'state' if i == 0 else f'state_{i + 1}'} [s]": ds["state" if i == 0 else f"state_{i + 1}"].values
        for i in range(params.n_states)
    }
    text = format_lab_record(
        ds.time.values,
        ds.load_point_velocity.values,
        measured,
        {"slip velocity [um/s]": ds.slip_velocity.values * 1e6, **states},
        meta,
    )
    with OutputFolder(out_dir, "ratestate", overwrite=overwrite) as out:
        path = save_sweep(ds, "ratestate.nc", kind="ratestate", out=out)
        csv_path = out.write("ratestate.csv", "ratestate-record", text_writer(text))
        paths = save_figure(plot_rate_state(ds), "ratestate", out=out)
    click.echo(f"wrote {path}, {csv_path} (a record ratestate-fit reads), {', '.join(paths)}")
    click.echo(f"friction from {float(ds.friction.min()):.6g} to {float(ds.friction.max()):.6g}")
    if params.radiation_damping is not None or params.mass is not None:
        # the record's friction column is the spring force / W (what a load cell measures)
        sp = ds.spring_friction.values
        click.echo(f"spring force / W (the record's friction column) from {sp.min():.6g} to {sp.max():.6g}")
    if "peak_friction_change" in ds:
        for t_h, dmu in zip(ds.hold_time.values, ds.peak_friction_change.values, strict=True):
            click.echo(f"hold {t_h:g} s: peak friction change {dmu:.6g}")


_COMMANDLINE = click.core.ParameterSource.COMMANDLINE


def _split(text: str) -> list[str]:
    return [x.strip() for x in text.split(",") if x.strip()]


@click.command("ratestate-fit", cls=OnceCommand)
@click.argument("record_file", type=click.Path(dir_okay=False))
@click.option("--mu0", type=float, default=None, help="Steady friction at V_r (else '# mu0 = ...').")
@click.option("--v-ref", "v_ref", default=None, help="Reference velocity V_r (else '# v_ref = ...').")
@click.option(
    "--stiffness-per-load",
    "kw",
    default=None,
    help="k/W, e.g. '1e-3 1/um' (else '# stiffness_per_load = ...'); the start with --fit-stiffness.",
)
@click.option(
    "--law",
    type=click.Choice(["aging", "slip", "prz"]),
    default=None,
    help="State evolution law (else '# law = ...', else aging).",
)
@click.option(
    "--states",
    type=click.IntRange(1, 2),
    default=1,
    show_default=True,
    help="Number of state variables: 2 fits a second b and Dc.",
)
@click.option("--fit-stiffness", is_flag=True, help="Fit k/W too.")
@click.option(
    "--detrend",
    type=click.Choice(["linear", "offset", "none"]),
    default="linear",
    show_default=True,
    help="Fit a friction offset and a slope in load-point displacement with the parameters "
    "(linear), the offset only, or neither (mu0 as given).",
)
@click.option("--window", default=None, help="Fit only the samples between two times, e.g. '50 s,400 s'.")
@click.option(
    "--max-seconds",
    type=click.FloatRange(min=0.0, min_open=True),
    default=300.0,
    show_default=True,
    help="Give up after this much wall time (s), saying what to check.",
)
@out_dir_option("Output folder: ratestate_fit.json, ratestate_fit.png/.svg.")
@click.option("--no-plot", is_flag=True, help="Do not draw the overlay figure.")
@click.option("--json", "as_json", is_flag=True, help="Print the fit as JSON.")
@overwrite_option
@handle_errors
def ratestate_fit(
    record_file: str,
    mu0: float | None,
    v_ref: str | None,
    kw: str | None,
    law: str | None,
    states: int,
    fit_stiffness: bool,
    detrend: str,
    window: str | None,
    max_seconds: float,
    out_dir: str,
    no_plot: bool,
    as_json: bool,
    overwrite: bool,
) -> None:
    """Fit rate-and-state a, b, Dc (a second b, Dc; k/W) to a velocity-step or slide-hold-slide record.

    The record: 'time [s]', 'load-point velocity [um/s]' (or 'load-point displacement
    [um]') and 'friction [1]', with '# mu0 = 0.6', '# v_ref = 1 um/s',
    '# stiffness_per_load = 1e-3 1/um' and '# law = aging' header lines or the options.
    Errors, correlations, identifiability warnings and the reduced chi-squared.
    """
    from ..io.lab import read_lab_record
    from ..io.output import OutputFolder, json_writer
    from ..ratestate.fitting import fit_rate_state

    win = None
    if window is not None:
        parts = _split(window)
        if len(parts) != 2:
            raise click.UsageError(f"--window {window!r}: expected two times, e.g. '50 s,400 s'")
        win = (parts[0], parts[1])
    with OutputFolder(out_dir, "ratestate-fit", overwrite=overwrite) as out:
        out.expect(
            {"ratestate_fit.json": "ratestate-fit"} | ({} if no_plot else figure_names("ratestate_fit"))
        )
        rec = read_lab_record(record_file, need_friction=True)
        res = fit_rate_state(
            rec, mu0=mu0, v_ref=v_ref, stiffness_per_load=kw, law=law, n_states=states,
            fit_stiffness=fit_stiffness, detrend=detrend, window=win, max_seconds=max_seconds,
        )  # fmt: skip
        d = res.as_dict()
        paths = [out.write("ratestate_fit.json", "ratestate-fit", json_writer(d, "ratestate-fit"))]
        if not no_plot:
            from ..plots.figures import plot_rate_state_fit, save_figure

            paths += save_figure(plot_rate_state_fit(res), "ratestate_fit", out=out)
    if as_json:
        click.echo(dumps_json(d, indent=2))
        return
    for name, v in d["parameters"].items():
        err = "nan" if v["error"] is None else f"{v['error']:.2g}"
        unit = "" if v["unit"] in ("1", "") else f" {v['unit']}"  # a and b are numbers, no '1'
        click.echo(f"{name:18s} = {v['value']:.6g} +- {err}{unit}")
    click.echo(f"reduced chi2 = {res.reduced_chi2:.3f} ({res.samples} samples, noise {res.noise:.3g})")
    for w in res.warnings:
        click.echo(f"warning: {w}")
    click.echo("wrote " + ", ".join(paths))


@click.command("earthquake-cycles", cls=OnceCommand)
@click.option("--duration", default="3000 yr", show_default=True, help="Simulated time.")
@click.option("--a", "a", type=float, default=0.010, show_default=True, help="Direct effect a.")
@click.option("--b", "b", type=float, default=0.015, show_default=True, help="Evolution effect b.")
@click.option("--dc", default="8 mm", show_default=True, help="Critical slip distance Dc.")
@click.option("--normal-stress", default="50 MPa", show_default=True, help="Effective normal stress.")
@click.option("--plate-rate", default="1e-9 m/s", show_default=True, help="Plate (loading) rate.")
@click.option("--f0", type=float, default=0.6, show_default=True, help="Reference friction at V0.")
@click.option("--v0", default="1e-6 m/s", show_default=True, help="Reference slip rate V0.")
@click.option("--eta", default="4.62 MPa*s/m", show_default=True, help="Radiation damping G/(2 c_s).")
@click.option("--stiffness", default=None, help="Spring stiffness k, e.g. '1.5e7 Pa/m'.")
@click.option(
    "--stiffness-ratio",
    type=float,
    default=0.5,
    show_default=True,
    help="k / k_c when --stiffness is not given (below 1: earthquake cycles).",
)
@click.option("--mass", default=None, help="Mass per area of the inertial slider (default eta^2/k).")
@click.option(
    "--inertial/--no-inertial",
    default=False,
    show_default=True,
    help="Run the inertial slider beside the quasi-dynamic one.",
)
@click.option("--v-event", default="1 mm/s", show_default=True, help="Slip rate above which an event runs.")
@click.option("--rtol", type=float, default=1e-8, show_default=True, help="Relative tolerance.")
@out_dir_option(
    "Output folder: cycles.nc (cycles_inertial.nc), catalog_quasi-dynamic.csv (catalog_inertial.csv), "
    "cycles.json, cycles.png/.svg."
)
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
@overwrite_option
@handle_errors
def earthquake_cycles(
    duration: str, a: float, b: float, dc: str, normal_stress: str, plate_rate: str, f0: float, v0: str,
    eta: str, stiffness: str | None, stiffness_ratio: float, mass: str | None, inertial: bool,
    v_event: str, rtol: float, out_dir: str, as_json: bool, overwrite: bool,
) -> None:  # fmt: skip
    """Earthquake cycles of a rate-and-state spring-slider (SEAS BP1's friction by default).

    The quasi-dynamic slider (radiation damping eta) for thousands of years, steps from
    years down to milliseconds through each event; a catalog (time, peak slip rate,
    slip, recurrence, stress drop), the slip and energy budgets, the spring-slider
    estimate, and with --inertial the slider with a mass beside it.
    """
    from ..io.output import OutputFolder, json_writer, text_writer
    from ..plots.figures import plot_earthquake_cycles, save_figure
    from ..ratestate.cycles import YEAR, SpringSliderFault, recurrence_estimate
    from ..ratestate.cycles import earthquake_cycles as run_cycles

    ctx = click.get_current_context()
    if stiffness is not None and ctx.get_parameter_source("stiffness_ratio") is _COMMANDLINE:
        raise click.UsageError("give --stiffness or --stiffness-ratio, not both")
    if mass is not None and not inertial:
        raise click.UsageError("--mass is the inertial slider's: give --inertial with it")
    fault = SpringSliderFault(
        a=a, b=b, dc=dc, normal_stress=normal_stress, plate_rate=plate_rate, f0=f0, v0=v0, eta=eta,
        stiffness=stiffness, stiffness_ratio=stiffness_ratio, mass=mass,
    )  # fmt: skip
    runs = [run_cycles(fault, duration, v_event=v_event, rtol=rtol)]
    if inertial:
        runs.append(run_cycles(fault, duration, v_event=v_event, rtol=rtol, inertial=True))
    summary: dict[str, Any] = {}
    for run in runs:
        s = run.summary()
        est = recurrence_estimate(fault, s["peak_slip_rate"]) if s["events"] else {}
        summary[run.model] = {
            **s,
            "estimate": {
                "stress_drop_MPa": est.get("stress_drop", float("nan")) / 1e6,
                "slip_m": est.get("slip", float("nan")),
                "recurrence_yr_lower_bound": est.get("recurrence", float("nan")) / YEAR,
            },
            "budget": {k: float(v) for k, v in run.budget.items()},
            "steps": run.steps,
            "seconds": run.seconds,
            "slip_rate_range_m_s": _slip_rate_range(run),
        }
    with OutputFolder(out_dir, "earthquake-cycles", overwrite=overwrite) as out:
        paths = []
        for run in runs:
            stem = "cycles" if run.model == "quasi-dynamic" else "cycles_inertial"
            ds = run.series.assign(run.catalog.rename({"slip": "event_slip"}))
            from ..dynamics.sweep import save_sweep
            from ..io.tables import frame_with_units

            paths.append(save_sweep(ds, f"{stem}.nc", kind="earthquake-cycles", out=out))
            paths.append(
                out.write(
                    f"catalog_{run.model}.csv",
                    "catalog",
                    text_writer(frame_with_units(run.catalog).to_csv(index=False)),
                )
            )
        paths.append(out.write("cycles.json", "summary", json_writer(summary, "earthquake-cycles")))
        peak0 = runs[0].summary()["peak_slip_rate"]
        est0 = recurrence_estimate(fault, peak0) if math.isfinite(peak0) else None
        paths += save_figure(plot_earthquake_cycles(runs, est0), "cycles", out=out)
    if as_json:
        click.echo(dumps_json(summary, indent=2))
        return
    for model, s in summary.items():
        e = s["estimate"]
        if not s["events"]:
            click.echo(
                f"{model}: no event after the spin-up reached v_event = {v_event} (the slip "
                f"rate peaked at {s['slip_rate_range_m_s'][1]:.3g} m/s): give a lower --v-event "
                "or a longer run"
            )
            continue
        click.echo(
            f"{model}: {s['events']} events after the spin-up, recurrence {s['recurrence_yr']:.4g} yr "
            f"(estimate >= {e['recurrence_yr_lower_bound']:.4g}), slip {s['slip_m']:.4g} m (estimate "
            f"{e['slip_m']:.4g}), peak slip rate {s['peak_slip_rate']:.3g} m/s, stress drop "
            f"{s['stress_drop_MPa']:.3g} MPa (estimate {e['stress_drop_MPa']:.3g})"
        )
        bud = s["budget"]
        lo, hi = s["slip_rate_range_m_s"]
        click.echo(
            f"  slip budget closed to {bud['slip_error']:.1e}, "
            f"energy budget to {bud['energy_error']:.1e}; "
            f"{s['steps']} steps in {s['seconds']:.2f} s; slip rate from {lo:.2g} to {hi:.2g} m/s"
        )
    click.echo("wrote " + ", ".join(paths))


def _slip_rate_range(run: Any) -> list[float]:
    """Lowest and highest slip rate (m/s): the samples', and the events' peaks between samples.

    The samples alone would put the top below the catalogue's own peak slip rate (located on
    the dense output) in the same JSON.
    """
    import numpy as np

    rate = run.series.slip_rate.values
    peaks = run.catalog.peak_slip_rate.values
    top = float(np.nanmax(np.concatenate([rate, peaks]))) if peaks.size else float(np.nanmax(rate))
    return [float(np.nanmin(rate)), top]


def register(main: click.Group) -> None:
    """Add the family's commands (module-level click commands) to ``main``, in this order."""
    main.add_command(ratestate_fit)
    main.add_command(earthquake_cycles)
    main.add_command(dulac)
    main.add_command(ratestate)


def register_fit(main: click.Group) -> None:
    """Add ``ratestate-fit`` (:data:`ratestate_fit`) to ``main``."""
    main.add_command(ratestate_fit)


def register_cycles(main: click.Group) -> None:
    """Add ``earthquake-cycles`` (:data:`earthquake_cycles`) to ``main``."""
    main.add_command(earthquake_cycles)
