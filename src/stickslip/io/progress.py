"""Progress bars of long computations (tqdm, on standard error)."""

from __future__ import annotations

import os
import sys
from typing import Any

__all__ = ["progress_bar", "show_progress"]


def show_progress(progress: bool | None) -> bool:
    """Decide whether to show a progress bar.

    Parameters
    ----------
    progress : bool or None
        True always, False never; None (the default of every long computation) on a
        terminal only, unless the environment sets ``STICKSLIP_NO_PROGRESS``.

    """
    if progress is not None:
        return bool(progress)
    if os.environ.get("STICKSLIP_NO_PROGRESS"):
        return False
    return sys.stderr.isatty()


def progress_bar(total: int, *, unit: str, desc: str, progress: bool | None) -> Any:
    """Return a tqdm bar on standard error, or None when :func:`show_progress` says no.

    A bar asked for explicitly (``progress=True``) shows at once; the default one
    after half a second, so that quick runs print nothing.
    """
    if not show_progress(progress):
        return None
    from tqdm.auto import tqdm

    delay = 0.0 if progress else 0.5
    return tqdm(total=total, unit=unit, desc=desc, delay=delay, file=sys.stderr, leave=False)
