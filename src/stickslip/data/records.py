"""Measuring force-time records: cycles, amplitudes, periods, stick, and a summary.

The method, robust to noise, drift and sampling rate:

1. The dominant period comes from the spectrum of the linearly detrended force.
2. Extrema are located with :func:`scipy.signal.find_peaks` on a lightly smoothed
   signal, at least half a period apart and prominent against the record's range.
3. Their values come from local quadratic fits on one side: the samples *before*
   a peak and *after* a trough, over a tenth of a period. A stick-slip record is a
   sawtooth whose ramp is straight up to the peak and starts straight from the
   trough: the fit extrapolates to the corner without being pulled by the sharp
   drop, and averages the noise; a smooth (pure-slip) oscillation is fitted on
   its cap equally well.
4. Linear drift is estimated from the peaks (the static threshold is the same
   every cycle) and removed before the values are taken.
5. Per cycle: amplitude (peak minus the following trough, as in the paper),
   period (peak to peak), drop time (the 90% to 10% fall time of the drop,
   interpolated on the falling edge) and rise time (the rest of the period);
   with displacement or velocity columns, the fraction of the cycle at rest.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.ndimage import uniform_filter1d
from scipy.signal import find_peaks

from ..core.memory import check_memory
from ..core.noise import noise_level
from ..errors import ArgumentTypeError
from ..io.errors import DataError
from ..io.records import Record

# the cleaning of the force, the slider's rests and the synthetic records are imported from
# this module too, where a record is measured: a name imported as itself is re-exported
from .cleaning import MAX_COEFFICIENT as MAX_COEFFICIENT
from .cleaning import OUTLIER_SIGMAS as OUTLIER_SIGMAS
from .cleaning import _dominant_period as _dominant_period
from .cleaning import _inverted as _inverted
from .cleaning import clean_force
from .cleaning import exclude_outliers as exclude_outliers
from .cleaning import saturation as saturation
from .rests import OBSERVED as OBSERVED
from .rests import REST_RUN as REST_RUN
from .rests import UNRESOLVED as UNRESOLVED
from .rests import _at_rest, _load_point_column, _rest_velocity, _rests, _stick, observed_regime
from .rests import observed_line as observed_line
from .synthetic import synthetic_record as synthetic_record

__all__ = ["CycleTable", "RecordSummary", "clean_force", "measure_record"]

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class CycleTable:
    """Per-cycle measurements (SI units): one entry per peak followed by a trough."""

    peak_time: FloatArray
    peak_force: FloatArray
    trough_force: FloatArray
    amplitude: FloatArray
    period: FloatArray
    rise_time: FloatArray
    drop_time: FloatArray
    stick_fraction: FloatArray
    rise_slope: FloatArray
    rests: FloatArray  # 1 the slider rests (REST_RUN samples), 0 not, UNRESOLVED shorter rests, NaN unknown


@dataclass(frozen=True)
class RecordSummary:
    """Median and robust spread (1.4826 MAD) over the cycles of one record (SI units)."""

    name: str
    n_cycles: int
    amplitude: float
    amplitude_spread: float
    period: float
    period_spread: float
    peak_force: float
    trough_force: float
    rise_time: float
    drop_time: float
    stick_fraction: float
    observed_regime: str
    rise_slope: float
    drift: float
    v0: float
    load: float
    warning: str

    def as_dict(self) -> dict[str, Any]:
        """Return a dictionary (for tables and JSON)."""
        return asdict(self)


def _spread(x: FloatArray) -> float:
    x = x[np.isfinite(x)]
    if x.size < 2:
        return math.nan
    return float(1.4826 * np.median(np.abs(x - np.median(x))))


def _median(x: FloatArray) -> float:
    x = x[np.isfinite(x)]
    return float(np.median(x)) if x.size else math.nan


#: working memory of the measurement per sample (filters, spectrum, copies), measured on a
#: 2e7-sample record (1.8 GB) and rounded up
BYTES_PER_SAMPLE = 120.0
#: a record's cycles must stand this many times above its noise to be measured
SIGNAL_TO_NOISE = 10.0


def _side_fit(t: FloatArray, f: FloatArray, i: int, w: int, side: int) -> float:
    """Value at sample ``i`` of a quadratic fitted on ``w`` samples before (-1) or after (+1) it.

    Before a peak a guard of ``w // 20`` samples (at least 2) next to ``i`` is left
    out: with noise the raw maximum can sit a sample or two into the sharp drop, and
    those samples would bend the fit. After a trough the ramp starts at once.
    """
    g = max(2, w // 20)
    lo, hi = (i - w, i + 1 - g) if side < 0 else (i, i + w + 1)
    lo, hi = max(lo, 0), min(hi, f.size)
    if hi - lo < 4:
        return float(f[i])
    tt = t[lo:hi] - t[i]
    c = np.polyfit(tt, f[lo:hi], 2)
    return float(c[2])


def measure_record(record: Record, *, min_cycles: int = 3) -> tuple[CycleTable, RecordSummary]:
    """Extract the cycles of a force-time record and summarise them.

    Parameters
    ----------
    record : Record
        From :func:`stickslip.io.records.read_record`.
    min_cycles : int, optional
        Fewest complete cycles to accept the record.

    Returns
    -------
    CycleTable, RecordSummary

    Raises
    ------
    ArgumentTypeError
        If ``record`` is not a :class:`~stickslip.io.records.Record` or ``min_cycles`` not an integer.
    ValueError
        If the record holds fewer than ``min_cycles`` cycles or no oscillation.

    """
    if not isinstance(record, Record):
        raise ArgumentTypeError(f"record={record!r}: expected a Record (read_record(path) reads one)")
    if isinstance(min_cycles, bool) or not isinstance(min_cycles, int | np.integer):
        raise ArgumentTypeError(f"min_cycles={min_cycles!r}: expected a whole number of cycles >= 1")
    if min_cycles < 1:
        raise ValueError(f"min_cycles={min_cycles!r}: expected a whole number of cycles >= 1")
    t, f = record.time, record.force
    n = f.size
    if n < 20:
        raise DataError(f"{record.name}: {n} samples are too few to find cycles")
    check_memory(n * BYTES_PER_SAMPLE, f"{record.name} ({n} samples)", "cut the record into parts")
    f, notes, period = clean_force(record)
    dt = (t[-1] - t[0]) / (n - 1)
    per_n = max(4, round(period / dt))
    # light smoothing to locate extrema (values are taken from the raw data below)
    smooth = uniform_filter1d(f, size=max(1, per_n // 100), mode="nearest")
    span = float(np.percentile(smooth, 99) - np.percentile(smooth, 1))
    if span <= 0:
        raise DataError(f"{record.name}: the force does not vary")
    pk, _ = find_peaks(smooth, distance=max(1, per_n // 2), prominence=0.3 * span)
    tr, _ = find_peaks(-smooth, distance=max(1, per_n // 2), prominence=0.3 * span)
    # snap to the raw extremum next to the smoothed one (the smoothing blurs the corner)
    r = max(1, per_n // 100)
    pk = np.array([max(0, p - r) + int(np.argmax(f[max(0, p - r) : p + r + 1])) for p in pk], dtype=int)
    tr = np.array([max(0, q - r) + int(np.argmin(f[max(0, q - r) : q + r + 1])) for q in tr], dtype=int)
    w = max(4, per_n // 10)
    # drift: the peaks' trend
    drift = 0.0
    if pk.size >= 3:
        pv = np.array([_side_fit(t, f, i, w, -1) for i in pk])
        drift = float(np.polyfit(t[pk], pv, 1)[0])
    fd = f - drift * (t - t[0])
    velocity, rest = _rest_velocity(record)
    speed = None if velocity is None else np.abs(velocity)
    stage = _load_point_column(record, speed)
    at_rest = None if stage or velocity is None or math.isnan(rest) else _at_rest(velocity, rest)
    if velocity is not None and not np.any(np.abs(velocity) > 0):
        # such a column would give a stick fraction of 1 to a record whose force drops every cycle
        column = "velocity" if record.velocity is not None else "displacement"
        still = "is zero (or missing)" if column == "velocity" else "does not change"
        notes.append(f"the {column} column {still} throughout: no stick fraction from it")
    cycles = []
    j = 0
    for a, p in enumerate(pk[:-1]):
        while j < tr.size and tr[j] <= p:
            j += 1
        if j >= tr.size or tr[j] >= pk[a + 1]:
            continue
        q = tr[j]
        peak_v = _side_fit(t, fd, p, w, -1)
        trough_v = _side_fit(t, fd, q, w, +1)
        period_c = t[pk[a + 1]] - t[p]
        drop = _fall_time(t, fd, p, q, peak_v, trough_v)
        nxt = pk[a + 1]
        lo, hi = q + (nxt - q) // 5, nxt - (nxt - q) // 5
        slope = float(np.polyfit(t[lo:hi], fd[lo:hi], 1)[0]) if hi - lo >= 3 else math.nan
        cycles.append(
            (
                t[p], peak_v, trough_v, period_c, period_c - drop, drop, _stick(at_rest, p, nxt), slope,
                _rests(at_rest, p, nxt),
            )
        )  # fmt: skip
    if len(cycles) < min_cycles:
        raise DataError(
            f"{record.name}: found {len(cycles)} complete cycles, need at least "
            f"{min_cycles} (is the record long enough, or the oscillation too noisy?)"
        )
    arr = np.array(cycles)
    sigma = noise_level(f)
    amp = float(np.median(arr[:, 1] - arr[:, 2]))
    if not amp > SIGNAL_TO_NOISE * sigma:
        raise DataError(
            f"{record.name}: no stick-slip structure: the 'cycles' found ({len(cycles)}, median range "
            f"{amp:.3g} N) are only {amp / sigma if sigma > 0 else 0:.1f} times the noise ({sigma:.3g} N), "
            f"not {SIGNAL_TO_NOISE:g}; there is no slow rise and fast drop above the noise"
        )
    table = CycleTable(
        arr[:, 0],
        arr[:, 1],
        arr[:, 2],
        arr[:, 1] - arr[:, 2],
        arr[:, 3],
        arr[:, 4],
        arr[:, 5],
        arr[:, 6],
        arr[:, 7],
        arr[:, 8],
    )
    if w < 8:
        notes.append(f"only {per_n} samples per period: extrema values are rough; sample faster")
    if stage:
        notes.append(stage)
    warning = "; ".join(notes)
    summary = RecordSummary(
        name=record.name,
        n_cycles=len(cycles),
        amplitude=_median(table.amplitude),
        amplitude_spread=_spread(table.amplitude),
        period=_median(table.period),
        period_spread=_spread(table.period),
        peak_force=_median(table.peak_force),
        trough_force=_median(table.trough_force),
        rise_time=_median(table.rise_time),
        drop_time=_median(table.drop_time),
        stick_fraction=_median(table.stick_fraction),
        observed_regime=observed_regime(table.rests),
        rise_slope=_median(table.rise_slope),
        drift=drift,
        v0=float(record.v0.to("m/s").magnitude) if record.v0 is not None else math.nan,
        load=float(record.load.to("N").magnitude) if record.load is not None else math.nan,
        warning=warning,
    )
    return table, summary


def _fall_time(t: FloatArray, f: FloatArray, p: int, q: int, hi: float, lo: float) -> float:
    """Time for the force to fall from 90% to 10% of the drop between samples p and q.

    Interpolated on the falling edge, so that noise on the flat start of the next
    ramp (where the trough sits) does not move it.
    """
    seg = f[p : q + 1]
    tt = t[p : q + 1]
    a = lo + 0.9 * (hi - lo)
    b = lo + 0.1 * (hi - lo)
    ia = int(np.argmax(seg < a)) if np.any(seg < a) else 0
    ib = int(np.argmax(seg < b)) if np.any(seg < b) else seg.size - 1
    ta = tt[ia] if ia == 0 else np.interp(a, [seg[ia], seg[ia - 1]], [tt[ia], tt[ia - 1]])
    tb = tt[ib] if ib == 0 else np.interp(b, [seg[ib], seg[ib - 1]], [tt[ib], tt[ib - 1]])
    return float(max(tb - ta, 0.0))


def _motion_row(rec: Record) -> tuple[dict[str, Any] | None, Any]:
    """Return a record's motion columns where its force and driving velocity give them, and its events.

    Tried for records with a driving velocity and no velocity or displacement column (a
    column of the slider's own motion is measured as it is; None, None). A record whose
    motion cannot be measured gets its reason in ``motion_note`` (and no events).
    """
    from .motion import measure_motion, motion_columns

    if rec.v0 is None or rec.velocity is not None or rec.displacement is not None:
        return None, None
    try:
        events, _, summary = measure_motion(rec)
    except DataError as exc:
        return {"motion_note": str(exc)}, None
    except (ValueError, FloatingPointError) as exc:  # the cycles are measured all the same
        return {"motion_note": f"the slider's motion could not be measured ({exc})"}, None
    return motion_columns(summary) | {"motion_note": "; ".join(summary.notes)}, events.as_frame(rec.name)


def _from_motion(row: dict[str, Any], motion: dict[str, Any]) -> dict[str, Any]:
    """Return ``row`` with its period, amplitude, stick fraction and observed regime from the motion.

    The slip events measure an irregular record where a spectral period does not: the
    period is the median recurrence of the events in stick-slip, the median cycle of
    the slider's velocity otherwise; the amplitude the median range of the denoised force
    over a cycle.
    """
    from .motion import OBSERVED_OF

    stick_slip = str(motion["regime"]).endswith("stick-slip")
    period = motion["recurrence [s]"] if stick_slip else motion["motion_period"]
    q1, q3 = (
        (motion["recurrence_q1 [s]"], motion["recurrence_q3 [s]"]) if stick_slip else (math.nan, math.nan)
    )
    k, v0 = motion["stiffness [N/m]"], row.get("v0", math.nan)
    return row | {
        "n_cycles": motion["n_events"] if stick_slip else motion["n_motion_cycles"],
        "period": period,
        "period_spread": (q3 - q1) / 1.349,
        "amplitude": motion["motion_amplitude"],
        "amplitude_spread": motion["motion_amplitude_spread"],
        "peak_force": motion["motion_force_before"],
        "trough_force": motion["motion_force_after"],
        "drop_time": motion["slip_duration [s]"],
        "rise_time": period - motion["slip_duration [s]"] if stick_slip else math.nan,
        "rise_slope": k * v0,
        "stick_fraction": motion["stick_fraction"],
        "observed_regime": OBSERVED_OF.get(str(motion["regime"]), "unknown"),
    }


def _failed_row(rec: Record | str, reason: str) -> dict[str, Any]:
    """Return the summary row of a record that could not be measured (or, named only, read).

    NaN values and the reason: ``not measured: ...`` or ``not read: ...``.
    """
    row: dict[str, Any] = dict.fromkeys((f.name for f in fields(RecordSummary)), math.nan)  # its columns
    row["observed_regime"] = "unknown"
    if isinstance(rec, str):
        return row | {"name": rec, "n_cycles": 0, "warning": "not read: " + reason}
    return row | {
        "name": rec.name,
        "n_cycles": 0,
        "v0": float(rec.v0.to("m/s").magnitude) if rec.v0 is not None else math.nan,
        "load": float(rec.load.to("N").magnitude) if rec.load is not None else math.nan,
        "warning": "not measured: " + reason if reason else "",
    }


def analyze_records(
    records: list[Record],
    *,
    confidence: float = 0.95,
    unreadable: Mapping[str, str] | None = None,
    return_events: bool = False,
) -> tuple[Any, ...]:
    """Measure every record; return the summary table and the criterion's verdict.

    A record that cannot be measured (no cycles, no structure above its noise) gets a
    row of NaN with the reason in ``warning``, and counts for nothing in the verdict;
    a single record that cannot be measured, or none of several, raises. Records that
    could not be read (``unreadable``: name to reason, from the
    :class:`~stickslip.io.records.UnreadableRecord` warnings of
    ``read_records(on_error="warn")``) get such a row too, after the others.

    Returns
    -------
    table : pandas.DataFrame
        One row per record (SI units in the column names); ``warning`` says what was
        excluded, inverted or could not be measured; ``in_verdict`` marks the
        records the verdict was computed from.
    verdict : CriterionResult or None
        The amplitude-velocity criterion over the records' driving velocities
        (records at one load: the most common one), or None without velocities.
    events : pandas.DataFrame or None
        With ``return_events``: the slip events of every record whose motion was
        measured, as :func:`~stickslip.data.motion.records_events` gives them (None if
        none), from the same measurement as the table.

    """
    import pandas as pd

    from .criterion import check_confidence, classify

    if (
        isinstance(records, str | bytes | os.PathLike)
        or not isinstance(records, Iterable)
        or not all(isinstance(r, Record) for r in records)
    ):
        raise TypeError(
            f"records={records!r}: expected a list of Record (read_records(folder) reads a folder of them)"
        )
    if not records:
        raise ValueError("no records to analyze")
    check_confidence(confidence)
    rows = []
    failed = []
    event_frames = []
    for rec in records:
        motion, events = _motion_row(rec)
        if events is not None:
            event_frames.append(events)
        try:
            _, s = measure_record(rec)
        except DataError as exc:
            if motion is None or motion.get("regime", "undetermined") == "undetermined":
                if len(records) == 1:
                    raise
                failed.append(str(exc))
                rows.append(_failed_row(rec, str(exc)) | (motion or {}))
                continue
            # the events measure what the cycles could not (an irregular real record)
            row = _failed_row(rec, "") | motion
            row["n_cycles"] = motion["n_events"]
            rows.append(_from_motion(row, motion))
            continue
        row = s.as_dict()
        if motion is not None and motion.get("regime", "undetermined") != "undetermined":
            row = _from_motion(row | motion, motion)
        elif motion is not None:
            row |= motion
        if rec.v0 is None:  # it was measured, and left out of the verdict: say why
            note = (
                "no driving velocity, so not in the criterion's verdict (give '# v0 = ...' in the "
                "file or 'v0 [unit]' in index.csv)"
            )
            row["warning"] = f"{row['warning']}; {note}" if row["warning"] else note
        rows.append(row)
    rows += [_failed_row(name, reason) for name, reason in (unreadable or {}).items()]
    if len(failed) == len(records):
        raise DataError(f"no record could be measured: {failed[0]} (and {len(failed) - 1} more)")
    df = pd.DataFrame(rows).rename(
        columns={
            "amplitude": "amplitude [N]",
            "amplitude_spread": "amplitude_spread [N]",
            "period": "period [s]",
            "period_spread": "period_spread [s]",
            "peak_force": "peak_force [N]",
            "trough_force": "trough_force [N]",
            "rise_time": "rise_time [s]",
            "drop_time": "drop_time [s]",
            "drift": "drift [N/s]",
            "rise_slope": "rise_slope [N/s]",
            "v0": "v0 [m/s]",
            "load": "load [N]",
        }
    )
    df = df.drop(
        columns=[c for c in df.columns if str(c).startswith("motion_") and c != "motion_note"],
        errors="ignore",
    )
    if "motion_note" in df.columns:  # the motion's notes join the record's warning
        note = df.pop("motion_note").fillna("").astype(str)
        old = df["warning"].fillna("").astype(str)
        df["warning"] = [("; ".join(x for x in (a, b) if x)) for a, b in zip(old, note, strict=True)]
    verdict = None
    sel = df[np.isfinite(df["v0 [m/s]"]) & np.isfinite(df["amplitude [N]"])]
    if len(sel) and sel["load [N]"].notna().any():
        common = sel["load [N]"].round(12).mode()
        if len(common):
            sel = sel[(sel["load [N]"].round(12) == common.iloc[0]) | sel["load [N]"].isna()]
    df["in_verdict"] = False
    if len(sel) >= 2:
        df.loc[sel.index, "in_verdict"] = True
        err = sel["amplitude_spread [N]"].to_numpy() / np.sqrt(sel["n_cycles"].to_numpy())
        err = np.where(np.isfinite(err) & (err > 0), err, np.nan)
        verdict = classify(
            sel["v0 [m/s]"].to_numpy(),
            sel["amplitude [N]"].to_numpy(),
            None if np.any(np.isnan(err)) else err,
            confidence=confidence,
        )
    if return_events:
        return df, verdict, pd.concat(event_frames, ignore_index=True) if event_frames else None
    return df, verdict
