"""Fitting the spring-block model to a measured stick-slip record.

Two stages.

1. **Cycle features** give a robust start: the peak force, the trough force, the
   period, the slope of the stick ramp and the drop (fall) time, each the median
   over the record's cycles with its standard error. The peak is the static
   friction ``mu_s W``, the ramp's slope is ``k v0`` exactly, the drop time sets
   ``sqrt(m/k)``, the period and the trough set the weakening ``a``. A fit on
   features alone cannot say whether the model fits: the trough is nearly the
   ramp slope times the period, so four parameters meet four independent numbers,
   and its chi-square measures the bias of the extraction (peaks and troughs picked
   from noisy samples), not the fit.
2. **The force waveform**: the model's steady cycle, repeated with the period it
   predicts, against every sample of a window of whole cycles (up to
   :data:`MAX_WAVEFORM_SAMPLES`), by :func:`scipy.optimize.least_squares` over
   ``mu_s, a, k, m`` (and ``b``) in log space and the time of the first breakaway.
   Residuals are weighted by the record's noise, estimated from the spread of
   successive differences (robust to the drops), so the reduced chi-square is
   about 1 when the model describes the record, and larger when it does not (it is
   reported, and a warning given above 2). Uncertainties and correlations come from
   the Jacobian at the optimum, scaled by the reduced chi-square when it exceeds 1.
   The waveform fit assumes a periodic record: cycle-to-cycle jitter of a real
   experiment shows up as a reduced chi-square above 1, and ``method="features"``
   is then the more robust estimate.

A parameter whose relative uncertainty exceeds 50%, or two whose correlation
exceeds 0.99 in magnitude while one of them is uncertain by more than 10%, are
reported as not identifiable; a pair correlated beyond 0.9999 gets a warning that
their errors move together.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

from ..core.noise import noise_level
from ..errors import ArgumentTypeError
from ..io.errors import DataError
from ..io.records import Record
from ..laws import PhysicalWeakeningLaw
from ..models.parameters import PhysicalParameters
from ..units import Q_, check_number

# the fit's model, solver and stages are imported from this module too, where the fit is
# made: a name imported as itself is re-exported
from .cleaning import clean_force
from .fit_model import FEATURES, _first_breakaway, _model_features, _values, model_waveform
from .fit_model import _cycle as _cycle
from .fit_model import _fall_time_model as _fall_time_model
from .fit_model import _physical as _physical
from .fit_model import _time_of_max as _time_of_max
from .fit_solver import _covariance
from .fit_solver import _Jacobian as _Jacobian
from .fit_solver import _minimise as _minimise
from .fit_stages import MAX_WAVEFORM_SAMPLES as MAX_WAVEFORM_SAMPLES
from .fit_stages import _Features, _Fit, _fit_features, _fit_waveform, _peaks_drift_error
from .records import CycleTable, RecordSummary, measure_record

__all__ = ["FitResult", "fit_record"]

FloatArray = npt.NDArray[np.float64]
UNITS = {"mu_s": "", "a": "s/m", "b": "s/m", "k": "N/m", "m": "kg"}


@dataclass(frozen=True)
class FitResult:
    """Fitted parameters with uncertainties.

    Attributes
    ----------
    values : dict
        Parameter name to fitted value (SI: ``a``, ``b`` in s/m, ``k`` in N/m, ``m`` in kg).
    errors : dict
        One-sigma uncertainties, same units.
    correlation : ndarray
        Correlation matrix, in the order of ``names``.
    names : tuple of str
        Fitted parameter names.
    features : dict
        Measured feature: (value, standard error, model value at the fit).
    warnings : tuple of str
        Identifiability warnings.
    parameters : PhysicalParameters
        The fitted set-up.
    summary : RecordSummary
        The record's measurement.
    reduced_chi2 : float
        Sum of squared weighted residuals over the degrees of freedom, for the
        waveform (samples against the model, weighted by the record's noise) or for
        the features (``method="features"``).
    method : str
        ``waveform`` or ``features``.
    noise : float
        Standard deviation of the record's noise (N), estimated from the data.
    samples : int
        Samples (waveform) or features the final fit used.
    breakaway_time : float
        Time of a breakaway of the fitted model (s), on the record's clock: fitted with
        the waveform, from the first peak with the features.
    drift : float
        Linear drift of the record's force (N/s): fitted with the waveform, from the
        peaks with the features.
    drift_origin : float
        Time (s) at which the drift term is zero.
    drift_error : float
        Standard error of ``drift`` (N/s): from the waveform fit's covariance, or from the
        peaks' scatter about their trend with the features (NaN with fewer than three).
    upper_limits : dict
        Parameters at their bound (``b = 0``): one-sided 95% upper limit (SI) instead of an
        error (the error is NaN, ``null`` in JSON).

    """

    values: dict[str, float]
    errors: dict[str, float]
    correlation: FloatArray
    names: tuple[str, ...]
    features: dict[str, tuple[float, float, float]]
    warnings: tuple[str, ...]
    parameters: PhysicalParameters
    summary: RecordSummary
    reduced_chi2: float = field(default=math.nan)
    method: str = "waveform"
    noise: float = field(default=math.nan)
    samples: int = 0
    breakaway_time: float = 0.0
    drift: float = 0.0
    drift_origin: float = 0.0
    upper_limits: dict[str, float] = field(default_factory=dict)
    drift_error: float = math.nan

    def model_force(self, t: Any) -> FloatArray:
        """Return the fitted model's force (N) at times ``t`` (s), drift included, overlaying the record."""
        t = np.asarray(t, dtype=float)
        theta = np.log([self.values[n] for n in self.names])
        v0 = float(self.parameters.v0.to("m/s").magnitude)
        load = float(self.parameters.load.to("N").magnitude)
        return model_waveform(theta, self.names, self.breakaway_time, t, v0, load) + self.drift * (
            t - self.drift_origin
        )

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary with units."""
        return {
            "parameters": {
                n: {
                    "value": self.values[n],
                    "error": self.errors[n] if math.isfinite(self.errors[n]) else None,
                    "unit": UNITS[n] or "1",
                    **(
                        {"upper_limit_95": self.upper_limits[n], "at_bound": True}
                        if n in self.upper_limits
                        else {}
                    ),
                }
                for n in self.names
            },
            "correlation": {
                a: {
                    b: None if math.isnan(self.correlation[i, j]) else float(self.correlation[i, j])
                    for j, b in enumerate(self.names)
                }
                for i, a in enumerate(self.names)
            },
            "features": {
                k: {"measured": v[0], "error": v[1], "model": v[2]} for k, v in self.features.items()
            },
            "warnings": list(self.warnings),
            "reduced_chi2": self.reduced_chi2,
            "method": self.method,
            "noise": {"value": self.noise, "unit": "N"},
            "drift": {
                "value": self.drift,
                "error": self.drift_error if math.isfinite(self.drift_error) else None,
                "unit": "N/s",
                "zero_at": self.drift_origin,
                "zero_at_unit": "s",
            },
            "breakaway_time": {"value": self.breakaway_time, "unit": "s"},
            "samples": self.samples,
            "fit_on": (
                f"force waveform ({self.samples} samples), started from a fit on cycle features: "
                if self.method == "waveform"
                else "cycle features: "
            )
            + ", ".join(FEATURES),
        }


#: b below this fraction of a is at its bound b = 0 (F1)
B_AT_BOUND = 1e-4
#: rise of the chi-square that bounds a parameter at a bound from above at 95% (one-sided: the
#: 90% quantile of chi-square with one degree of freedom)
DCHI2_95_ONE_SIDED = 2.706
#: reduced chi-square below which the waveform fit warns that the noise it read is too large
CHI2_LOW = 0.25
#: reduced chi-square above which the fit warns that the model does not describe the record
CHI2_WARN = 2.0
#: a drift this many standard errors from zero is one the record shows (not its noise)
DRIFT_SIGNIFICANT = 4.0
METHODS = ("waveform", "features")


def _check_guess(guess: dict[str, float] | None, names: tuple[str, ...]) -> dict[str, float] | None:
    """Return the starting values as floats; a key that is not fitted would reach nothing."""
    if guess is None:
        return None
    if not isinstance(guess, dict):
        raise ArgumentTypeError(f"guess={guess!r}: expected a dict of starting values by parameter name")
    out = {}
    for key, value in guess.items():
        if not isinstance(key, str):
            raise ArgumentTypeError(
                f"guess: the key {key!r} (type {type(key).__name__}): expected one of {names}"
            )
        if key not in names:
            extra = " (b is fitted with fit_b=True)" if key == "b" else ""
            raise ValueError(f"guess: {key!r} is not a fitted parameter{extra}; expected one of {names}")
        out[key] = check_number(value, f"guess[{key!r}]", what="a positive starting value (SI)")
    return out


def fit_record(
    record: Record,
    *,
    fit_b: bool = False,
    guess: dict[str, float] | None = None,
    method: str = "waveform",
    noise: Any = None,
) -> FitResult:
    """Fit ``mu_s``, ``a``, ``k``, ``m`` (and ``b``) of the paper's model to a stick-slip record.

    Parameters
    ----------
    record : Record
        A measured record with its driving velocity ``v0`` and normal load.
    fit_b : bool, optional
        Also fit the strengthening rate ``b`` of F2 (default: F1, ``b = 0``).
    guess : dict, optional
        Starting values (SI), by parameter name; default from the features.
    method : {"waveform", "features"}, optional
        Fit the force waveform, starting from a fit on cycle features (default), or
        stop at the features (robust to cycle-to-cycle jitter, but its chi-square
        does not measure the fit; see the module docstring).
    noise : force, optional
        Standard deviation of the record's noise, e.g. ``"0.4 mN"``, which weights the
        waveform's residuals; default estimated from the record (the median absolute
        deviation of its second differences; see :func:`stickslip.core.noise.noise_level`).
        Give it when you know it better: a record whose noise is not white, or averaged.

    Returns
    -------
    FitResult

    Raises
    ------
    TypeError
        For an argument of the wrong type: a ``record`` that is not a Record (a plain
        :class:`TypeError`), any other (:class:`~stickslip.ArgumentTypeError`).
    ValueError
        Without ``v0`` or load, for an unknown method, or when the record is not
        stick-slip-like.
    RuntimeError
        When the fit does not converge.

    """
    given_noise = _check_arguments(record, fit_b, method, noise)
    prep = _prepare(record)
    names = ("mu_s", "a", "k", "m", "b") if fit_b else ("mu_s", "a", "k", "m")
    guess = _check_guess(guess, names)
    coords = ("mu_s", "d", "k", "m", "b") if fit_b else names  # see _values
    start = _features_fit(record, prep, coords, guess)
    noise_ = noise_level(record.force) if given_noise is None else given_noise
    if method == "waveform":
        fitted = _waveform_stage(record, prep, coords, start.theta, guess, noise_)
    else:
        fitted = _features_stage(record, prep, coords, start)
    vals = _values(fitted.theta, coords)
    if fit_b and vals["b"] < B_AT_BOUND * vals["a"]:
        # b ran to its bound 0 (in log coordinates it runs away towards -infinity with an error
        # shrinking with it): refit without it and give b an upper limit instead of an error
        return _with_b_at_bound(record, guess, method, vals, given_noise)
    values, errors, corr, rel = _uncertainties(vals, names, fitted.cov, fitted.chi2, fit_b)
    warnings = [
        *_chi2_warnings(method, fitted.chi2, given_noise, noise_, prep.dt),
        *_drift_warnings(record, method, fitted, prep, errors["mu_s"]),
        # what was done to the force before it was fitted (outliers excluded, turned the right
        # way up) and a rail that clipped its peaks (mu_s from them is the rail's): said as for
        # analyze
        *prep.force_notes,
        *_record_warnings(fit_b, prep.summary, prep.dt),
        *_identifiability_warnings(names, rel, corr),
    ]
    return FitResult(
        values,
        errors,
        corr,
        names,
        _feature_table(names, values, start, prep),
        tuple(warnings),
        _fitted_parameters(record, values),
        prep.summary,
        fitted.chi2,
        method,
        noise_,
        fitted.samples,
        fitted.breakaway,
        fitted.drift,
        fitted.drift_origin,
        drift_error=fitted.drift_error,
    )


def _check_arguments(record: Any, fit_b: Any, method: Any, noise: Any) -> float | None:
    """Check :func:`fit_record`'s arguments; return the noise level given (N), or None."""
    if not isinstance(record, Record):
        raise TypeError(f"record={record!r}: expected a Record (read_record(path) reads one)")
    if not isinstance(method, str):
        raise ArgumentTypeError(
            f"method={method!r} (type {type(method).__name__}): expected one of {METHODS}"
        )
    if method not in METHODS:
        raise ValueError(f"method={method!r}: expected one of {METHODS}")
    given_noise = None if noise is None else _noise(noise)
    if record.v0 is None or record.load is None:
        raise DataError(
            f"{record.name}: fitting needs the driving velocity and the normal load "
            "(give '# v0 = ...' and '# load = ...' header lines or --v0/--load)"
        )
    if not isinstance(fit_b, bool | np.bool_):
        raise ArgumentTypeError(f"fit_b={fit_b!r}: expected True or False")
    if given_noise is not None:  # 1e-320 N weighs the fit into overflow, 1e308 N into a chi-square of 0
        span = float(np.ptp(record.force))
        if not 1e-9 * span <= given_noise <= span:
            raise ValueError(
                f"noise={noise!r}: expected a noise level between 1e-9 and 1 times the record's force "
                f"range ({span:.3g} N)"
            )
    return given_noise


class _Prepared(NamedTuple):
    """A record measured for a fit.

    Its cycles and their summary, its force as measured and what was done to it (for the
    warnings), its driving velocity (m/s) and normal load (N), and its sample interval (s).
    """

    table: CycleTable
    summary: RecordSummary
    force: FloatArray
    force_notes: list[str]
    v0: float
    load: float
    dt: float


def _prepare(record: Record) -> _Prepared:
    """Measure the record's cycles, and its force as measured once for every fit of it."""
    table, summary = measure_record(record)
    # the force as measured (outliers out, the right way up), once for every waveform fit,
    # and what was done to it, for the warnings
    force, force_notes, _ = clean_force(record)
    v0 = float(record.v0.to("m/s").magnitude)  # type: ignore[union-attr]
    load = float(record.load.to("N").magnitude)  # type: ignore[union-attr]
    dt = float(np.median(np.diff(record.time)))  # the sample interval (s)
    return _Prepared(table, summary, force, force_notes, v0, load, dt)


def _features_fit(
    record: Record,
    prep: _Prepared,
    coords: tuple[str, ...],
    guess: dict[str, float] | None,
    fixed: dict[str, float] | None = None,
) -> _Features:
    """Fit the prepared record's cycle features (:func:`~.fit_stages._fit_features`)."""
    return _fit_features(record, prep.table, prep.summary, coords, prep.v0, prep.load, guess, fixed)


def _waveform_fit(
    record: Record,
    prep: _Prepared,
    coords: tuple[str, ...],
    theta: FloatArray,
    noise: float,
    fixed_b: float = 0.0,
) -> _Fit:
    """Fit the prepared record's waveform from ``theta`` (:func:`~.fit_stages._fit_waveform`)."""
    return _fit_waveform(
        record, prep.force, prep.table, prep.summary, coords, theta, prep.v0, prep.load, noise, fixed_b
    )


def _features_stage(record: Record, prep: _Prepared, coords: tuple[str, ...], start: _Features) -> _Fit:
    """Stop at the fit on cycle features: the drift from the peaks, a breakaway on the first peak."""
    return _Fit(
        theta=start.theta,
        cov=_covariance(start.jac),
        chi2=start.chi2 / max(1, len(FEATURES) - len(coords)),
        samples=len(FEATURES),
        breakaway=_first_breakaway(start.theta, coords, prep.v0, prep.load, float(prep.table.peak_time[0])),
        drift=float(prep.summary.drift),
        drift_error=_peaks_drift_error(prep.table),
        drift_origin=float(record.time[0]),
        cost=start.chi2,
    )


def _waveform_stage(
    record: Record,
    prep: _Prepared,
    coords: tuple[str, ...],
    theta: FloatArray,
    guess: dict[str, float] | None,
    noise: float,
) -> _Fit:
    """Fit the force waveform from the features' parameters ``theta``.

    Where the drop falls between samples and the fit misses the record, it is restarted in
    ``m`` (:func:`_restart_in_m`), unless ``m`` was given a starting value. The drift's
    error is scaled as the parameters' are, by the square root of the reduced chi-square
    when it exceeds 1.
    """
    fitted = _waveform_fit(record, prep, coords, theta, noise)
    unresolved = prep.summary.drop_time < 3.0 * prep.dt
    if fitted.chi2 > CHI2_WARN and unresolved and (guess is None or "m" not in guess):
        fitted = _restart_in_m(record, prep, coords, theta, guess, noise, fitted)
    return fitted._replace(drift_error=fitted.drift_error * math.sqrt(max(1.0, fitted.chi2)))


def _restart_in_m(
    record: Record,
    prep: _Prepared,
    coords: tuple[str, ...],
    theta: FloatArray,
    guess: dict[str, float] | None,
    noise: float,
    best: _Fit,
) -> _Fit:
    """Return the best of ``best`` and waveform fits started with ``m`` away from the features' value.

    With the drop between samples the features cannot place m (nor a, along the a-m valley),
    and from a poor start the waveform fit wanders off (2 Hz: reduced chi2 900 from the
    features' m = 3.6 kg, 0.86 from 0.3 kg). Each start is the features refitted with m held
    at a hundredth of their value up to three times it; the fit of least cost is kept.
    """
    free = tuple(x for x in coords if x != "m")
    m_features = _values(theta, coords)["m"]
    for factor in (0.01, 0.03, 0.1, 0.3, 3.0):
        m = m_features * factor
        try:
            th, _, _, _, _ = _features_fit(record, prep, free, guess, {"m": m})
            start = np.insert(th, coords.index("m"), math.log(m))
            other = _waveform_fit(record, prep, coords, start, noise)
        except (RuntimeError, DataError):
            continue
        if other.cost < best.cost:
            best = other
    return best


def _uncertainties(
    vals: dict[str, float], names: tuple[str, ...], cov: FloatArray, chi2: float, fit_b: bool
) -> tuple[dict[str, float], dict[str, float], FloatArray, FloatArray]:
    """Return the fitted values, their errors, their correlations and their relative errors.

    ``cov`` is the covariance of the fit's coordinates; the errors are scaled by the square
    root of the reduced chi-square ``chi2`` when it exceeds 1.
    """
    values = {x: float(vals[x]) for x in names}
    # covariance of the log-parameters from that of the coordinates: log a = log(d + b)
    to_log = np.eye(len(names))
    if fit_b:
        ia, ib = names.index("a"), names.index("b")
        to_log[ia, ia] = (values["a"] - values["b"]) / values["a"]
        to_log[ia, ib] = values["b"] / values["a"]
    cov_log = to_log @ cov @ to_log.T * max(1.0, chi2)
    rel = np.sqrt(np.clip(np.diag(cov_log), 0, None))
    errors = {x: values[x] * float(r) for x, r in zip(names, rel, strict=True)}
    d = np.sqrt(np.clip(np.diag(cov_log), 1e-300, None))
    corr = cov_log / np.outer(d, d)
    return values, errors, corr, rel


def _chi2_warnings(method: str, chi2: float, given_noise: float | None, noise: float, dt: float) -> list[str]:
    """Say what the reduced chi-square tells of the fit, and of the noise that weights it."""
    warnings = []
    if method == "features" and given_noise is not None:  # the features do not use it: say so
        warnings.append(
            "the noise given weights the waveform fit only: the features are weighted by their "
            "cycle-to-cycle spread"
        )
    if chi2 > CHI2_WARN and method == "features":
        # on records the model itself made this is the features' own bias, not a misfit
        warnings.append(
            f"reduced chi-square {chi2:.2f} > {CHI2_WARN:g} over the cycle features: they differ from "
            "the model's by more than their cycle-to-cycle spread (a feature measured on sampled data "
            f"carries a bias of up to a sample interval, {dt:.3g} s, that the spread does not show); "
            "errors scaled up by its square root; the waveform fit (the default) uses every sample"
        )
    elif chi2 > CHI2_WARN:
        warnings.append(
            f"reduced chi-square {chi2:.2f} > {CHI2_WARN:g}: the model does not describe the record "
            f"to within its noise ({1e3 * noise:.3g} mN); errors scaled up by its square root"
        )
    elif method == "waveform" and given_noise is None and chi2 < CHI2_LOW:
        # the noise read off the record is larger than the misfit: the errors scale with it
        # (a reduced chi-square of 0.045 comes with errors 4.8 times too large)
        warnings.append(
            f"reduced chi-square {chi2:.2g} < {CHI2_LOW:g}: the record fits better than the noise read "
            f"off it ({1e3 * noise:.3g} mN), so that estimate is too large and the errors with it, by "
            f"about {1.0 / math.sqrt(max(chi2, 1e-300)):.2g} times; give the noise if you know it "
            "(--noise '0.4 mN', noise= in Python)"
        )
    return warnings


def _drift_warnings(
    record: Record, method: str, fitted: _Fit, prep: _Prepared, mu_s_error: float
) -> list[str]:
    """Say where the record's drift moves ``mu_s`` by more than its error over the fitted window.

    A drift the record shows (significant) that moves mu_s by more than its error between
    the window's middle and its ends: where the sensor read true decides mu_s. (Compared
    with the noise instead, a drift of 2 uN/s over 200 s that moves mu_s by 44 of its errors
    would pass unsaid: mu_s, fitted on every sample, is known far better than one sample's
    noise.)
    """
    drift, drift_error = fitted.drift, fitted.drift_error
    half_window = (
        0.5 * fitted.samples * prep.dt
        if method == "waveform"
        else 0.5 * float(record.time[-1] - record.time[0])
    )
    shift = abs(drift) * half_window / prep.load
    if not (abs(drift) > DRIFT_SIGNIFICANT * drift_error and shift > mu_s_error):
        return []
    return [
        f"the force drifts ({1e3 * drift:+.3g} +- {1e3 * drift_error:.2g} mN/s, "
        f"{1e3 * abs(drift) * half_window:.3g} mN from the fitted window's middle to its ends, "
        f"{shift / mu_s_error:.3g} times mu_s's error): mu_s and a describe the force at t = "
        f"{fitted.drift_origin:.6g} s, where the drift term is zero; if the force sensor read true "
        "at another time t', the static friction coefficient is about mu_s + drift x (t' - t) / "
        "load, and a moves with it (refit the record with the drift removed from t')"
    ]


def _record_warnings(fit_b: bool, summary: RecordSummary, dt: float) -> list[str]:
    """Say what in the record keeps the model from describing it: no stick, or a drop between samples."""
    warnings = []
    if not fit_b and summary.stick_fraction == 0.0:
        # fitted to a pure-slip record, F1 gives k and m with errors of 0.06 % for values half
        # the truth
        warnings.append(
            "the record never sticks (stick fraction 0, from its velocity): a pure-slip oscillation, "
            "which the F1 law (friction falling at every speed) cannot make, so these parameters are "
            "not the record's, whatever their errors; F2 (--fit-b) has a pure-slip regime"
        )
    if summary.drop_time < dt:
        warnings.append(
            f"a and m are not identifiable: the force drop is not resolved (it falls within one "
            f"sample interval, {dt:.3g} s; measured drop time {summary.drop_time:.3g} s); the fit sees "
            "the waveform only at the samples, may sit at one of several minima along a and m, and "
            "their errors are local (sample faster than the drop, or start elsewhere with fit_record's "
            "guess= and compare the chi-square)"
        )
    return warnings


def _identifiability_warnings(names: tuple[str, ...], rel: FloatArray, corr: FloatArray) -> list[str]:
    """Name the parameters the record does not determine, alone or as a correlated pair."""
    warnings = []
    for x, r in zip(names, rel, strict=True):
        if r > 0.5:
            warnings.append(
                f"{x} is not identifiable from this record (relative uncertainty "
                f"{_relative(r)}); the record does not constrain it"
            )
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            # strongly correlated errors are fine while each parameter is well determined (a and
            # m of a well-sampled record: 0.997, each to 0.1%); a pair is not identifiable when it
            # is also poorly determined one by one; nearly perfectly correlated, say so
            if abs(corr[i, j]) > 0.99 and max(rel[i], rel[j]) > 0.1:
                warnings.append(
                    f"{names[i]} and {names[j]} are correlated ({corr[i, j]:+.3f}): "
                    "only a combination of them is determined"
                )
            elif abs(corr[i, j]) > 0.9999:
                warnings.append(
                    f"{names[i]} and {names[j]} are correlated ({corr[i, j]:+.5f}): each is determined "
                    f"(to {100 * rel[i]:.2g}% and {100 * rel[j]:.2g}%), but their errors move together; "
                    "propagate them with the correlation matrix"
                )
    return warnings


def _feature_table(
    names: tuple[str, ...], values: dict[str, float], start: _Features, prep: _Prepared
) -> dict[str, tuple[float, float, float]]:
    """Return each cycle feature: its measured value, its standard error, the fitted model's value."""
    theta = np.log([values[x] for x in names])
    model = _model_features(theta, names, {"b": 0.0}, prep.v0, prep.load)
    return {k: (float(start.data[i]), float(start.err[i]), float(model[i])) for i, k in enumerate(FEATURES)}


def _fitted_parameters(record: Record, values: dict[str, float]) -> PhysicalParameters:
    """Return the fitted set-up: the record's load and driving velocity with the fitted values."""
    return PhysicalParameters(
        mass=Q_(values["m"], "kg"),
        stiffness=Q_(values["k"], "N/m"),
        load=record.load,
        v0=record.v0,
        law=PhysicalWeakeningLaw(
            mu_s=values["mu_s"], a=Q_(values["a"], "s/m"), b=Q_(values.get("b", 0.0), "s/m")
        ),
    )


def _relative(r: float) -> str:
    """Say a relative uncertainty in words: a percentage, a multiple, or none at all."""
    if not math.isfinite(r):
        return "unbounded: the residuals do not depend on it"
    return f"{r:.0%}" if r < 10 else f"{r:.2g} times its value"


def _noise(value: Any) -> float:
    """Return the user's noise level (N), validated."""
    from ..units import parse_quantity

    return float(parse_quantity(value, "noise", "[force]", "0.4 mN").to("N").magnitude)


def _with_b_at_bound(
    record: Record,
    guess: dict[str, float] | None,
    method: str,
    at_bound: dict[str, float],
    noise: float | None,
) -> FitResult:
    """Refit without ``b`` (F1) and report ``b = 0`` with a one-sided 95% upper limit.

    The limit is where the profile of the chi-square (every other parameter refitted with
    ``b`` held fixed) has risen by 2.71 (times the reduced chi-square when it exceeds 1)
    above its value at ``b = 0``: one-sided 95% for a parameter bounded below. The
    linearised (Fisher) error understates it: ``b`` moves the stick time, and with it every
    later drop, far from linearly.
    """
    f1_guess = None if guess is None else {k: v for k, v in guess.items() if k != "b"}
    f1 = fit_record(record, fit_b=False, guess=f1_guess, method=method, noise=noise)
    theta = np.log([f1.values[n] for n in f1.names])
    prep = _prepare(record)
    scale = max(1.0, f1.reduced_chi2)

    def profile(b: float) -> float:
        if method == "waveform":
            return _waveform_fit(record, prep, f1.names, theta, f1.noise, fixed_b=b).cost
        return _features_fit(record, prep, f1.names, f1.values, {"b": b}).chi2

    c0 = profile(0.0)
    # sqrt(delta chi2) is about linear in b: a secant on it, from a thousandth of a
    b, target = 1e-3 * f1.values["a"], math.sqrt(DCHI2_95_ONE_SIDED * scale)
    for _ in range(12):
        rise = math.sqrt(max(profile(b) - c0, 0.0))
        if abs(rise / target - 1.0) < 0.02:
            break
        b = b * target / rise if rise > 0 else 10.0 * b
    upper = b
    names = (*f1.names, "b")
    corr = np.full((len(names), len(names)), math.nan)
    corr[:-1, :-1] = f1.correlation
    corr[-1, -1] = 1.0
    note = (
        f"b is at its bound 0 (the fit drove it towards 0, to {at_bound['b']:.2g} s/m): the record is F1; "
        f"b < {upper:.3g} s/m (95%, one-sided, from the profile of the chi-square)"
    )
    return dataclasses.replace(
        f1,
        values={**f1.values, "b": 0.0},
        errors={**f1.errors, "b": math.nan},
        correlation=corr,
        names=names,
        warnings=(*f1.warnings, note),
        upper_limits={"b": upper},
    )
