"""Commands of the measured-data family: ``examples``, ``analyze``, ``fit``, ``classify``."""

from __future__ import annotations

import json
import math
import warnings
from typing import Any

import click
import numpy as np

from ..io.jsonable import dumps as dumps_json
from ..units import FORCE_UNITS, VELOCITY_UNITS, readable_unit
from .errors import handle_errors
from .options import OnceCommand, OutPath, figure_names, out_dir_option, overwrite_option

__all__ = ["analyze", "classify", "examples", "fit", "register"]


def reading_options(func: Any) -> Any:
    """Add the options that say how a laboratory's files are read (variables, units, set-up).

    The command takes them as ``**reading`` and passes :func:`_reading` of them to the reader.
    """
    options = [
        click.option("--time", "time_name", default=None, help="The variable or column holding the time."),
        click.option("--force", "force_name", default=None, help="The variable or column holding the force."),
        click.option(
            "--normalised/--absolute",
            "normalised",
            default=None,
            help="The force is divided by the normal load (a friction coefficient, F/W) / is a force "
            "(default: by its name: Fnorm, mu are normalised).",
        ),
        click.option(
            "--time-unit", default=None, help="The time's unit where the file states none (default s)."
        ),
        click.option(
            "--force-unit", default=None, help="The force's unit where the file states none (default N)."
        ),
        click.option(
            "--name-pattern",
            default=None,
            help="Metadata from file names, e.g. 'k{stiffness}Nm_v{v0}' or 'k{stiffness:N/m}_v{v0:mm/s}' "
            "(bare fields: N/m, um/s, g, N).",
        ),
        click.option("--stiffness", default=None, help="Spring stiffness, e.g. '168 N/m' (the set-up's)."),
        click.option("--mass", default=None, help="Slider mass, e.g. '30.7 g' (the set-up's)."),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _reading(reading: dict[str, Any]) -> dict[str, Any]:
    """Return :func:`reading_options`' values as ``read_record``'s keywords (``options``, stiffness, mass)."""
    from ..io.formats import RecordOptions

    options = RecordOptions(
        reading["time_name"],
        reading["force_name"],
        reading["normalised"],
        reading["time_unit"],
        reading["force_unit"],
        reading["name_pattern"],
    )
    return {"options": options, "stiffness": reading["stiffness"], "mass": reading["mass"]}


@click.command(cls=OnceCommand)
@click.argument("folder", type=OutPath(file_okay=False), default="examples", required=False)
@overwrite_option
@handle_errors
def examples(folder: str, overwrite: bool) -> None:
    """Write example inputs into FOLDER (default ./examples): the files the README's commands read.

    A friction table (mu_v.csv), measured-style amplitudes (amplitudes.csv), a folder
    of force-time records (records/) and one record (record.csv), made by the model
    of the paper's zv set-up with a force sensor's noise (synthetic: a few seconds,
    always the same).
    """
    from ..data.examples import write_examples

    paths = write_examples(folder, overwrite=overwrite)
    click.echo(f"wrote {len(paths)} files into {folder}: mu_v.csv, amplitudes.csv, records/, record.csv")


@click.command(cls=OnceCommand)
@click.argument("source", type=click.Path(exists=False))
@out_dir_option("Output folder: summary.csv and figures.")
@click.option("--json", "as_json", is_flag=True, help="Print the verdict and summary as JSON.")
@click.option("--no-plot", is_flag=True, help="Write summary.csv only.")
@reading_options
@click.option("--v0", default=None, help="Driving velocity of every record (overrides the files').")
@click.option(
    "--load", default=None, help="Normal load of every record; 'weight' is the slider's (mass x g)."
)
@click.option(
    "--model",
    "model_law",
    default=None,
    help="The paper's law, 'mu_s=0.35, a=30 s/m, b=10 s/m', or a fit.json from 'stickslip fit': "
    "the model's regime at each record's set-up and over the (V, k) plane, beside the measured ones.",
)
@overwrite_option
@handle_errors
def analyze(
    source: str,
    out_dir: str,
    as_json: bool,
    no_plot: bool,
    overwrite: bool,
    v0: str | None,
    load: str | None,
    model_law: str | None,
    **reading: Any,
) -> None:
    """Measure a folder of force-time records (or one long table) and apply the criterion.

    SOURCE is a folder of records (CSV/TSV/text, MATLAB .mat, HDF5, .npz, .xlsx,
    TDMS; with index.csv giving 'file', 'v0 [unit]', 'load [unit]', 'stiffness
    [unit]', 'mass [unit]', or '# v0 = ...' header lines, a sidecar NAME.json, or
    --name-pattern), one record, or one table with a 'record' column. With the
    driving velocity, the slider's motion follows from the force: slip events,
    stick phases, the observed regime, the stiffness from the stick slopes and the
    mass. Writes summary.csv (one row per record), events.csv (one row per slip
    event), amplitude and period against driving velocity and load, and the
    measured regime diagram in the (V, k) plane; with --model, the model's regime
    at each record's set-up (summary.csv's model_* columns) and over that plane.
    """
    from ..data.model_plane import read_model_law
    from ..data.records import analyze_records, observed_line
    from ..io.output import OutputFolder
    from ..io.records import UnreadableRecord, read_records
    from ..plots.figures import plot_records, plot_regime_plane, save_figure

    law = None if model_law is None else read_model_law(model_law)
    with OutputFolder(out_dir, "analyze", overwrite=overwrite) as out:
        out.expect({"summary.csv": "records-summary", "events.csv": "records-events"})
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            records = read_records(source, on_error="warn", v0=v0, load=load, **_reading(reading))
        unread = {}
        for w in caught:  # a record that cannot be read is a row of the table; the rest are said
            if isinstance(w.message, UnreadableRecord):
                unread[w.message.name] = w.message.reason
            else:
                warnings.showwarning(w.message, w.category, w.filename, w.lineno)
        table, verdict, events = analyze_records(records, unreadable=unread, return_events=True)
        model = None
        if law is not None:
            from ..data.model_plane import model_regimes

            model = model_regimes(table, law)
            for col, values in model.columns.items():
                table[col] = values
        written = [
            out.write(
                "summary.csv",
                "records-summary",
                lambda p: table.to_csv(p, index=False, float_format="%.10g"),
            )
        ]
        if events is not None:
            written.append(
                out.write(
                    "events.csv",
                    "records-events",
                    lambda p: events.to_csv(p, index=False, float_format="%.10g"),
                )
            )
        if not no_plot:
            for name, fig in (plot_records(table) | plot_regime_plane(table, model)).items():
                written += save_figure(fig, name, out=out)
    if as_json:
        click.echo(
            dumps_json(
                {
                    "verdict": None if verdict is None else verdict.as_dict(),
                    "observed": observed_line(table, verdict),
                    **(
                        {}
                        if model is None
                        else {
                            "model": {
                                "law": model.law,
                                "mass_of_plane": {"value": model.mass, "unit": "kg"},
                                "load_of_plane": {"value": model.load, "unit": "N"},
                                "agree": model.agree,
                                "compared": model.compared,
                            }
                        }
                    ),
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
    # in units that suit the records (um/s or mm/s, mN or N; summary.csv and the JSON stay SI)
    shown = table[["name", "n_cycles"]].copy()
    for col, units in (
        ("v0 [m/s]", VELOCITY_UNITS),
        ("load [N]", FORCE_UNITS),
        ("amplitude [N]", FORCE_UNITS),
        ("period [s]", (("s", 1.0),)),
    ):
        unit, size = readable_unit(table[col], units)
        shown[f"{col.split(' [')[0]} [{unit}]"] = table[col] / size
    shown["stick_fraction"] = table["stick_fraction"]
    shown["observed"] = table["observed_regime"]
    click.echo(shown.to_string(index=False, float_format=lambda x: f"{x:.4g}"))
    if "regime" in table.columns and table["regime"].notna().any():
        click.echo(_motion_text(table))
    if model is not None:
        click.echo(_model_text(table, model))
    click.echo("(summary.csv holds these in SI units)")
    if verdict is None:
        read = table[~table["name"].isin(unread)]
        no_v0 = int(read["v0 [m/s]"].isna().sum())
        measured = int((table["v0 [m/s]"].notna() & table["amplitude [N]"].notna()).sum())
        why = (
            f"{no_v0} of {len(read)} records read have no driving velocity; give it in index.csv "
            "('v0 [unit]') or a '# v0 = ...' header line"
            if no_v0
            else f"it needs at least 2 measured records at different driving velocities, "
            f"and {measured} of {len(table)} could be measured"
        )
        click.echo(f"criterion: no verdict ({why})")
    else:
        used = table[table["in_verdict"]]
        loads = used["load [N]"].dropna().unique()
        at = f" at load {loads[0] * 1e3:.6g} mN" if len(loads) == 1 else ""
        measured = int((table["v0 [m/s]"].notna() & table["amplitude [N]"].notna()).sum())
        left = measured - len(used)
        other = f"; {left} measured at other loads left out" if left > 0 else ""
        # records with a warning stay in the verdict: say how many, next to it (three files in
        # mN labelled N can turn a folder's verdict, and their warnings scroll away)
        warned = int(used["warning"].map(lambda w: isinstance(w, str) and bool(w)).sum())
        other += f"; {warned} of them with a warning above" if warned else ""
        click.echo(f"criterion: {verdict.verdict} ({verdict.reason}); from {len(used)} records{at}{other}")
    seen = observed_line(table, verdict)
    if seen is not None:
        click.echo(seen)


def _motion_for_fit(rec: Any, method: str) -> Any:
    """Return the record's motion summary where the motion is what is fitted (None: the model's fit)."""
    from ..data.motion import measure_motion
    from ..io.errors import DataError

    if method == "auto" and (rec.v0 is None or rec.velocity is not None or rec.displacement is not None):
        return None
    try:
        _, _, summary = measure_motion(rec)
    except DataError:
        if method == "motion":
            raise
        return None
    if method == "auto" and summary.regime in ("periodic stick-slip", "undetermined"):
        return None
    return summary


def _print_motion_fit(summary: Any, out_dir: str, overwrite: bool, as_json: bool) -> None:
    from ..io.output import OutputFolder, json_writer

    d = summary.as_dict()
    result = {
        "method": "motion",
        "record": summary.name,
        "regime": summary.regime,
        "regime_reason": summary.regime_reason,
        "parameters": {
            "k": {
                "value": summary.stiffness,
                "error": summary.stiffness_error if math.isfinite(summary.stiffness_error) else None,
                "unit": "N/m",
                "source": summary.stiffness_source,
                "stated": summary.stiffness_nominal if math.isfinite(summary.stiffness_nominal) else None,
            },
            "m": {
                "value": summary.mass if math.isfinite(summary.mass) else None,
                "error": summary.mass_error if math.isfinite(summary.mass_error) else None,
                "unit": "kg",
                "source": summary.mass_source,
                "stated": summary.mass_nominal if math.isfinite(summary.mass_nominal) else None,
            },
        },
        "motion": d,
    }
    with OutputFolder(out_dir, "fit", overwrite=overwrite) as out:
        out.expect({"fit.json": "fit"})
        path = out.write("fit.json", "fit", json_writer(result, "fit"))
    if as_json:
        click.echo(dumps_json(result, indent=2))
        return
    k, m = result["parameters"]["k"], result["parameters"]["m"]
    err = f" +- {k['error']:.2g}" if k["error"] is not None else ""
    stated = f"; stated {k['stated']:.4g} N/m" if k["stated"] is not None else ""
    click.echo(f"k    = {k['value']:.5g}{err} N/m ({k['source']}{stated})")
    if m["value"] is None:
        click.echo(f"m    : {m['source']}")
    else:
        err = f" +- {1e3 * m['error']:.2g}" if m["error"] is not None else ""
        stated = f"; stated {1e3 * m['stated']:.4g} g" if m["stated"] is not None else ""
        click.echo(f"m    = {1e3 * m['value']:.4g}{err} g ({m['source']}{stated})")
    click.echo(f"regime: {summary.regime} ({summary.regime_reason})")
    click.echo(
        "the paper's model (a periodic orbit) is not fitted to this record: its slips are not periodic; "
        "--method waveform fits it all the same"
    )
    for note in summary.notes:
        click.echo(f"note: {note}")
    click.echo(f"wrote {path}")


def _motion_text(table: Any) -> str:
    """Return the records' motion as a table: regime, events, recurrence, stick, stiffness, mass."""
    rows = table[table["regime"].notna()]
    shown = rows[["name"]].copy()
    shown["regime"] = rows["regime"]
    shown["events"] = rows["n_events"]
    shown["recurrence [s]"] = rows["recurrence [s]"]
    shown["rec. CV"] = rows["recurrence_cv"]
    shown["period [s]"] = rows["period [s]"]
    shown["stick"] = rows["stick_fraction"]
    shown["k [N/m]"] = [
        f"{k:.4g} +- {e:.2g}" if math.isfinite(e) else f"{k:.4g}"
        for k, e in zip(rows["stiffness [N/m]"], rows["stiffness_error [N/m]"], strict=True)
    ]
    shown["(stated)"] = rows["stiffness_nominal [N/m]"]
    shown["m [g]"] = [
        f"{1e3 * m:.3g} +- {1e3 * e:.1g}" if math.isfinite(m) else "not resolved"
        for m, e in zip(rows["mass [kg]"], rows["mass_error [kg]"], strict=True)
    ]
    shown["(stated) [g]"] = rows["mass_nominal [kg]"] * 1e3
    drops = ", ".join(
        f"{n}: {1e3 * d:.3g} mN" for n, d in zip(rows["name"], rows["min_drop [N]"], strict=True)
    )
    text = "the slider's motion from the force (x = V t - F/k, total-variation denoised):\n"
    text += shown.to_string(index=False, float_format=lambda x: f"{x:.4g}")
    text += f"\nevents: drops of at least {drops} (5 noise deviations) counted"
    for name, reason in zip(rows["name"], rows["regime_reason"], strict=True):
        text += f"\nregime: {name}: {reason}"
    return text


def _model_text(table: Any, model: Any) -> str:
    """Return the model's regime beside the measured one, record by record, and the count."""
    shown = table[["name"]].copy()
    shown["measured"] = table["regime"] if "regime" in table.columns else None
    shown["stick"] = table["stick_fraction"]
    shown["model"] = table["model_regime"].fillna("(no set-up)")
    shown["model stick"] = table["model_stick_fraction"]
    shown["period [s]"] = table["period [s]"]
    shown["model period [s]"] = table["model_period [s]"]
    shown["agree"] = table["model_agrees"].map(lambda a: "-" if a is None or a != a else str(a).lower())
    ratio = (table["model_period [s]"] / table["period [s]"]).to_numpy(dtype=float)
    ratio = ratio[np.isfinite(ratio)]
    periods = (
        f"\nthe model's period over the measured: {ratio.min():.3g} to {ratio.max():.3g}"
        if ratio.size
        else ""
    )
    return (
        "the model at each record's driving velocity, stiffness, mass and load:\n"
        + shown.to_string(index=False, float_format=lambda x: f"{x:.4g}")
        + "\n"
        + model.line()
        + periods
    )


@click.command(cls=OnceCommand)
@click.argument("record_file", type=click.Path(exists=False, dir_okay=False))
@click.option("--v0", default=None, help="Driving velocity (overrides the file's '# v0 = ...').")
@click.option("--load", default=None, help="Normal load (overrides the file's '# load = ...').")
@click.option("--fit-b", is_flag=True, help="Also fit b (law F2); default F1 (b = 0).")
@click.option(
    "--method",
    type=click.Choice(["auto", "waveform", "features", "motion"]),
    default="auto",
    show_default=True,
    help="Fit the force waveform (started from cycle features), the cycle features only, or measure "
    "the stiffness and mass from the slider's motion (stick slopes, slips); auto: motion for a record "
    "that is not periodic stick-slip (the paper's model has a periodic orbit), waveform otherwise.",
)
@click.option(
    "--noise",
    default=None,
    help="Standard deviation of the force's noise, e.g. '0.4 mN', weighting the waveform fit "
    "(default: estimated from the record's second differences).",
)
@out_dir_option("Output folder: fit.json, fit.csv, fit_overlay.png/.svg.")
@click.option("--no-plot", is_flag=True, help="Do not draw the overlay figure.")
@click.option("--json", "as_json", is_flag=True, help="Print the fit as JSON.")
@reading_options
@overwrite_option
@handle_errors
def fit(
    record_file: str,
    v0: str | None,
    load: str | None,
    fit_b: bool,
    method: str,
    noise: str | None,
    out_dir: str,
    no_plot: bool,
    as_json: bool,
    overwrite: bool,
    **reading: Any,
) -> None:
    """Fit mu_s (the paper's mu0), a, k and the mass (and b) of the paper's model to a stick-slip record.

    By default the force waveform itself is fitted (residuals weighted by the record's
    noise, so the reduced chi-square says whether the model describes the record),
    starting from a fit on cycle features (peak and trough force, period, stick-ramp
    slope, drop time). Uncertainties, correlations and identifiability warnings.
    A real record whose slips are irregular is not the model's periodic orbit: there
    (--method motion, or auto) the stiffness comes from the stick slopes and the mass
    from the slips or the inertial oscillation, beside the stated values.
    """
    from ..data.fitting import fit_record
    from ..io.output import OutputFolder, json_writer, text_writer
    from ..io.records import read_record

    rec = read_record(record_file, v0=v0, load=load, **_reading(reading))
    if method in ("auto", "motion"):
        summary = _motion_for_fit(rec, method)
        if summary is not None:
            _print_motion_fit(summary, out_dir, overwrite, as_json)
            return
        method = "waveform"

    with OutputFolder(out_dir, "fit", overwrite=overwrite) as out:
        out.expect(
            {"fit.json": "fit", "fit.csv": "fit-parameters"}
            | ({} if no_plot else figure_names("fit_overlay"))
        )
        res = fit_record(rec, fit_b=fit_b, method=method, noise=noise)
        d = res.as_dict()
        rows = "".join(
            f"{name},{v['value']!r},{v['error']!r},{v['unit']}\n" for name, v in d["parameters"].items()
        )
        paths = [
            out.write("fit.json", "fit", json_writer(d, "fit")),
            out.write("fit.csv", "fit-parameters", text_writer("parameter,value,error,unit\n" + rows)),
        ]
        if not no_plot:
            from ..plots.figures import plot_fit_overlay, save_figure

            paths += save_figure(plot_fit_overlay(rec, res), "fit_overlay", out=out)
    if as_json:
        click.echo(dumps_json(d, indent=2))
        return
    for name, v in d["parameters"].items():
        unit = "" if v["unit"] in ("1", "") else f" {v['unit']}"  # mu_s is a number ('+- 1.9e-05 1')
        if v.get("at_bound"):
            click.echo(f"{name:4s} = 0 (at its bound; < {v['upper_limit_95']:.3g}{unit} at 95%)")
        elif v["error"] is None:
            click.echo(f"{name:4s} = {v['value']:.6g}{unit} (not constrained by the record)")
        else:
            click.echo(f"{name:4s} = {v['value']:.6g} +- {v['error']:.2g}{unit}")
    click.echo(
        f"reduced chi2 = {res.reduced_chi2:.3f} ({res.method} fit, {res.samples} "
        f"{'samples' if res.method == 'waveform' else 'features'}, noise {1e3 * res.noise:.3g} mN)"
    )
    if res.drift:
        err = f" +- {1e3 * res.drift_error:.2g}" if math.isfinite(res.drift_error) else ""
        click.echo(f"drift = {1e3 * res.drift:+.3g}{err} mN/s (zero at t = {res.drift_origin:.6g} s)")
    for w in res.warnings:
        click.echo(f"warning: {w}")
    click.echo("wrote " + ", ".join(paths))


@click.command(cls=OnceCommand)
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
@handle_errors
def classify(file: str, as_json: bool, confidence: float, min_points: int) -> None:
    """Apply the amplitude-velocity criterion to a CSV of measured amplitudes.

    The CSV needs columns 'velocity' and 'amplitude', optionally 'amplitude_err',
    with units in brackets: velocity [um/s],amplitude [mN],amplitude_err [mN].
    Verdict: stick-slip (amplitude rises with velocity), pure-slip (it falls) or
    inconclusive (too few points, slope consistent with zero, non-monotonic).
    """
    from ..data.criterion import classify_file

    res = classify_file(file, confidence=confidence, min_points=min_points)
    if as_json:
        click.echo(dumps_json(res.as_dict(), indent=2))
        return
    lo, hi = res.slope_ci
    click.echo(f"verdict   {res.verdict}")
    click.echo(f"slope     {res.slope:.4g}  ({100 * res.confidence:g}% CI [{lo:.4g}, {hi:.4g}])")
    click.echo(f"points    {res.n_points}")
    click.echo(f"reason    {res.reason}")


def register(main: click.Group) -> None:
    """Add the family's commands (module-level click commands) to ``main``, in this order."""
    main.add_command(examples)
    main.add_command(analyze)
    main.add_command(fit)
    main.add_command(classify)
