"""The explorer in the browser: ``explore``."""

from __future__ import annotations

import click

from .errors import handle_errors
from .options import OnceCommand

__all__ = ["explore", "register"]


@click.command(cls=OnceCommand)
@click.option(
    "--port", type=click.IntRange(1, 65535), default=5006, show_default=True, help="Port to serve on."
)
@click.option(
    "--host",
    default="127.0.0.1",
    show_default=True,
    help="Address to listen on (the default serves this machine only).",
)
@click.option("--no-browser", is_flag=True, help="Do not open a browser; print the address.")
@click.option(
    "--law",
    default="weakening",
    show_default=True,
    help="The law shown first: a registered law's name or 'expr'.",
)
@click.option("--nu", type=float, default=0.01, show_default=True, help="The driving velocity shown first.")
@handle_errors
def explore(port: int, host: str, no_browser: bool, law: str, nu: float) -> None:
    """Explore the one-block model in the browser: sliders, live plots, the criterion.

    Serves a page on http://HOST:PORT/ (Bokeh server): choose a friction law
    (built-in or a formula) and its parameters, the driving velocity and the
    units, and see the spring force against time, the phase portrait, the
    amplitude-velocity curve with the paper's criterion and the regime
    diagram, recomputed by the engine at every change. The page gives the
    equivalent 'stickslip cycle' command and the motion as CSV. Ctrl-C stops it.
    """
    from ..explore import Setup, check_nu, default_params, law_names, serve

    if law not in law_names():
        raise click.BadParameter(f"{law!r}: expected one of {', '.join(law_names())}", param_hint="--law")
    try:
        check_nu(nu)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--nu") from None
    # the paper's F1 first; another law with its example parameters
    setup = Setup(nu=nu) if law == "weakening" else Setup(law=law, nu=nu, params=default_params(law))
    serve(port=port, host=host, open_browser=not no_browser, setup=setup)


def register(main: click.Group) -> None:
    """Add ``explore`` (a module-level click command) to ``main``."""
    main.add_command(explore)
