"""The store's error, and how a disk's refusal (full, read-only, no permission) is said in it.

Zarr may wrap the OSError of a refused write in its own exceptions (or in an
exception group from its event loop): :func:`disk_error` finds it, :func:`why`
says it in a few words for a one-line :class:`StoreError`.
"""

from __future__ import annotations

import errno

from ..io.errors import DataError

__all__ = ["StoreError", "disk_error", "why"]


class StoreError(DataError):
    """A store cannot be used: another job's, unreadable, or the disk refuses writes (one line).

    A :class:`~stickslip.io.errors.DataError` (so a :class:`ValueError`): the command
    line prints it as one ``Error:`` line.
    """


def disk_error(exc: BaseException) -> OSError | None:
    """Return the OSError behind ``exc`` (zarr may wrap it), or None."""
    seen: BaseException | None = exc
    while seen is not None:
        if isinstance(seen, OSError):
            return seen
        if isinstance(seen, BaseExceptionGroup):
            for sub in seen.exceptions:
                found = disk_error(sub)
                if found is not None:
                    return found
        seen = seen.__cause__ or seen.__context__
    return None


def why(err: OSError) -> str:
    """Say in a few words why the disk refused (``the disk is full``, ``permission denied``, ...)."""
    if err.errno in (errno.ENOSPC, errno.EDQUOT):
        return "the disk is full"
    if err.errno in (errno.EACCES, errno.EPERM):
        return "permission denied"
    if err.errno == errno.EROFS:
        return "the file system is read-only"
    return err.strerror or str(err)
