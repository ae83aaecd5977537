"""Warnings that point at the user's line, not at stickslip's own code.

A fixed ``stacklevel`` is right for one call path only: a law built in a script,
in a sweep or by the CLI reaches the warning through different depths of
stickslip's frames. :func:`warn` walks out of the package instead, so the warning
names the first frame outside it (a script's line, a notebook cell, click).
"""

from __future__ import annotations

import os
import sys
import warnings

__all__ = ["moved", "warn"]

_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def warn(message: str | Warning, category: type[Warning] = UserWarning) -> None:
    """Issue ``message`` as a warning attributed to the first caller outside stickslip.

    Parameters
    ----------
    message : str or Warning
        The warning's text (or a warning instance, whose class is then the category).
    category : type of Warning, optional
        The category for a text message. Default :class:`UserWarning`.

    """
    level = 2  # stacklevel 2 is this function's caller
    frame = sys._getframe(1)
    while frame is not None and _inside(frame.f_code.co_filename):
        if not _importing(frame.f_code.co_filename):  # warnings skips the import system's own frames
            level += 1
        frame = frame.f_back  # type: ignore[assignment]
    warnings.warn(message, category, stacklevel=level)


def _importing(filename: str) -> bool:
    """Whether a frame is the import system's (``<frozen importlib._bootstrap>``)."""
    return filename.startswith("<frozen importlib")


def _inside(filename: str) -> bool:
    """Whether a frame is stickslip's own or the import system's: not the user's."""
    return _importing(filename) or os.path.abspath(filename).startswith(_PACKAGE)


def moved(old: str, new: str) -> None:
    """Warn that the module ``old`` is now ``new``: a :class:`DeprecationWarning` at the user's import.

    A module that moved keeps its old path as a shim for one release; the warning
    names both paths, so the import line can be changed before the shim goes.
    """
    text = f"{old} is now {new}: import it from there (the old path goes in the next release)"
    warn(text, DeprecationWarning)
