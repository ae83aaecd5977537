"""The ``stickslip`` click group: every command family registered on one group.

Loaded by :func:`stickslip.__main__.main` (the console script) and, on first use, by
``from stickslip.cli import main``; :mod:`stickslip.cli` itself imports nothing heavy.
"""

from __future__ import annotations

import signal
import threading
import warnings
from typing import Any

import click

from ..io.output import COMMAND_LINE
from . import bifurcation, chain, data, diagram, dynamics, explore, forced, paper, ratestate
from .options import OnceCommand, build_parameters, describe_parameters

__all__ = ["build_parameters", "describe_parameters", "main"]


#: the sections of ``stickslip --help``, in order, each with its commands in order
SECTIONS = (
    ("The paper", ("reproduce", "examples", "explore")),
    ("One block", ("cycle", "simulate", "sweep")),
    ("Measured records", ("analyze", "fit", "classify")),
    ("Bifurcation", ("regimes", "diagram")),
    ("Rate and state", ("ratestate", "ratestate-fit", "earthquake-cycles", "dulac")),
    ("Chains of blocks", ("chain",)),
    ("Forced oscillators", ("forced",)),
)


class SectionedGroup(click.Group):
    """A group whose help lists its commands by :data:`SECTIONS`, each description whole."""

    def invoke(self, ctx: click.Context) -> Any:
        """Run the command; a usage error is reported in one line, ``Error: ...``.

        click prints the usage and a ``--help`` hint above the message; without the context
        it prints the message alone, and ``COMMAND --help`` still shows the usage.
        """
        try:
            return super().invoke(ctx)
        except click.UsageError as exc:
            exc.ctx = None
            raise

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        names = self.list_commands(ctx)
        placed = {n for _, group in SECTIONS for n in group}
        sections = [*SECTIONS, ("Other", tuple(n for n in names if n not in placed))]
        formatter.write_paragraph()
        formatter.write_text(
            "Start here: 'stickslip reproduce' (the paper, about 2 min), 'stickslip examples' (the "
            "inputs the README's commands read), 'stickslip COMMAND --help'."
        )
        for title, group in sections:
            rows = []
            for name in group:
                cmd = self.get_command(ctx, name)
                if cmd is None or cmd.hidden:
                    continue
                rows.append((name, cmd.get_short_help_str(limit=10_000)))
            if rows:
                with formatter.section(title):
                    formatter.write_dl(rows)


@click.group(cls=SectionedGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="stickslip")
def main() -> None:
    """Friction oscillators: the one-block spring-slider, exact and fast."""
    warnings.showwarning = _one_line_warning
    ctx = click.get_current_context()
    ctx.meta[COMMAND_LINE] = True  # outputs record this command and its options (io.output)
    _exit_on_sigterm(ctx)


def _exit_on_sigterm(ctx: click.Context) -> None:
    """Make SIGTERM (``kill``, a batch scheduler's time limit) end a command as Ctrl-C does.

    Python's default for SIGTERM ends the process at once, skipping every ``finally``:
    an output folder would keep its hidden staging folder and a chain's partial catalogue
    would stay open. Raised as ``SystemExit(143)`` instead, the clean-up runs and an
    interrupted chain can be resumed (``--resume``). Only where SIGTERM still has its
    default handler, only in the main thread (where signal handlers live), and for
    the command only: the default comes back when it ends (a program or a test run
    that calls :func:`main` keeps its own SIGTERM).
    """
    if threading.current_thread() is not threading.main_thread():
        return
    if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _terminated)
        ctx.call_on_close(lambda: signal.signal(signal.SIGTERM, signal.SIG_DFL))


def _terminated(signum: int, frame: Any) -> None:
    # the same advice as Ctrl-C's, for every command: a sweep or map goes on with --store, a
    # chain with --resume
    click.echo(
        "stickslip: stopped by SIGTERM (the same command with --store, or a chain's with --resume, "
        "goes on where it stopped)",
        err=True,
    )
    raise SystemExit(128 + signum)


def _one_line_warning(message: Any, category: Any, filename: str, lineno: int, *args: Any, **kw: Any) -> None:
    """Print a warning as one ``warning:`` line on standard error (no file, no source line)."""
    click.echo(f"warning: {message}", err=True)


main.command_class = OnceCommand  # every command refuses a single-valued option given twice
for _family in (dynamics, paper, ratestate, data, bifurcation, diagram, forced, chain, explore):
    _family.register(main)
