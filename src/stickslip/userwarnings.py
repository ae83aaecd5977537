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

__all__ = ["warn"]

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
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE):
        frame = frame.f_back  # type: ignore[assignment]
        level += 1
    warnings.warn(message, category, stacklevel=level)
