"""How the command line reports problems: one line each, with the right exit status."""

from __future__ import annotations

import errno
import functools
from collections.abc import Callable
from typing import Any

import click

from ..core.results import Status
from ..io.errors import DataError

__all__ = ["DataProblem", "fail_unless_ok", "handle_errors"]


class DataProblem(click.ClickException):
    """A file or record that cannot be used: one ``Error:`` line, no usage text, exit code 2."""

    exit_code = 2


def _os_message(exc: OSError) -> str:
    where = exc.filename or ""
    what = exc.strerror or str(exc)
    if exc.errno == errno.ENOSPC:
        what += " (the previous file, if any, is untouched)"
    return f"{where}: {what}" if where else what


def handle_errors(func: Callable[..., Any]) -> Callable[..., Any]:
    """Turn the library's exceptions into click's: data errors, bad values, failed runs, file errors."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except DataError as exc:  # a file or record: the options were fine, the data were not
            raise DataProblem(str(exc)) from None
        except ValueError as exc:
            raise click.UsageError(f"invalid value: {exc}") from None
        except RuntimeError as exc:  # a computation that failed (not a user mistake)
            raise click.ClickException(str(exc)) from None
        except OSError as exc:  # a file that cannot be read or written: name it
            raise click.ClickException(_os_message(exc)) from None

    return wrapper


def fail_unless_ok(status: str) -> None:
    """Exit with status 1 (after the output) when the computation did not finish, saying why."""
    if status != Status.OK:
        try:
            hint = Status.from_label(str(status)).message
        except ValueError:
            hint = ""
        click.echo(f"stickslip: the computation did not finish: {status}; {hint}", err=True)
        raise SystemExit(1)
