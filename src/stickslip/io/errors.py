"""Errors about data: a file that cannot be read, a record that cannot be measured, an output in the way."""

from __future__ import annotations

__all__ = ["DataError"]


class DataError(ValueError):
    """A file or a record is not what stickslip can use; the message names the file and the place.

    A subclass of :class:`ValueError`, so code that catches bad values catches it; the
    command line prints it as one ``Error:`` line (no usage text: the options were fine,
    the data were not).
    """
