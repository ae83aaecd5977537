"""Command of the chains family: ``chain``."""

from __future__ import annotations

import math
import os
from typing import Any

import click
import numpy as np

from ..io.jsonable import dumps as dumps_json
from .errors import handle_errors
from .options import (
    OutPath,
    build_parameters,
    law_command,
    overwrite_option,
    scale_options,
    scale_report,
    warn_unwritten,
)

__all__ = ["chain", "register"]

_FIGURES = ("magnitude_frequency", "space_time", "recurrence")


@law_command(default_law="carlson-langer")  # the chain's law (Carlson & Langer 1989)
@click.option("--blocks", type=int, required=True, help="Number of blocks N.")
@click.option("--events", type=int, default=1000, show_default=True, help="Events to record.")
@click.option(
    "--ell",
    type=float,
    default=None,
    help="Coupling ell = sqrt(k_c/k_p) (dimensionless input; 1 when not given).",
)
@click.option(
    "--coupling", default=None, help="Coupling stiffness k_c with units, e.g. '100 N/m' (physical input)."
)
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help="Seed of the initial positions and thresholds (a whole number >= 0).",
)
@click.option(
    "--init",
    type=click.Choice(["random", "uniform"]),
    default="random",
    show_default=True,
    help="random: small seeded displacements; uniform: identical blocks at rest.",
)
@click.option(
    "--amplitude",
    type=float,
    default=0.01,
    show_default=True,
    help="Range of the random initial displacements (units of F_s/k_p).",
)
@click.option("--boundary", type=click.Choice(["free", "periodic"]), default="free", show_default=True)
@click.option(
    "--threshold-spread",
    type=float,
    default=0.0,
    show_default=True,
    help="Heterogeneous static thresholds 1 + s U(-1, 1), seeded.",
)
@click.option(
    "--backslip/--no-backslip",
    default=None,
    help="Allow backward slip (default: yes, except for the Carlson-Langer law).",
)
@click.option(
    "--transient", type=int, default=0, show_default=True, help="Events simulated first, not recorded."
)
@click.option(
    "--mc",
    default="auto",
    show_default=True,
    metavar="M|auto|maxc",
    help="Lower magnitude of the b-value fit: a number; auto (default), both ends by an objective "
    "rule: the lower end of each range the one of least Kolmogorov-Smirnov distance to its fit "
    "(Clauset-Shalizi-Newman), the widest range that passes KS by parametric bootstrap and one "
    "slope against two at p >= 0.1 with its events spread over a magnitude unit (a decade of "
    "moment), and no b-value where none passes (not a power law); maxc, the completeness "
    "magnitude by maximum curvature.",
)
@click.option("--m-max", type=float, default=None, help="Upper magnitude of the b-value fit.")
@click.option(
    "--events-as",
    type=click.Choice(["whole", "connected"]),
    default="whole",
    show_default=True,
    help="What an event of the statistics (b-value, magnitude-frequency) is: whole, from all blocks "
    "stuck to all stuck (slips in separate places add up); connected, each connected run of "
    "slipping blocks in it, with its own moment and block count (Carlson-Langer; kept in the "
    "catalogue as rupture_*).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option(
    "--out",
    "out_dir",
    type=OutPath(file_okay=False),
    default=None,
    help="Write catalog.nc (streamed), summary.json and the figures into this folder.",
)
@click.option("--resume", is_flag=True, help="Continue the interrupted run in --out (same command).")
@click.option("--no-plot", is_flag=True, help="No figures.")
@click.option("--quiet", is_flag=True, help="No progress bar.")
@click.option(
    "--seeds",
    default=None,
    metavar="A..B|A,B,C",
    help="An ensemble: one chain per seed (A..B includes both ends); each member's statistics, "
    "with --store (catalogues kept in it), --workers or --scheduler.",
)
@scale_options
@overwrite_option
@handle_errors
def chain(
    blocks: int,
    events: int,
    ell: float | None,
    coupling: str | None,
    seed: int,
    init: str,
    amplitude: float,
    boundary: str,
    threshold_spread: float,
    backslip: bool | None,
    transient: int,
    mc: str,
    m_max: float | None,
    events_as: str,
    as_json: bool,
    out_dir: str | None,
    resume: bool,
    no_plot: bool,
    quiet: bool,
    seeds: str | None,
    store: str | None,
    scheduler: str | None,
    workers: int | None,
    overwrite: bool,
    **opts: Any,
) -> None:
    """Simulate a Burridge-Knopoff chain of N blocks, exactly; an event catalogue and its statistics.

    Every block sticks in closed form or slips (integrated); events are located
    on the dense output. Dimensionless input (--nu, --ell) gives dimensionless
    output; physical input (--v0 --mass --stiffness --load --coupling) gives s and m.
    """
    from ..chains import Boundary, ChainParameters, static_thresholds
    from ..chains import chain as run_chain
    from ..io.output import OutputFolder
    from ..models import PhysicalParameters

    params1 = build_parameters(opts)
    if not 0.0 <= threshold_spread < 1.0:
        raise click.BadParameter(
            f"{threshold_spread!r}: expected a threshold spread in [0, 1)",
            param_hint="--threshold-spread",
        )
    phi = static_thresholds(blocks, threshold_spread, seed) if blocks >= 1 and seeds is None else None
    if isinstance(params1, PhysicalParameters):
        if ell is not None:
            raise click.UsageError("--ell is for dimensionless input; give --coupling with physical input")
        if coupling is None:
            raise click.UsageError("physical input needs --coupling (the stiffness between blocks)")
        params = ChainParameters.from_physical(
            params1,
            blocks=blocks,
            coupling=coupling,
            boundary=Boundary(boundary),
            thresholds=phi,
            backslip=backslip,
        )
    else:
        if coupling is not None:
            raise click.UsageError("--coupling is for physical input; give --ell with --nu")
        params = ChainParameters(
            blocks,
            params1.law,
            params1.nu,
            1.0 if ell is None else ell,
            boundary=Boundary(boundary),
            thresholds=phi,
            backslip=backslip,
        )
    # the usage errors first, then the warnings
    if seeds is None and (store or scheduler or workers):
        raise click.UsageError("--store, --scheduler and --workers go with --seeds (an ensemble)")
    if seeds is not None and resume:
        raise click.UsageError("--resume is for one chain's --out; an ensemble resumes from its --store")
    if seeds is not None and no_plot:
        click.echo("warning: --no-plot does nothing with --seeds (an ensemble draws no figure)", err=True)
    if out_dir is None:
        warn_unwritten(("overwrite",) if seeds is not None else ("no_plot", "overwrite"), "without --out")
    mc_ = _mc(mc)
    above = not isinstance(mc_, float) or (m_max is not None and m_max > mc_)
    if m_max is not None and not (math.isfinite(m_max) and above):
        raise click.UsageError(f"--m-max={m_max!r}: expected a finite magnitude above --mc ({mc})")
    _warn_unused_seed(init, threshold_spread, seeds is not None)
    if seeds is not None:
        fit = {"mc": mc_, "m_max": m_max, "events_as": events_as}
        _ensemble(params, events, seeds, threshold_spread, init, amplitude, transient, opts, fit, store,
                  scheduler, workers, quiet, as_json, out_dir, overwrite)  # fmt: skip
        return
    kw: dict[str, Any] = dict(
        init=init,
        seed=seed,
        amplitude=amplitude,
        transient=transient,
        rtol=opts["rtol"],
        atol=opts["atol"],
        mc=mc_,
        m_max=m_max,
        progress=False if quiet else None,
        events_as=events_as,
    )
    if out_dir is None:
        if resume:
            raise click.UsageError("--resume needs --out (the folder of the interrupted run)")
        res = run_chain(params, events, **kw)
        _report(res, as_json)
        return
    # the folder is made by OutputFolder below, which removes it again if the run is refused
    partial = os.path.join(out_dir, ".catalog.partial.nc")
    if resume and not os.path.exists(partial):
        if os.path.exists(os.path.join(out_dir, "catalog.nc")):
            raise click.UsageError(
                f"--resume: the run in {out_dir} is complete (catalog.nc), nothing to resume; "
                "run without --resume to replace it"
            )
        click.echo(f"stickslip: no interrupted run in {out_dir}: starting a new one", err=True)
    names = {"catalog.nc": "chain-catalog", "summary.json": "summary"}
    if not no_plot:
        names |= {f"{f}.{ext}": "figure" for f in _FIGURES for ext in ("png", "svg")}
    with OutputFolder(out_dir, "chain", overwrite=overwrite) as out:
        out.expect(names)
        # the folder's own working file (its outputs were checked above)
        res = run_chain(
            params, events, out=partial, resume=resume and os.path.exists(partial), overwrite=True, **kw
        )
        summary = res.summary()
        cat = res.catalog
        figs: list[Any] = []
        if not no_plot:
            from ..plots.chains import plot_magnitude_frequency, plot_recurrence, plot_space_time

            figs = [
                ("magnitude_frequency", plot_magnitude_frequency(_statistics_events(res), res.b)),
                ("space_time", plot_space_time(cat)),
                ("recurrence", plot_recurrence(cat)),
            ]
        cat.close()
        out.write("catalog.nc", "chain-catalog", lambda path: os.replace(partial, path))
        from ..io.output import json_writer

        out.write("summary.json", "summary", json_writer(_jsonable(summary), "summary"))
        if figs:
            from ..plots.figures import save_figure

            for stem, fig in figs:
                save_figure(fig, stem, out=out)
    _report(res, as_json, out_dir, figures=not no_plot)


def _warn_unused_seed(init: str, threshold_spread: float, ensemble: bool) -> None:
    """Warn where --seed or --amplitude is given and cannot change the run (or the members differ not)."""
    ctx = click.get_current_context()
    given = [
        f"--{name}"
        for name in ("seed", "amplitude")
        if ctx.get_parameter_source(name) is click.core.ParameterSource.COMMANDLINE
    ]
    if ensemble:
        if "--seed" in given:
            click.echo("warning: --seed is not used with --seeds (each member has its own seed)", err=True)
        if init == "uniform" and not threshold_spread:
            click.echo(
                "warning: with --init uniform and no --threshold-spread the members of --seeds are identical",
                err=True,
            )
        given = [g for g in given if g != "--seed"]
    if init != "uniform" or not given:
        return
    if "--seed" in given and threshold_spread != 0:
        given.remove("--seed")  # it seeds the thresholds
    if given:
        verb = "does" if len(given) == 1 else "do"
        what = "all blocks at rest at one place" + ("" if threshold_spread else ", equal thresholds")
        click.echo(f"warning: {' and '.join(given)} {verb} nothing with --init uniform ({what})", err=True)


def _jsonable(d: dict[str, Any]) -> dict[str, Any]:
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in d.items()}


def _report(res: Any, as_json: bool, out_dir: str | None = None, *, figures: bool = True) -> None:
    s = _jsonable(res.summary())
    if as_json:
        click.echo(dumps_json(s, indent=2))
    else:
        u = s["units"]
        click.echo(f"blocks               {s['blocks']}")
        click.echo(f"events               {s['events']}")
        click.echo(f"simulated time       {s['simulated_time']:.6g} [{u['time']}]")
        click.echo(f"mean recurrence      {_shown(s['mean_recurrence'])} [{u['time']}]")
        click.echo(f"mean moment          {_shown(s['mean_moment'])} [{u['length']}]")
        click.echo(f"largest event        {s['largest_event_blocks']} blocks")
        if u["length"] != "1":  # a magnitude is log10 of the moment in its unit: say which
            click.echo(f"magnitude            M = log10(moment / 1 {u['length']})")
        connected = s["events_as"] == "connected"
        if connected:
            click.echo(
                f"ruptures             {s['ruptures']} (connected runs of slipping blocks in the events: "
                "the events of the b-value)"
            )
        unit, without = (
            ("ruptures", "ruptures_without_magnitude")
            if connected
            else ("events", "events_without_magnitude")
        )
        if s[without]:
            click.echo(
                f"no magnitude         {s[without]} {unit} (a net backward or zero "
                "moment: the blocks' slips are signed), left out of the b-value"
            )
        verdict = s["b_value_verdict"]
        if s["b_value"] is None:
            # one line: no b-value at all (too few events), or none because no range is a power law
            shown = (
                f"undefined{verdict[len('no b-value') :]}" if verdict.startswith("no b-value") else verdict
            )
            click.echo(f"b-value              {shown}")
        else:
            top = "" if s["b_value_m_max"] is None else f" to {s['b_value_m_max']:.2f}"
            law = f"; {verdict}" if verdict else ""
            ks = "" if s["b_value_ks_p"] is None else f", KS p = {s['b_value_ks_p']:.2g}"
            click.echo(
                f"b-value              {s['b_value']:.4g} ± {_shown(s['b_value_err'])} "
                f"(M from {_shown(s['completeness_magnitude'], '.2f')}{top}, {s['b_value_range']}{ks}{law}; "
                f"error by bootstrap in blocks of {s['b_value_block']} {unit})"
            )
            click.echo(f"slope change         {_knee(s)}")
        click.echo(f"status               {s['status']}")
        if out_dir:
            click.echo(f"wrote {out_dir}/catalog.nc, summary.json{' and figures' if figures else ''}")
    if s["status"] != "ok":
        from ..core.results import ChainStatus

        click.echo(
            f"stickslip: the chain did not finish: {ChainStatus.from_label(s['status']).message}", err=True
        )
        raise SystemExit(1)


def _statistics_events(res: Any) -> Any:
    """Return the catalogue whose ``magnitude`` the b-value was fitted to: its events, or their ruptures."""
    if res.events_as != "connected":
        return res.catalog
    ruptures = res.catalog[["rupture_magnitude"]].rename(
        {"rupture_magnitude": "magnitude", "rupture": "event"}
    )
    ruptures.attrs = dict(res.catalog.attrs)
    return ruptures


def _knee(s: dict[str, Any]) -> str:
    """Return the most likely change of slope in the fitted range and the test of one slope, in words."""
    from ..chains.statistics import MIN_PART

    if s["b_value_slope_p"] is None or s["b_value_split"] is None:
        return f"not tested (fewer than {MIN_PART} events on either side of every cut of the range)"
    return (
        f"b = {_shown(s['b_value_lower'], '.4g')} below M = {s['b_value_split']:.2f}, "
        f"{_shown(s['b_value_upper'], '.4g')} above ({s['b_value_upper_events']} of the range's "
        f"events; one slope: p = {s['b_value_slope_p']:.2g})"
    )


def _shown(value: float | None, spec: str = ".6g") -> str:
    """Return a number of the summary as text, ``undefined`` where it has none (too few events)."""
    return "undefined" if value is None else format(value, spec)


def _mc(text: str) -> float | str | None:
    """``--mc``: a magnitude, ``auto`` or ``maxc`` (None: maximum curvature)."""
    if text in ("auto", "maxc"):
        return None if text == "maxc" else text
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise click.UsageError(f"--mc={text!r}: expected a finite magnitude, 'auto' or 'maxc'")
    return value


def _seeds(text: str) -> list[int]:
    try:
        if ".." in text:
            a, b = (int(x) for x in text.split(".."))
            if b < a:
                raise ValueError
            from ..chains.ensemble import MAX_MEMBERS  # the API's own bound, before the list is made

            if b - a + 1 > MAX_MEMBERS:  # 0..100000000000 would not fit in memory
                raise click.UsageError(
                    f"--seeds={text!r}: {b - a + 1} members; expected at most {MAX_MEMBERS} in one ensemble "
                    "(run more as ensembles of their own)"
                )
            seeds = list(range(a, b + 1))
        else:
            seeds = [int(x) for x in text.split(",")]
        if min(seeds) < 0:
            raise ValueError
        return seeds
    except ValueError:
        raise click.UsageError(
            f"--seeds={text!r}: expected A..B (0 <= A <= B) or A,B,C (whole numbers >= 0)"
        ) from None


def _ensemble(
    params: Any,
    events: int,
    seeds: str,
    spread: float,
    init: str,
    amplitude: float,
    transient: int,
    opts: dict[str, Any],
    fit: dict[str, Any],
    store: str | None,
    scheduler: str | None,
    workers: int | None,
    quiet: bool,
    as_json: bool,
    out_dir: str | None,
    overwrite: bool,
) -> None:
    """``stickslip chain --seeds``: an ensemble, one member per seed."""
    from ..chains import chain_ensemble
    from ..core.results import ChainStatus

    ds = chain_ensemble(
        params, events, _seeds(seeds), threshold_spread=spread, init=init, amplitude=amplitude,
        transient=transient, rtol=opts["rtol"], atol=opts["atol"], **fit, store=store, scheduler=scheduler,
        workers=workers, progress=False if quiet else None,
    )  # fmt: skip
    if store is not None:
        scale_report(ds)
        del ds.attrs["run"]
    if out_dir is not None:
        from ..io.netcdf import netcdf_writer
        from ..io.output import OutputFolder

        with OutputFolder(out_dir, "chain ensemble", overwrite=overwrite) as out:
            out.write("ensemble.nc", "chain-ensemble", netcdf_writer(ds, "chain-ensemble"))
    names = {m.code: m.value for m in ChainStatus}
    members = [
        {
            "seed": int(s),
            **{k: (v.item() if np.isfinite(v) else None) for k in ds.data_vars if k != "status"
               for v in [ds[k].sel(seed=s).values]},
            "status": names[int(ds["status"].sel(seed=s))],
        }
        for s in ds.seed.values
    ]  # fmt: skip
    b = ds["b_value"].values
    b_mean = float(np.nanmean(b)) if np.isfinite(b).any() else None
    b_std = float(np.nanstd(b, ddof=1)) if np.isfinite(b).sum() > 1 else None  # the sample spread
    # each member's own error (block bootstrap) beside the spread: far below it, the error understates
    err = ds["b_value_err"].values
    err_mean = float(np.nanmean(err)) if np.isfinite(err).any() else None
    summary = {
        "members": len(members),
        "b_value_mean": b_mean,
        "b_value_std": b_std,
        "b_value_err_mean": err_mean,
        "b_value_fit": ds.attrs["b_value_fit"],
        "events": int(ds["events"].sum()),
        "per_member": members,
    }
    if as_json:
        click.echo(dumps_json(summary, indent=2))
    else:
        click.echo(f"members              {summary['members']}")
        click.echo(f"events               {summary['events']}")
        click.echo(
            f"b-value              {_shown(b_mean, '.4g')} (spread {_shown(b_std, '.2g')} over seeds; "
            f"each member's error {_shown(err_mean, '.2g')} on average; fitted {ds.attrs['b_value_fit']})"
        )
        if out_dir:
            click.echo(f"wrote {out_dir}/ensemble.nc")
    bad = [m["seed"] for m in members if m["status"] != "ok"]
    if bad:
        click.echo(f"stickslip: {len(bad)} members did not finish (seeds {bad[:10]})", err=True)
        raise SystemExit(1)


def register(main: click.Group) -> None:
    """Add ``chain`` (a module-level click command) to ``main``."""
    main.add_command(chain)
