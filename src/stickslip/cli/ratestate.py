"""Commands of the rate-and-state family: ``ratestate`` (laboratory protocols) and ``dulac``."""

from __future__ import annotations

import json
from typing import Any

import click

from .errors import handle_errors
from .options import out_dir_option, overwrite_option

__all__ = ["register"]

A_HELP = (
    "Rate-and-state direct effect a (dimensionless, typically 0.005-0.02; the paper's A): "
    "not the weakening law's a in s/m."
)
B_HELP = (
    "Rate-and-state evolution effect b (dimensionless, the paper's B): velocity weakening at steady "
    "state where b > a; not the weakening law's b in s/m."
)
DC_HELP = "Critical slip distance Dc (the paper's D0), e.g. '10 um'."


def register(main: click.Group) -> None:
    """Add the commands to ``main``."""

    @main.command()
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
    @click.option("--a", "a", type=float, required=True, help=A_HELP)
    @click.option("--b", "b", type=float, required=True, help=B_HELP)
    @click.option("--dc", required=True, help=DC_HELP)
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
    @click.option(
        "--steps", default=None, help="Velocity-step test: velocities, e.g. '1 um/s,10 um/s,1 um/s'."
    )
    @click.option("--displacement", default=None, help="Load-point displacement per slide (default 20 D0).")
    @click.option("--holds", default=None, help="Slide-hold-slide test: hold times, e.g. '1 s,10 s,100 s'.")
    @click.option("--v-slide", "v_slide", default=None, help="Slide velocity of the slide-hold-slide test.")
    @out_dir_option("Output folder for ratestate.nc and ratestate.png/.svg.")
    @overwrite_option
    @handle_errors
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
        from ..dynamics.sweep import save_sweep
        from ..plots.figures import plot_rate_state, save_figure
        from ..ratestate.model import RateStateParameters
        from ..ratestate.protocols import slide_hold_slide, velocity_steps

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
        from ..io.output import OutputFolder

        with OutputFolder(out_dir, "ratestate", overwrite=overwrite) as out:
            path = save_sweep(ds, "ratestate.nc", kind="ratestate", out=out)
            paths = save_figure(plot_rate_state(ds), "ratestate", out=out)
        click.echo(f"wrote {path}, {', '.join(paths)}")
        click.echo(f"friction from {float(ds.friction.min()):.6g} to {float(ds.friction.max()):.6g}")
        if "peak_friction_change" in ds:
            for t_h, dmu in zip(ds.hold_time.values, ds.peak_friction_change.values, strict=True):
                click.echo(f"hold {t_h:g} s: peak friction change {dmu:.6g}")
