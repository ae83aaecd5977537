"""``stickslip`` and ``python -m stickslip``: start the command line.

The command line loads numba's compiled kernels, pint and xarray before it can
parse an option (some seconds on a loaded machine). Ctrl-C in that time raised
``KeyboardInterrupt`` inside an import and printed a traceback; :func:`main`
ends it with one line, then by SIGINT itself, as Python does for an unhandled
Ctrl-C: a shell reports status 130 and a script's loop stops. (Python may already
have marked the interrupt unhandled, inside a C extension's start-up code, and
end by SIGINT anyway: so it always does.) Once the command runs, click turns
Ctrl-C into ``Aborted!`` (exit status 1).
"""

from __future__ import annotations

import os
import signal
import sys


def main() -> None:
    """Load the command line, then run it (the ``stickslip`` console script)."""
    try:
        from .cli.commands import main as command_line
    except KeyboardInterrupt:
        print("stickslip: interrupted while starting", file=sys.stderr, flush=True)
        if os.name == "posix":
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            os.kill(os.getpid(), signal.SIGINT)
        raise SystemExit(130) from None
    command_line()


if __name__ == "__main__":
    main()
