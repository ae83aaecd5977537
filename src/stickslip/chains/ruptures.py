"""The connected ruptures of a chain's events, and the events whose slips are in pieces.

An event of a chain runs from one moment when every block sticks to the next. On a
long chain that moment is rare, and slips far apart, unrelated ruptures, fall into one
event (:func:`ruptures_in_pieces` counts such events). Carlson and Langer's event is
one connected run of slipping blocks: :func:`connected_ruptures` splits the events into
those runs (:class:`Ruptures`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from .magnitudes import FloatArray, _floats

__all__ = ["Ruptures", "connected_ruptures", "ruptures_in_pieces"]


def ruptures_in_pieces(
    n_blocks: npt.ArrayLike,
    first_block: npt.ArrayLike,
    last_block: npt.ArrayLike,
    slips: npt.ArrayLike | None = None,
    *,
    periodic: bool = False,
) -> tuple[int, int]:
    """Count the events whose slipping blocks are not one connected stretch of the chain.

    An event runs from one moment when every block sticks to the next. On a long
    chain that moment is rare, and slips far apart, unrelated ruptures, fall into one
    event (764 of 1500 events of 100 Carlson-Langer blocks; one event of 12 blocks
    spread from block 2 to block 992 on 1000). Carlson and Langer count
    connected clusters instead; a magnitude-frequency law of such events is not theirs.

    Parameters
    ----------
    n_blocks, first_block, last_block : array_like
        The catalogue's columns: blocks that slipped and their extent.
    slips : array_like, optional
        ``slip(recorded_event, block)`` of the first events (NaN rows unrecorded);
        needed on a periodic chain, where the extent does not tell a stretch across
        the ends from two pieces.
    periodic : bool, optional
        The chain's ends are joined.

    Returns
    -------
    (int, int)
        Events in pieces, and events checked (all on a free chain; the recorded ones
        on a periodic chain).

    """
    nb = np.asarray(n_blocks, dtype=np.int64)
    if not periodic:
        span = np.asarray(last_block, dtype=np.int64) - np.asarray(first_block, dtype=np.int64) + 1
        return int(np.count_nonzero(nb < span)), int(nb.size)
    if slips is None:
        return 0, 0
    rows = np.asarray(slips, dtype=float)
    rows = rows[np.all(np.isfinite(rows), axis=1)] if rows.ndim == 2 else np.empty((0, 0))
    moved = rows != 0.0
    # pieces on a ring: the places where a stuck block is followed by a slipping one
    starts = np.count_nonzero(moved & ~np.roll(moved, 1, axis=1), axis=1)
    return int(np.count_nonzero(starts > 1)), int(rows.shape[0])


class Ruptures(NamedTuple):
    """The connected ruptures of events (:func:`connected_ruptures`), one entry per rupture.

    Attributes
    ----------
    event : ndarray of int
        The event (row of the slips) each rupture belongs to; ruptures in event order, then
        by their first block.
    first_block, last_block : ndarray of int
        The rupture's ends (0-based); on a ring a rupture across the ends has
        ``last_block < first_block``.
    n_blocks : ndarray of int
        Blocks that slipped in the rupture.
    moment : ndarray of float
        Sum of its blocks' slips.

    """

    event: npt.NDArray[np.int64]
    first_block: npt.NDArray[np.int64]
    last_block: npt.NDArray[np.int64]
    n_blocks: npt.NDArray[np.int64]
    moment: FloatArray


def connected_ruptures(slips: npt.ArrayLike, *, periodic: bool = False) -> Ruptures:
    """Split events into connected ruptures: each run of neighbouring blocks that slipped.

    Carlson and Langer (1989) count an event as a connected cluster of slipping blocks;
    an event of a chain (from all stuck to all stuck) may hold several, separated by
    blocks that never slipped, and on a long chain at a fast drive it often does (5 168 of
    10 000 events of 100 Carlson-Langer blocks at ``nu = 0.01``, ``ell = 10``). Each run is one
    rupture here, with its own moment (the sum of its blocks' slips) and block count.
    A block slipped where its slip is not zero. The split is by place only: a run
    that slipped twice in one event (a rupture, then another over the same blocks)
    stays one rupture.

    Parameters
    ----------
    slips : array_like, shape (events, blocks)
        Each block's slip in each event (the catalogue's ``slip``); every value finite.
    periodic : bool, optional
        The chain's ends are joined: a run through the last block and the first is one.

    Returns
    -------
    Ruptures

    """
    s = _floats("slips", slips)
    if s.ndim != 2:
        raise ValueError(f"slips: shape {s.shape}; expected (events, blocks), each block's slip per event")
    if not np.isfinite(s).all():
        row = int(np.flatnonzero(~np.isfinite(s).all(axis=1))[0])
        raise ValueError(
            f"slips[{row}]: not finite (an event whose slips were not recorded); expected finite slips"
        )
    e, n = s.shape
    moved = s != 0.0
    edges = np.diff(np.pad(moved, ((0, 0), (1, 1))).astype(np.int8), axis=1)
    event, first = np.nonzero(edges == 1)  # row by row, left to right
    _, end = np.nonzero(edges == -1)  # one past each run's last block, in the same order
    # a run's slips and the zeros up to the next run's start sum to its moment exactly
    starts = event * n + first
    moment = np.add.reduceat(s.ravel(), starts) if starts.size else np.zeros(0)
    count = end - first
    last = end - 1
    if periodic and n > 1 and e:
        # a row that slipped at both ends, not everywhere: its last run continues into its first
        wrap = moved[:, 0] & moved[:, -1] & ~moved.all(axis=1)
        rows = np.flatnonzero(wrap)
        if rows.size:
            head = np.searchsorted(event, rows, "left")  # each such row's first run (at block 0)
            tail = np.searchsorted(event, rows, "right") - 1  # and its last (to block n - 1)
            count[tail] += count[head]
            moment[tail] += moment[head]
            last[tail] = last[head]
            keep = np.ones(event.size, dtype=bool)
            keep[head] = False
            event, first, last, count, moment = (
                event[keep],
                first[keep],
                last[keep],
                count[keep],
                moment[keep],
            )
    i8 = np.int64
    return Ruptures(
        event.astype(i8), first.astype(i8), last.astype(i8), count.astype(i8), moment.astype(float)
    )
