"""``stickslip`` and ``python -m stickslip``: start the command line.

The command line loads numba's compiled kernels, pint and xarray before it can
parse an option (some seconds on a loaded machine). Ctrl-C in that time raised
``KeyboardInterrupt`` inside an import and printed a traceback; :func:`main`
ends it with one line, then by SIGINT itself, as Python does for an unhandled
Ctrl-C: a shell reports status 130 and a script's loop stops. (Python may already
have marked the interrupt unhandled, inside a C extension's start-up code, and
end by SIGINT anyway: so it always does.) Ctrl-C while a command runs ends the
same way, with one line saying that a store or a chain goes on where it stopped
(click's own ``Aborted!`` and status 1 let a shell's loop run its next command).
"""

from __future__ import annotations

import os
import signal
import sys
from typing import NoReturn

#: the line printed on Ctrl-C while a command runs
INTERRUPTED = (
    "stickslip: interrupted (the same command with --store, or a chain's with --resume, "
    "goes on where it stopped)"
)


#: the line printed on Ctrl-C while the command line loads
STARTING = "stickslip: interrupted while starting"


def main() -> None:
    """Load the command line, then run it (the ``stickslip`` console script)."""
    # Ctrl-C during the imports ends the process from the handler itself: a KeyboardInterrupt
    # raised there can land in importlib's weakref callbacks, where Python prints it as an
    # "Exception ignored" traceback and goes on importing. A shell that started this process
    # with SIGINT ignored (a background job) keeps it ignored.
    previous = signal.getsignal(signal.SIGINT)
    if previous is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, _interrupted_while_starting)
    try:
        from .cli.commands import main as command_line
    except KeyboardInterrupt:
        _end_by_sigint(STARTING)
    if previous is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, previous)
    import click

    try:
        code = command_line.main(standalone_mode=False)
    except click.Abort as exc:
        if isinstance(exc.__cause__, KeyboardInterrupt):
            _end_by_sigint(INTERRUPTED)
        click.echo("Aborted!", err=True)
        raise SystemExit(1) from None
    except click.ClickException as exc:
        exc.show()
        raise SystemExit(exc.exit_code) from None
    except KeyboardInterrupt:  # while click reported something
        _end_by_sigint(INTERRUPTED)
    raise SystemExit(code if isinstance(code, int) else 0)


def _interrupted_while_starting(signum: int, frame: object) -> None:
    """End the loading command line on SIGINT: one line, then end by SIGINT."""
    _end_by_sigint(STARTING)


def _end_by_sigint(message: str) -> NoReturn:
    """Print ``message`` and end the process by SIGINT (a shell's 130; its loop stops)."""
    print(message, file=sys.stderr, flush=True)
    if os.name == "posix":
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGINT)
    raise SystemExit(130)


if __name__ == "__main__":
    main()
