"""The paper's reproduction: ``reproduce``."""

from __future__ import annotations

import click

from .errors import handle_errors
from .options import OnceCommand, out_dir_option, overwrite_option

__all__ = ["register", "reproduce"]


@click.command(cls=OnceCommand, short_help="Reproduce the paper, figures and report.")
@out_dir_option("Output folder.")
@click.option("--quick", is_flag=True, help="A reduced version (fewer points per curve), for tests.")
@click.option(
    "--serial",
    is_flag=True,
    help="Compute everything in this process (by default the appendix and half the "
    "figures run in a second one).",
)
@overwrite_option
@handle_errors
def reproduce(out_dir: str, quick: bool, serial: bool, overwrite: bool) -> None:
    """Reproduce the paper: Figs. 1-3, parameter dependences, the criterion, a report.

    Writes reproduce.nc (every curve), each figure as PNG and SVG, report.md and a
    self-contained report.html into the output folder.
    """
    import time

    from ..paper import reproduce as run

    t0 = time.perf_counter()
    click.echo(
        f"reproducing the paper into {out_dir} in 5 stages: "
        + ("a quick run, about 1 min" if quick else "about 1 to 2.5 min on two cores")
        + " (the first run after an install also compiles the engines, cached afterwards)"
    )
    # the appendix in a second process: this entry point is safe to import (spawn)
    res = run(out_dir, quick=quick, overwrite=overwrite, parallel=not serial, notify=click.echo)
    click.echo(f"wrote {res.netcdf}")
    for paths in res.figures.values():
        click.echo(f"wrote {', '.join(paths)}")
    click.echo(f"wrote {res.report_md}, {res.report_html}")
    for c in res.claims:
        click.echo(f"claim {c.number:2d}: {c.grade} ({c.verdict})")
    click.echo(f"done in {time.perf_counter() - t0:.1f} s")


def register(main: click.Group) -> None:
    """Add ``reproduce`` (a module-level click command) to ``main``."""
    main.add_command(reproduce)
