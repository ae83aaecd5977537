"""The two stages of the fit of the paper's law to a record: cycle features, then the force waveform.

:func:`_fit_features` fits the model's cycle features to the medians of the record's
cycles (each with its standard error), from several starting values of ``a``;
:func:`_fit_waveform` fits the model's steady cycle, with the phase of its breakaway and a
linear drift, to every sample of a window of whole cycles, weighted by the record's noise.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import numpy.typing as npt
from scipy.optimize import least_squares

from ..io.errors import DataError
from ..io.records import Record
from .fit_model import _first_breakaway, _model_features, model_waveform
from .fit_solver import _covariance, _minimise
from .records import CycleTable, RecordSummary

__all__ = ["MAX_WAVEFORM_SAMPLES"]

FloatArray = npt.NDArray[np.float64]

#: largest number of samples the waveform fit uses (a window of whole cycles)
MAX_WAVEFORM_SAMPLES = 200_000


class _Features(NamedTuple):
    """A fit on cycle features (:func:`_fit_features`).

    The fit's log-coordinates, the Jacobian of the weighted residuals there, the total
    chi-square, and the measured features (:data:`~stickslip.data.fit_model.FEATURES`) with
    their standard errors.
    """

    theta: FloatArray
    jac: FloatArray
    chi2: float
    data: FloatArray
    err: FloatArray


def _fit_features(
    record: Record,
    table: CycleTable,
    summary: RecordSummary,
    names: tuple[str, ...],
    v0: float,
    load: float,
    guess: dict[str, float] | None,
    fixed: dict[str, float] | None = None,
) -> _Features:
    """Fit on cycle features; return log-parameters, Jacobian, chi-square, features and their errors."""
    n = summary.n_cycles
    data, err = [], []
    dt = float(np.median(np.diff(record.time)))
    for key, arr in (
        ("peak_force", table.peak_force),
        ("trough_force", table.trough_force),
        ("period", table.period),
        ("rise_slope", table.rise_slope),
        ("drop_time", table.drop_time),
    ):
        med = float(np.median(arr))
        se = 1.2533 * float(np.std(arr, ddof=1)) / math.sqrt(n) if n > 1 else math.nan
        floor = {"period": dt / math.sqrt(n), "drop_time": dt / math.sqrt(n)}.get(key, 0.0)
        data.append(med)
        err.append(max(se, floor, 1e-6 * abs(med)))
    data_a, err_a = np.array(data), np.array(err)
    k0 = summary.rise_slope / v0
    mu_s0 = summary.peak_force / load
    m0 = k0 * (summary.drop_time / (0.6 * math.pi)) ** 2
    start = {"mu_s": mu_s0, "a": 100.0, "k": k0, "m": max(m0, 1e-9), "b": 10.0}
    start.update(guess or {})
    start["d"] = start["a"] - start["b"]
    if not all(math.isfinite(start[x]) and start[x] > 0 for x in names):
        raise DataError(f"{record.name}: cannot start the fit from the features {start}")

    held = {"b": 0.0, **(fixed or {})}

    def residuals(theta: FloatArray) -> FloatArray:
        model = _model_features(theta, names, held, v0, load)
        r = (model - data_a) / err_a
        return np.where(np.isfinite(r), r, 1e6)

    best = None
    for a_start in (30.0, 100.0, 300.0, 1000.0):
        s0 = dict(start)
        if guess is None or "a" not in guess:
            s0["a"] = a_start
            s0["d"] = a_start - s0["b"]
        theta0 = np.log([s0[x] for x in names])
        res = least_squares(residuals, theta0, method="trf", x_scale=1.0, diff_step=1e-6, max_nfev=400)
        if best is None or res.cost < best.cost:
            best = res
    assert best is not None
    if not best.success:
        raise RuntimeError(f"{record.name}: the fit did not converge ({best.message})")
    return _Features(best.x, best.jac, 2.0 * best.cost, data_a, err_a)


class _Fit(NamedTuple):
    """A fit of the model to a record: the waveform's (:func:`_fit_waveform`), or the features'.

    The log-parameters, their covariance (not scaled by the chi-square; for the waveform
    with the phase and the drift marginalised), the reduced chi-square, the samples or
    features used, a breakaway time (s), the drift (N/s) and its standard error, the time
    the drift term is zero at (s), and the total chi-square.
    """

    theta: FloatArray
    cov: FloatArray
    chi2: float
    samples: int
    breakaway: float
    drift: float
    drift_error: float
    drift_origin: float
    cost: float


def _peaks_drift_error(table: CycleTable) -> float:
    """Return the standard error (N/s) of the peaks' trend, from their scatter about it.

    The record's drift is the slope of its peaks against time
    (:func:`~stickslip.data.records.measure_record`); the
    peaks in ``table`` have it removed, which changes the slope but not the scatter.
    """
    t, f = np.asarray(table.peak_time, dtype=float), np.asarray(table.peak_force, dtype=float)
    if t.size < 3 or np.ptp(t) <= 0:
        return math.nan
    from scipy.stats import linregress

    return float(linregress(t, f).stderr)


def _fit_waveform(
    record: Record,
    force: FloatArray,
    table: CycleTable,
    summary: RecordSummary,
    names: tuple[str, ...],
    theta0: FloatArray,
    v0: float,
    load: float,
    noise: float,
    fixed_b: float = 0.0,
) -> _Fit:
    """Fit the force waveform over a window of whole cycles (``b`` held at ``fixed_b`` unless fitted).

    ``force`` is the record's force as measured (:func:`~stickslip.data.cleaning.clean_force`:
    outliers out, the right
    way up), computed once by the caller: the refits and the profile call this many times.
    """
    t = record.time
    f = force
    # a window of whole cycles, from one peak to a later one, at most MAX_WAVEFORM_SAMPLES long
    peaks = np.searchsorted(t, table.peak_time)
    last = int(np.searchsorted(peaks, peaks[0] + MAX_WAVEFORM_SAMPLES, side="right")) - 1
    i0, i1 = int(peaks[0]), int(peaks[max(1, last)]) if len(peaks) > 1 else len(t)
    if i1 - i0 < 20:
        i0, i1 = 0, len(t)
    tw, fw = t[i0:i1], f[i0:i1]
    if not noise > 0:
        raise DataError(
            f"{record.name}: the record has no measurable noise (its second differences are all "
            "zero), so nothing weights a waveform fit; give the noise level (--noise '0.4 mN', "
            "or noise= in Python)"
        )
    # the phase is anchored at the peak in the middle of the window: every drop sits at
    # t_ref + j T, and with j centred the phase and the period are not correlated (as a
    # regression centres its abscissa); anchored at the first drop they are, and the cost
    # becomes a long curved valley that the optimisers crawl along
    inside = table.peak_time[(table.peak_time >= tw[0]) & (table.peak_time <= tw[-1])]
    t_peak = float(inside[len(inside) // 2]) if inside.size else float(table.peak_time[0])
    # a breakaway of the model that puts its force maximum on that peak
    t_ref = _first_breakaway(theta0, names, v0, load, t_peak, fixed_b)
    scale_t = max(float(summary.drop_time), 5.0 * float(np.median(np.diff(tw))))
    t_mid = 0.5 * (tw[0] + tw[-1])
    # the drift of the force (a sensor's, say) is a parameter too: estimated from a few noisy
    # peaks and subtracted beforehand, it would bias the others; in units of noise per window
    span = max(tw[-1] - tw[0], 1e-300)
    drift_unit = noise / span

    def residuals(x: FloatArray) -> FloatArray:
        model = model_waveform(x[:-2], names, t_ref + x[-2] * scale_t, tw, v0, load, fixed_b)
        r = (fw - model - x[-1] * drift_unit * (tw - t_mid)) / noise
        return np.where(np.isfinite(r), r, 1e3)

    x0 = np.concatenate([theta0, [0.0, summary.drift / drift_unit]])
    # align the phase first (the parameters from the features are close; the drop's time is not)
    offsets = np.linspace(-2.0, 2.0, 21)
    costs = [float(np.sum(residuals(np.concatenate([theta0, [o, x0[-1]]])) ** 2)) for o in offsets]
    x0[-2] = offsets[int(np.argmin(costs))]
    x, jac, cost = _minimise(residuals, x0, record.name)
    dof = max(1, tw.size - x.size)
    chi2 = cost / dof
    # the parameters' covariance with the nuisance parameters (phase, drift) marginalised:
    # the inverse of the full normal matrix, restricted to the parameters
    full = _covariance(jac)
    n_p = len(names)
    cov = np.asarray(full[:n_p, :n_p], dtype=float)
    return _Fit(
        theta=x[:n_p],
        cov=cov,
        chi2=chi2,
        samples=int(tw.size),
        breakaway=t_ref + float(x[-2]) * scale_t,
        drift=float(x[-1] * drift_unit),
        drift_error=float(np.sqrt(full[-1, -1])) * drift_unit,
        drift_origin=float(t_mid),
        cost=cost,
    )
