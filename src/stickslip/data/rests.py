"""Whether the slider rests: from a record's velocity or displacement column.

The velocity column, or the gradient of the displacement column, is at rest within four
deviations of its noise of zero; a slip is grown over its slow start and end. Per cycle:
the fraction of samples at rest and whether the slider rests at all (:data:`REST_RUN`
samples in a row); per record: the regime its velocity shows, and a line setting that
against the criterion's verdict. A column that is the load point's (a stage moving
steadily at the driving velocity) says nothing of the slider and is named.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from ..io.records import Record

__all__ = ["OBSERVED", "REST_RUN", "UNRESOLVED", "observed_line", "observed_regime"]

FloatArray = npt.NDArray[np.float64]


def _load_point_column(record: Record, speed: FloatArray | None) -> str:
    """Say so where the velocity or displacement column is the load point's, not the slider's.

    A scratch tester logs its stage: a speed steady (5-95 % spread within 10 % of its
    median) at the driving velocity (within 20 %). Its stick fraction would be 0 for a
    record that sticks 99 % of the time.
    """
    if speed is None or record.v0 is None or not np.any(np.isfinite(speed)):
        return ""
    v0 = float(record.v0.to("m/s").magnitude)
    med = float(np.nanmedian(speed))
    lo, hi = (float(x) for x in np.nanpercentile(speed, [5.0, 95.0]))
    if not (med > 0 and hi - lo < 0.1 * med and abs(med / v0 - 1.0) < 0.2):
        return ""
    column = "velocity" if record.velocity is not None else "displacement"
    return (
        f"the {column} column moves steadily at {med * 1e6:.4g} um/s, the driving velocity: it is "
        "the load point's (a stage), not the slider's; no stick fraction from it"
    )


def _rest_velocity(record: Record) -> tuple[FloatArray | None, float]:
    """Return the slider's velocity and the speed below which it is at rest (None, NaN if neither).

    The velocity is the velocity column, or the gradient of the displacement column. At
    rest means at most four standard deviations of the velocity's noise, which comes from
    the median absolute fourth difference (white noise: variance 70 sigma^2; it passes none
    of a smooth cubic, so the slow start of a slip is not taken for noise, as a threshold
    at a fixed share of the largest speed takes it). A noise-free record keeps a floor of
    1e-9 of its largest speed. NaN when that limit is a quarter of the largest speed or
    more (rest cannot be told from slip).
    """
    if record.velocity is not None:
        signed = record.velocity
    elif record.displacement is not None:
        signed = np.gradient(record.displacement, record.time)
    else:
        return None, math.nan
    v = np.abs(signed)
    vmax = float(np.nanmax(v)) if np.any(np.isfinite(v)) else math.nan
    if not vmax > 0:  # a column that never moves (a sensor not read) tells no rest from slip
        return signed, math.nan
    d4 = np.diff(signed, 4)
    d4 = d4[np.isfinite(d4)]
    sigma = 1.4826 * float(np.median(np.abs(d4))) / math.sqrt(70.0) if d4.size else 0.0
    limit = max(4.0 * sigma, 1e-9 * vmax)
    return signed, (limit if limit < 0.25 * vmax else math.nan)


def _at_rest(velocity: FloatArray, limit: float) -> FloatArray:
    """Return 1 where the slider is at rest, 0 where it slips, NaN where its velocity is missing.

    A slip is a run of samples faster than ``limit`` (four noise deviations), grown on both
    sides over the samples that still move its way: a slip's slow start and end lie below
    four deviations, and counted as rest they bias the stick fraction (0.904 for a true
    0.847 with velocity noise of v0 at 5 mm/s; grown, the bias is +0.017 at a noise of
    0.8 v0). A sample moves the slip's way when its velocity, less the rest's median (an
    offset, a creep), is beyond a twentieth of ``limit`` that way; a slip grows by at most
    its own length on each side, so that no bias of the rest carries it through a stick.
    """
    finite = np.isfinite(velocity)
    fast = finite & (np.abs(velocity) > limit)
    rest = velocity[finite & ~fast]
    v = velocity - (float(np.median(rest)) if rest.size else 0.0)
    moving = fast.copy()
    step = np.diff(fast.astype(np.int8))
    starts = np.flatnonzero(step == 1) + 1
    ends = np.flatnonzero(step == -1) + 1
    if fast[0]:
        starts = np.r_[0, starts]
    if fast[-1]:
        ends = np.r_[ends, fast.size]
    grow = 0.05 * limit
    n = velocity.size
    for a_, b_ in zip(starts, ends, strict=True):
        a, b = int(a_), int(b_)
        way = 1.0 if velocity[a] > 0 else -1.0
        reach = b - a
        i = a - 1
        while i >= max(0, a - reach) and way * v[i] > grow:
            moving[i] = True
            i -= 1
        j = b
        while j < min(n, b + reach) and way * v[j] > grow:
            moving[j] = True
            j += 1
    return np.where(finite, (~moving).astype(float), np.nan)


def _stick(at_rest: FloatArray | None, i0: int, i1: int) -> float:
    """Fraction of the samples in [i0, i1) at rest, of those with a velocity (NaN without one)."""
    if at_rest is None:
        return math.nan
    part = at_rest[i0:i1]
    return float(np.nanmean(part)) if np.any(np.isfinite(part)) else math.nan


#: consecutive samples at rest that make a rest of the slider (a stick), not a velocity that
#: passes through the noise band about zero
REST_RUN = 3
#: ``CycleTable.rests`` of a cycle whose only samples at rest are runs shorter than REST_RUN
UNRESOLVED = 0.5


def _rests(at_rest: FloatArray | None, i0: int, i1: int) -> float:
    """Whether the slider rests in the samples [i0, i1): 1, 0, :data:`UNRESOLVED`, or NaN (unknown).

    1 where :data:`REST_RUN` samples in a row are at rest; 0 where none is; unresolved
    where only shorter runs are (a stick of a sample or two, as a stick of 1 % of the
    cycle sampled 300 times a cycle gives, or a slip's slowest speed dipping into the
    noise band: the record cannot tell them apart).
    """
    if at_rest is None:
        return math.nan
    part = at_rest[i0:i1]
    if not np.any(np.isfinite(part)):
        return math.nan
    rest = np.r_[False, part == 1.0, False]
    edges = np.flatnonzero(np.diff(rest.astype(np.int8)))
    runs = edges[1::2] - edges[::2]
    if not runs.size:
        return 0.0
    return 1.0 if int(runs.max()) >= REST_RUN else UNRESOLVED


def observed_regime(rests: npt.ArrayLike) -> str:
    """Return the regime a record's velocity shows, from its cycles' rests (``CycleTable.rests``).

    ``stick-slip`` where the slider comes to rest in every cycle (in some cycles for
    fewer than :data:`REST_RUN` samples at most); ``pure-slip`` where it does in none;
    ``mixed`` where it clearly does in some cycles and clearly not in others;
    ``unresolved`` where its only rests are a sample or two (sample faster to tell a
    short stick from a slip that slows into the noise); ``unknown`` without a velocity
    or a displacement, or where rest cannot be told from slip. At rest means a
    velocity within four deviations of its noise of zero: a pure-slip oscillation whose
    slowest speed stays that close to zero for :data:`REST_RUN` samples or more reads as
    stick-slip, as the slider is then at rest as far as the record can tell.
    """
    r = np.asarray(rests, dtype=float)
    r = r[np.isfinite(r)]
    if r.size == 0:
        return "unknown"
    rest, none = bool(np.any(r == 1.0)), bool(np.any(r == 0.0))
    if rest and none:
        return "mixed"
    if rest:
        return "stick-slip"
    if none and not np.any(r == UNRESOLVED):
        return "pure-slip"
    return "unresolved"


#: what the velocity can show of a record, in the order said
OBSERVED = ("stick-slip", "pure-slip", "mixed", "unresolved")


def observed_line(table: Any, verdict: Any) -> str | None:
    """Say what the records' velocities show, set against the criterion's verdict (None: no velocity).

    ``table`` and ``verdict`` are :func:`~stickslip.data.records.analyze_records`' results.
    The records counted are those in the verdict (all measured ones where there is none);
    the paper's criterion infers the regime from the amplitudes, the velocity shows it
    where it resolves it, so a record whose velocity clearly shows the other regime is
    named.
    """
    used = table[table["in_verdict"]] if verdict is not None else table[table["n_cycles"] > 0]
    seen = used[used["observed_regime"].isin(OBSERVED)]
    if seen.empty:
        return None
    counts = seen["observed_regime"].value_counts()
    parts = [f"{int(counts[r])} {r}" for r in OBSERVED if r in counts]
    where = "in the verdict" if verdict is not None else "measured"
    noun = "record" if len(used) == 1 else "records"
    line = f"observed: of the {len(used)} {noun} {where}, the velocity of {len(seen)} shows " + ", ".join(
        parts
    )
    if "unresolved" in counts:
        line += " (unresolved: rests of a sample or two only; sample faster)"
    if verdict is not None and verdict.verdict in ("stick-slip", "pure-slip"):
        other_regime = "pure-slip" if verdict.verdict == "stick-slip" else "stick-slip"
        other = seen[seen["observed_regime"] == other_regime]
        if other.empty:
            line += f"; none shows {other_regime}, as the criterion's {verdict.verdict} has it"
        else:
            names = ", ".join(map(str, other["name"].head(3))) + (" ..." if len(other) > 3 else "")
            line += f"; {len(other)} {other_regime} where the criterion says {verdict.verdict} ({names})"
    return line
