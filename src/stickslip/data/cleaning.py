"""Cleaning a record's force before it is measured or fitted.

Isolated outliers (a sensor's glitch) are replaced by the mean of their neighbours, an
inverted sawtooth (fast rises, slow falls) is turned the right way up, and the notes say
what was done and what looks wrong: a force clipped at a rail (a saturated sensor or ADC),
or one too large for the normal load (a unit error). The record's dominant period comes
from the spectrum of the linearly detrended force.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from scipy.ndimage import median_filter, uniform_filter1d

from ..io.errors import DataError
from ..io.records import Record

__all__ = ["MAX_COEFFICIENT", "OUTLIER_SIGMAS", "clean_force", "exclude_outliers", "saturation"]

FloatArray = npt.NDArray[np.float64]

#: a force beyond this many times the normal load is named as a likely unit error (friction
#: coefficients of rubber and adhesive contacts reach 2 to 3)
MAX_COEFFICIENT = 5.0
#: a sample this many robust standard deviations from the median of its neighbours is an outlier
OUTLIER_SIGMAS = 20.0


def _dominant_period(t: FloatArray, f: FloatArray) -> float:
    n = f.size
    dt = (t[-1] - t[0]) / (n - 1)
    x = f - np.polyval(np.polyfit(t, f, 1), t)
    spec = np.abs(np.fft.rfft(x * np.hanning(n)))
    freqs = np.fft.rfftfreq(n, dt)
    lo = 2.5 / (t[-1] - t[0])  # at least 2.5 cycles in the record
    ok = freqs >= lo
    if not ok.any():
        return math.nan
    return float(1.0 / freqs[ok][np.argmax(spec[ok])])


def exclude_outliers(force: FloatArray) -> tuple[FloatArray, npt.NDArray[np.int64]]:
    """Replace isolated outlier samples by the mean of their neighbours; return the force and their indices.

    A sample is an outlier when it is not finite, or when it lies more than
    :data:`OUTLIER_SIGMAS` robust standard deviations (of the deviations from a running
    median of 5) from that median *and* more than half the record's range (1st to 99th
    percentile) from it: a glitch (a sensor's 1e308, a dropped bit), not a sharp corner
    of the sawtooth, which the running median follows.
    """
    f = np.asarray(force, dtype=float).copy()
    bad = ~np.isfinite(f)
    if bad.any():
        f[bad] = np.interp(np.flatnonzero(bad), np.flatnonzero(~bad), f[~bad]) if (~bad).any() else 0.0
    if f.size >= 5:
        med = median_filter(f, size=5, mode="nearest")
        dev = f - med
        scale = 1.4826 * float(np.median(np.abs(dev - np.median(dev))))
        span = float(np.percentile(f, 99) - np.percentile(f, 1))
        out = (np.abs(dev) > OUTLIER_SIGMAS * scale) & (np.abs(dev) > 0.5 * span)
        bad |= out
        if out.any():
            good = ~bad
            f[out] = np.interp(np.flatnonzero(out), np.flatnonzero(good), f[good])
    return f, np.flatnonzero(bad)


def clean_force(record: Record) -> tuple[FloatArray, list[str], float]:
    """Return the record's force as it is measured (and fitted), what was done to it, and its period.

    Isolated outliers are replaced by the mean of their neighbours (their times named), and
    an inverted sawtooth (fast rises, slow falls) is turned the right way up.

    Raises
    ------
    DataError
        When the record shows no oscillation.

    """
    t = record.time
    notes: list[str] = []
    f, excluded = exclude_outliers(record.force)
    if excluded.size:
        # by time, which a record keeps (a row number depends on the file's header and comment lines)
        at = ", ".join(f"{t[i]:.9g}" for i in excluded[:10]) + (" ..." if excluded.size > 10 else "")
        notes.append(
            f"{excluded.size} outlier sample(s) excluded (at t = {at} s: "
            "far from their neighbours against the record's noise; replaced by the mean of their neighbours)"
        )
    period = _dominant_period(t, f)
    if not math.isfinite(period):
        raise DataError(f"{record.name}: no oscillation found (fewer than 2.5 cycles?)")
    clipped = saturation(f)  # outliers out: a spike is not the rail
    if clipped:
        notes.append(clipped)
    per_n = max(4, round(period / ((t[-1] - t[0]) / (t.size - 1))))
    if _inverted(f, per_n):
        f = -f
        notes.append(
            "the force column is inverted (it falls slowly and rises fast; stick-slip rises slowly and "
            "drops fast): measured as -force"
        )
    if record.load is not None:
        # mN written as N reads as amplitudes of 1000 N against a load of 2 N, and three such
        # files among a folder's records turn its verdict to pure-slip: the note names it
        load = float(record.load.to("N").magnitude)
        top = float(np.percentile(np.abs(f), 99))
        if load > 0 and top > MAX_COEFFICIENT * load:
            notes.append(
                f"the force reaches {top:.4g} N, {top / load:.3g} times the normal load {load:.4g} N: a "
                f"friction coefficient above {MAX_COEFFICIENT:g} is not plausible; check the force column's "
                "unit (mN written as N?) and the load's"
            )
    return f, notes, period


def saturation(force: FloatArray) -> str | None:
    """Say whether the force sits at a rail (a saturated sensor or ADC clips its peaks), or None.

    Samples pile up at the record's largest (or smallest) value: at least 3 of them, two in a
    row, and more than twice as many as at the next value below it. A force with continuous
    values reaches its extreme once; a quantized one (an ADC's steps) has fewer samples at
    its top step than at the one below, the tail of the noise.

    Parameters
    ----------
    force : array
        The force as recorded (N).

    Returns
    -------
    str or None
        The note: where the force is clipped and what it does to the measurements.

    """
    f = np.asarray(force, dtype=float)
    for side, x in (("largest", f), ("smallest", -f)):
        top = float(x.max())
        at = x == top
        n_top = int(at.sum())
        below = x[~at]
        n_next = int(np.sum(below == below.max())) if below.size else 0
        if n_top < max(3, 2 * n_next + 1) or not np.any(at[1:] & at[:-1]):
            continue
        value = top if side == "largest" else -top
        what = "peaks" if side == "largest" else "troughs"
        return (
            f"the force sits at its {side} value, {value:.6g} N, for {n_top} samples ({n_next} at the next "
            f"value): the sensor or its ADC saturated there and clipped the {what}; amplitude, {what} "
            "and what is fitted to them are short by what was cut off (record with a range that holds them)"
        )
    return None


def _inverted(force: FloatArray, per_n: int) -> bool:
    """Whether a record rises fast and falls slowly (an inverted stick-slip sawtooth).

    On a lightly smoothed record, stick-slip rises for most of each period and drops in a
    short time; inverted, it falls for most of it. A symmetric oscillation (pure slip)
    rises about half the time and is left as it is.
    """
    smooth = uniform_filter1d(force, size=max(3, per_n // 50), mode="nearest")
    d = np.diff(smooth)
    moving = np.abs(d) > 0
    if moving.sum() < 10:
        return False
    rising = float(np.mean(d[moving] > 0))
    return rising < 0.3
