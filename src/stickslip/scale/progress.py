"""Progress of a long job: points per second and the time left, in the terminal and from Python.

One module for every progress bar of the package: :func:`progress_bar` (tqdm on standard
error, on a terminal only by default) and, for jobs cut into blocks, :class:`Progress`.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

__all__ = ["Progress", "ProgressInfo", "ProgressLike", "progress_bar", "show_progress"]


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


@dataclass(frozen=True)
class ProgressInfo:
    """Where a job stands, as passed to a progress callback.

    Attributes
    ----------
    points, total_points : int
        Grid points done by this run, and to do in all (blocks found in the store excluded).
    blocks, total_blocks : int
        The same in blocks.
    elapsed : float
        Seconds since the run started.
    rate : float
        Points per second so far.
    eta : float
        Estimated seconds left (NaN before the first block).

    """

    points: int
    total_points: int
    blocks: int
    total_blocks: int
    elapsed: float
    rate: float
    eta: float

    @property
    def fraction(self) -> float:
        """Fraction of the points done."""
        return self.points / self.total_points if self.total_points else 1.0


#: ``progress=`` of a long job: True/False/None (terminal bar) or a callable taking a ProgressInfo
ProgressLike = bool | None | Callable[[ProgressInfo], Any]


class Progress:
    """Count finished blocks; draw a terminal bar and/or call the user's callback after each.

    Parameters
    ----------
    total_points, total_blocks : int
        What the run has to do.
    progress : bool, callable or None
        True: a bar always; False: none; None: a bar on a terminal (after half a
        second); a callable: called with a :class:`ProgressInfo` after each block
        (and no bar).
    desc : str
        Label of the bar.

    """

    def __init__(self, total_points: int, total_blocks: int, progress: ProgressLike, desc: str) -> None:
        self.total_points = int(total_points)
        self.total_blocks = int(total_blocks)
        self.points = 0
        self.blocks = 0
        self.t0 = time.perf_counter()
        self.callback = progress if callable(progress) else None
        self.bar = (
            None
            if self.callback is not None
            else progress_bar(self.total_points, unit="pt", desc=desc, progress=progress)  # type: ignore[arg-type]
        )

    def info(self) -> ProgressInfo:
        """Return where the run stands."""
        elapsed = time.perf_counter() - self.t0
        rate = self.points / elapsed if elapsed > 0 and self.points else 0.0
        eta = (self.total_points - self.points) / rate if rate > 0 else math.nan
        return ProgressInfo(
            self.points, self.total_points, self.blocks, self.total_blocks, elapsed, rate, eta
        )

    def update(self, points: int) -> None:
        """Count one finished block of ``points`` points."""
        self.blocks += 1
        if self.bar is not None:
            self.bar.set_postfix_str(f"block {self.blocks}/{self.total_blocks}", refresh=False)
        self.advance(points)

    def advance(self, points: int) -> None:
        """Count ``points`` more points done inside the current block."""
        self.points += int(points)
        if self.bar is not None:
            self.bar.update(points)
        if self.callback is not None:
            self.callback(self.info())

    def close(self) -> None:
        """Close the bar."""
        if self.bar is not None:
            self.bar.close()
