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
from scipy.optimize import least_squares

from ..core.api import run_attractors, run_trajectory
from ..core.noise import noise_level
from ..core.results import AttractorRows, EventKind, Regime, Status
from ..errors import ArgumentTypeError
from ..io.errors import DataError
from ..io.records import Record
from ..laws import PhysicalWeakeningLaw
from ..laws.weakening import WEAKENING
from ..models.parameters import PhysicalParameters
from ..units import Q_, check_number
from .records import CycleTable, RecordSummary, clean_force, measure_record

__all__ = ["FitResult", "fit_record"]

FloatArray = npt.NDArray[np.float64]
FEATURES = ("peak_force", "trough_force", "period", "rise_slope", "drop_time")
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


def _cycle(c: float, p: float, nu: float, rtol: float = 1e-10) -> AttractorRows:
    """Return the steady stick-slip cycle of the paper's law (``c``, ``p``) at ``nu``, from breakaway."""
    return run_attractors(
        WEAKENING.kernel(),
        [c, p],
        [nu],
        from_breakaway=True,
        rtol=rtol,
        atol=1e-12,
        max_slip_time=1e4,
        conv_tol=1e-8,
    )


def _fall_time_model(c: float, p: float, nu: float, t_slip: float, time_scale: float) -> float:
    """90%-10% fall time (s) of the model's force drop, from a dense trajectory of the slip."""
    tau = np.linspace(0.0, t_slip, 600)
    y, _, _, status = run_trajectory(WEAKENING.kernel(), [c, p], nu, 1.0, 0.0, tau, rtol=1e-9, atol=1e-12)
    if status != Status.OK:
        return math.nan
    s = y[:, 0]
    i_max = int(np.argmax(s))
    seg, tt = s[i_max:], tau[i_max:]
    hi, lo = s[i_max], float(seg.min())
    a, b = lo + 0.9 * (hi - lo), lo + 0.1 * (hi - lo)
    ta = np.interp(a, seg[::-1], tt[::-1])
    tb_idx = int(np.argmax(seg < b))
    tb = np.interp(b, [seg[tb_idx], seg[tb_idx - 1]], [tt[tb_idx], tt[tb_idx - 1]]) if tb_idx else tt[0]
    return float(max(tb - ta, 0.0) * time_scale)


def _values(theta: FloatArray, names: tuple[str, ...], fixed_b: float = 0.0) -> dict[str, float]:
    """Return the physical parameters (SI) from the fit's log-coordinates ``names``.

    With ``b`` fitted, the coordinate is ``d = a - b`` instead of ``a``: near breakaway
    F2 is ``f(w) = 1 - (c - p) w + ...``, so a record pins down ``a - b`` far better than
    ``a`` and ``b`` apart, and in ``(a, b)`` the cost is a long curved valley.
    """
    vals = {"b": fixed_b}
    # an optimiser's wild trial step must not overflow: exp(700) is absurd enough to fail the model
    vals.update({n: math.exp(min(float(x), 700.0)) for n, x in zip(names, theta, strict=True)})
    if "d" in vals:
        vals["a"] = vals.pop("d") + vals["b"]
    return vals


def _model_features(
    theta: FloatArray, names: tuple[str, ...], fixed: dict[str, float], v0: float, load: float
) -> FloatArray:
    vals = dict(fixed)
    vals.update(_values(theta, names, fixed.get("b", 0.0)))
    mu_s, a, b, k, m = vals["mu_s"], vals["a"], vals.get("b", 0.0), vals["k"], vals["m"]
    force = mu_s * load
    if not (force > 0 and k * m > 0 and math.isfinite(k * m / force)):  # an absurd trial step
        return np.full(len(FEATURES), np.nan)
    beta = math.sqrt(k * m) / force
    nu = beta * v0
    c, p = a / beta, b / beta
    try:
        out = _cycle(c, p, nu, rtol=1e-9)
    except ValueError:  # a trial step beyond the engine's range (lp[0]=2e23 ended the fit once)
        return np.full(len(FEATURES), np.nan)
    if not out.is_regime(Regime.STICK_SLIP)[0]:
        return np.full(len(FEATURES), np.nan)
    ts = math.sqrt(m / k)
    t_slip = float(out.period[0] - out.stick_time[0])
    return np.array(
        [
            force * out.s_max[0],
            force * out.s_min[0],
            out.period[0] * ts,
            k * v0,
            _fall_time_model(c, p, nu, t_slip, ts),
        ]
    )


#: b below this fraction of a is at its bound b = 0 (F1)
B_AT_BOUND = 1e-4
#: rise of the chi-square that bounds a parameter at a bound from above at 95% (one-sided: the
#: 90% quantile of chi-square with one degree of freedom)
DCHI2_95_ONE_SIDED = 2.706
#: largest number of samples the waveform fit uses (a window of whole cycles)
MAX_WAVEFORM_SAMPLES = 200_000
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
    if given_noise is not None:  # 1e-320 N weighed the fit into overflow, 1e308 N into a chi-square of 0
        span = float(np.ptp(record.force))
        if not 1e-9 * span <= given_noise <= span:
            raise ValueError(
                f"noise={noise!r}: expected a noise level between 1e-9 and 1 times the record's force "
                f"range ({span:.3g} N)"
            )
    table, summary = measure_record(record)
    # the force as measured (outliers out, the right way up), once for every waveform fit below,
    # and what was done to it, for the warnings
    force, force_notes, _ = clean_force(record)
    v0 = float(record.v0.to("m/s").magnitude)
    load = float(record.load.to("N").magnitude)
    names = ("mu_s", "a", "k", "m", "b") if fit_b else ("mu_s", "a", "k", "m")
    guess = _check_guess(guess, names)
    coords = ("mu_s", "d", "k", "m", "b") if fit_b else names  # see _values
    theta, jac, chi2, data_a, err_a = _fit_features(record, table, summary, coords, v0, load, guess)
    cov = _covariance(jac)
    noise_ = noise_level(record.force) if given_noise is None else given_noise
    samples = len(FEATURES)
    drift, drift_origin = float(summary.drift), float(record.time[0])
    drift_error = _peaks_drift_error(table)
    dt = float(np.median(np.diff(record.time)))  # the sample interval (s)
    if method == "waveform":
        fitted = _fit_waveform(record, force, table, summary, coords, theta, v0, load, noise_)
        if fitted.chi2 > CHI2_WARN and summary.drop_time < 3.0 * dt and (guess is None or "m" not in guess):
            # the drop falls between samples: the features cannot place m (nor a, along the a-m
            # valley), and from a poor start the waveform fit wanders off (2 Hz: reduced chi2 900
            # from the features' m = 3.6 kg, 0.86 from 0.3 kg); start again from the features
            # refitted with m held at values down to a hundredth and up to three times, keep the best
            free = tuple(x for x in coords if x != "m")
            m_features = _values(theta, coords)["m"]
            for factor in (0.01, 0.03, 0.1, 0.3, 3.0):
                m = m_features * factor
                try:
                    th, _, _, _, _ = _fit_features(record, table, summary, free, v0, load, guess, {"m": m})
                    start = np.insert(th, coords.index("m"), math.log(m))
                    other = _fit_waveform(record, force, table, summary, coords, start, v0, load, noise_)
                except (RuntimeError, DataError):
                    continue
                if other.cost < fitted.cost:
                    fitted = other
        theta, cov, chi2, samples, breakaway = (
            fitted.theta,
            fitted.cov,
            fitted.chi2,
            fitted.samples,
            fitted.breakaway,
        )
        drift, drift_error, drift_origin = (
            fitted.drift,
            fitted.drift_error * math.sqrt(max(1.0, chi2)),
            fitted.drift_origin,
        )
    else:
        chi2 = chi2 / max(1, len(FEATURES) - len(names))
        breakaway = _first_breakaway(theta, coords, v0, load, float(table.peak_time[0]))
    vals = _values(theta, coords)
    if fit_b and vals["b"] < B_AT_BOUND * vals["a"]:
        # b ran to its bound 0 (in log coordinates it runs away towards -infinity with an error
        # shrinking with it): refit without it and give b an upper limit instead of an error
        return _with_b_at_bound(record, guess, method, vals, given_noise)
    values = {x: float(vals[x]) for x in names}
    # covariance of the log-parameters from that of the coordinates: log a = log(d + b)
    to_log = np.eye(len(names))
    if fit_b:
        ia, ib = names.index("a"), names.index("b")
        to_log[ia, ia] = (values["a"] - values["b"]) / values["a"]
        to_log[ia, ib] = values["b"] / values["a"]
    cov_log = to_log @ cov @ to_log.T * max(1.0, chi2)
    theta = np.log([values[x] for x in names])
    rel = np.sqrt(np.clip(np.diag(cov_log), 0, None))
    errors = {x: values[x] * float(r) for x, r in zip(names, rel, strict=True)}
    d = np.sqrt(np.clip(np.diag(cov_log), 1e-300, None))
    corr = cov_log / np.outer(d, d)
    warnings = []
    if method == "features" and given_noise is not None:  # it was dropped without a word
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
            f"to within its noise ({1e3 * noise_:.3g} mN); errors scaled up by its square root"
        )
    elif method == "waveform" and given_noise is None and chi2 < CHI2_LOW:
        # the noise read off the record is larger than the misfit: the errors scale with it
        # (0.045 and errors 4.8 times too large, without a word: the measured-data audit)
        warnings.append(
            f"reduced chi-square {chi2:.2g} < {CHI2_LOW:g}: the record fits better than the noise read "
            f"off it ({1e3 * noise_:.3g} mN), so that estimate is too large and the errors with it, by "
            f"about {1.0 / math.sqrt(max(chi2, 1e-300)):.2g} times; give the noise if you know it "
            "(--noise '0.4 mN', noise= in Python)"
        )
    half_window = (
        0.5 * samples * dt if method == "waveform" else 0.5 * float(record.time[-1] - record.time[0])
    )
    # a drift the record shows (significant) that moves mu_s by more than its error between the
    # window's middle and its ends: where the sensor read true decides mu_s. (Compared with the
    # noise instead, a drift of 2 uN/s over 200 s moved mu_s by 44 of its errors unannounced:
    # mu_s, fitted on every sample, is known far better than one sample's noise.)
    shift = abs(drift) * half_window / load
    if abs(drift) > DRIFT_SIGNIFICANT * drift_error and shift > errors["mu_s"]:
        warnings.append(
            f"the force drifts ({1e3 * drift:+.3g} +- {1e3 * drift_error:.2g} mN/s, "
            f"{1e3 * abs(drift) * half_window:.3g} mN from the fitted window's middle to its ends, "
            f"{shift / errors['mu_s']:.3g} times mu_s's error): mu_s and a describe the force at t = "
            f"{drift_origin:.6g} s, where the drift term is zero; if the force sensor read true "
            "at another time t', the static friction coefficient is about mu_s + drift x (t' - t) / "
            "load, and a moves with it (refit the record with the drift removed from t')"
        )
    # what was done to the force before it was fitted (outliers excluded, turned the right way
    # up) and a rail that clipped its peaks (mu_s from them is the rail's): said as for analyze
    warnings += force_notes
    if not fit_b and summary.stick_fraction == 0.0:
        # k and m came with errors of 0.06 % for values half the truth (the measured-data audit)
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
    model = _model_features(theta, names, {"b": 0.0}, v0, load)
    feats = {k: (float(data_a[i]), float(err_a[i]), float(model[i])) for i, k in enumerate(FEATURES)}
    params = PhysicalParameters(
        mass=Q_(values["m"], "kg"),
        stiffness=Q_(values["k"], "N/m"),
        load=record.load,
        v0=record.v0,
        law=PhysicalWeakeningLaw(
            mu_s=values["mu_s"], a=Q_(values["a"], "s/m"), b=Q_(values.get("b", 0.0), "s/m")
        ),
    )
    return FitResult(
        values,
        errors,
        corr,
        names,
        feats,
        tuple(warnings),
        params,
        summary,
        chi2,
        method,
        noise_,
        samples,
        breakaway,
        drift,
        drift_origin,
        drift_error=drift_error,
    )


def _relative(r: float) -> str:
    """Say a relative uncertainty in words: a percentage, a multiple, or none at all."""
    if not math.isfinite(r):
        return "unbounded: the residuals do not depend on it"
    return f"{r:.0%}" if r < 10 else f"{r:.2g} times its value"


def _covariance(jac: FloatArray) -> FloatArray:
    """Inverse of the normal matrix ``J^T J``: the parameters' covariance (weighted residuals).

    Inverted with its columns scaled to unit norm, so parameters of very different
    sensitivity do not make it look singular; a direction it does not constrain at all (an
    eigenvalue of the scaled matrix below 1e-14 of the largest, or a parameter the residuals
    do not depend on) gives the parameters along it an infinite variance. (A pseudo-inverse
    gives that direction zero variance: a parameter the record does not constrain came out
    with an error of 1e-19 s/m.)
    """
    normal = jac.T @ jac
    scale = np.sqrt(np.diag(normal))
    unit = np.where(scale > 0, scale, 1.0)
    w, v = np.linalg.eigh(normal / np.outer(unit, unit))
    null = w <= 1e-14 * max(float(w.max()), 0.0)
    inv_w = np.where(null, 0.0, 1.0 / np.where(null, 1.0, w))
    cov = (v * inv_w) @ v.T / np.outer(unit, unit)
    free = np.any(np.abs(v[:, null]) > 1e-8, axis=1) | (scale == 0)
    cov[free, :] = np.nan
    cov[:, free] = np.nan
    cov[free, free] = np.inf
    return np.asarray(cov, dtype=float)


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
    v0 = float(record.v0.to("m/s").magnitude)  # type: ignore[union-attr]
    load = float(record.load.to("N").magnitude)  # type: ignore[union-attr]
    theta = np.log([f1.values[n] for n in f1.names])
    table, summary = measure_record(record)
    force = clean_force(record)[0]
    scale = max(1.0, f1.reduced_chi2)

    def profile(b: float) -> float:
        if method == "waveform":
            fit = _fit_waveform(record, force, table, summary, f1.names, theta, v0, load, f1.noise, fixed_b=b)
            return fit.cost
        _, _, cost, _, _ = _fit_features(record, table, summary, f1.names, v0, load, f1.values, {"b": b})
        return cost

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


def _fit_features(
    record: Record,
    table: CycleTable,
    summary: RecordSummary,
    names: tuple[str, ...],
    v0: float,
    load: float,
    guess: dict[str, float] | None,
    fixed: dict[str, float] | None = None,
) -> tuple[FloatArray, FloatArray, float, FloatArray, FloatArray]:
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
    return best.x, best.jac, 2.0 * best.cost, data_a, err_a


def _physical(
    theta: FloatArray, names: tuple[str, ...], v0: float, load: float, fixed_b: float = 0.0
) -> dict[str, float]:
    vals = _values(theta, names, fixed_b)
    force = vals["mu_s"] * load
    beta = math.sqrt(vals["k"] * vals["m"]) / force
    return {
        "force": force,
        "nu": beta * v0,
        "c": vals["a"] / beta,
        "p": vals["b"] / beta,
        "time": math.sqrt(vals["m"] / vals["k"]),
    }


def model_waveform(
    theta: FloatArray,
    names: tuple[str, ...],
    t0: float,
    t: FloatArray,
    v0: float,
    load: float,
    fixed_b: float = 0.0,
) -> FloatArray:
    """Return the spring force (N) of the model's steady cycle at times ``t``, breakaway at ``t0``.

    ``theta`` are the log-parameters ``names`` (``mu_s, a, k, m`` and ``b``; without ``b`` in
    ``names`` it is ``fixed_b``, s/m). The stick phase
    is the exact ramp ``s_stop + nu (tau - t_slip)``; the slip phase from breakaway
    ``(1, 0)`` is sampled on the engine's dense output. NaN where the model does not stick.
    """
    try:
        ph = _physical(theta, names, v0, load, fixed_b)
    except (ZeroDivisionError, OverflowError, ValueError):  # an optimiser's absurd trial step
        return np.full(t.shape, np.nan)
    nu, c, p = ph["nu"], ph["c"], ph["p"]
    if not all(math.isfinite(x) and x >= 0.0 for x in (nu, c, p)) or nu == 0.0:
        return np.full(t.shape, np.nan)
    try:
        row = _cycle(c, p, nu)
    except ValueError:  # a trial step beyond the engine's range (nu above 1e12, c above 1e15)
        return np.full(t.shape, np.nan)
    if not row.is_regime(Regime.STICK_SLIP)[0]:
        return np.full(t.shape, np.nan)
    period = float(row.period[0])
    t_slip = period - float(row.stick_time[0])
    tau = np.mod((t - t0) / ph["time"], period)
    s = float(row.s_stop[0]) + nu * (tau - t_slip)
    slip = tau < t_slip
    if slip.any():
        idx = np.flatnonzero(slip)
        order = np.argsort(tau[idx], kind="stable")
        y, _, _, status = run_trajectory(
            WEAKENING.kernel(), [c, p], nu, 1.0, 0.0, tau[idx[order]], rtol=1e-10, atol=1e-12
        )
        if status != Status.OK:
            return np.full(t.shape, np.nan)
        s[idx[order]] = y[:, 0]
    return ph["force"] * s


class _Waveform(NamedTuple):
    """A waveform fit of :func:`_fit_waveform`.

    The log-parameters, their covariance (phase and drift marginalised, not scaled by the
    chi-square), the reduced chi-square, the samples used, a breakaway time (s), the drift
    (N/s) and its standard error (not scaled), the time the drift term is zero at (s), and the
    total chi-square.
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

    The record's drift is the slope of its peaks against time (:func:`measure_record`); the
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
) -> _Waveform:
    """Fit the force waveform over a window of whole cycles (``b`` held at ``fixed_b`` unless fitted).

    ``force`` is the record's force as measured (:func:`clean_force`: outliers out, the right
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
    # first breakaway: where the model's first peak falls on the data's first peak
    ph = _physical(theta0, names, v0, load, fixed_b)
    tau_peak = _time_of_max(ph, _cycle(ph["c"], ph["p"], ph["nu"]))
    # the phase is anchored at the peak in the middle of the window: every drop sits at
    # t_ref + j T, and with j centred the phase and the period are not correlated (as a
    # regression centres its abscissa); anchored at the first drop they are, and the cost
    # becomes a long curved valley that the optimisers crawl along
    inside = table.peak_time[(table.peak_time >= tw[0]) & (table.peak_time <= tw[-1])]
    t_peak = float(inside[len(inside) // 2]) if inside.size else float(table.peak_time[0])
    t_ref = t_peak - tau_peak * ph["time"]
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
    return _Waveform(
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


class _Jacobian:
    """Central-difference Jacobian of ``fun`` (``n`` residuals), each step one conditional standard error.

    Forward differences are not enough here: near the minimum the gradient's components
    are large and nearly cancel along the Newton step (the cost is very stiff in the peak
    force and the period), and their O(h) error flips its sign. Nor is a fixed step: moved
    alone, a parameter changes the cost by 1 (one standard error, all others held) over
    ``1 / |J_i|``, which is 1e-7 in log mu_s for 60 cycles at 100 Hz, and a step of 1e-6
    there spans ten of them: the residuals of the samples on the drops are far from linear
    over it, the gradient came out with the wrong sign and the search stopped 20 standard
    errors from the minimum with no warning (the data audit). So each step is
    ``1 / |J_i|`` from the previous Jacobian (first 1e-6), between 1e-10 and 1e-6 of
    ``max(1, |x_i|)``: the model's own error (rtol 1e-10) over such a step is still far
    below the derivative.
    """

    def __init__(self, fun: Any, n: int) -> None:
        self.fun, self.n = fun, n
        self.steps: FloatArray | None = None

    def __call__(self, x: FloatArray) -> FloatArray:
        scale = np.maximum(1.0, np.abs(x))
        steps = 1e-6 * scale if self.steps is None else self.steps
        jac = np.empty((self.n, x.size))
        for i in range(x.size):
            e = np.zeros_like(x)
            e[i] = steps[i]
            jac[:, i] = (self.fun(x + e) - self.fun(x - e)) / (2.0 * steps[i])
        norm = np.linalg.norm(jac, axis=0)
        with np.errstate(divide="ignore"):
            one_error = np.where(norm > 0, 1.0 / norm, np.inf)
        self.steps = np.clip(one_error, 1e-10 * scale, 1e-6 * scale)
        return jac


def _minimise(fun: Any, x0: FloatArray, name: str) -> tuple[FloatArray, FloatArray, float]:
    """Minimise ``sum(fun(x)**2)``: Levenberg-Marquardt, then a quasi-Newton check of the minimum.

    The Jacobian is by central differences: near the minimum the gradient's components
    are large and nearly cancel along the step (the cost is very stiff in the peak force
    and the period), and forward differences make the methods stop early. With noise on
    every sample the residuals do not vanish at the minimum, and the curvature that
    Gauss-Newton leaves out (sum of residual times second derivative) is not small along
    the poorly determined combination of parameters; BFGS updates of the Gauss-Newton
    matrix pick it up where Levenberg-Marquardt stops short. Stops when the predicted or
    the achieved decrease of the cost is below 1e-4 (a ten-thousandth of the change that
    moves a parameter by one standard error), or when five steps gain less than 0.5
    together (a flat direction).

    Returns the minimiser, the Jacobian of the residuals there and the cost.
    """
    n = fun(x0).size
    jacobian = _Jacobian(fun, n)
    jacobian(x0)  # the first steps: one standard error of each parameter at the start
    res = least_squares(fun, x0, jac=jacobian, method="lm", x_scale="jac", max_nfev=1000)
    x = res.x
    r = fun(x)
    jac = jacobian(x)
    g = 2.0 * jac.T @ r
    hess = 2.0 * jac.T @ jac
    cost = float(r @ r)
    history = [cost]
    for _ in range(200):
        # a flat direction (a parameter the record does not determine) is crawled along forever,
        # each step gaining a few hundredths: five steps together gaining less than 0.5 (the
        # points are within a standard error of each other) end the search
        if len(history) > 5 and history[-6] - history[-1] < 0.5:
            break
        try:
            step = -np.linalg.solve(hess, g)
        except np.linalg.LinAlgError:
            step = -np.linalg.lstsq(hess, g, rcond=None)[0]
        decrement = float(-g @ step)
        if decrement < 1e-4:
            break
        t = 1.0
        while True:
            x_new = x + t * step
            r_new = fun(x_new)
            cost_new = float(r_new @ r_new)
            if cost_new <= cost - 1e-4 * t * decrement or t < 1e-6:
                break
            t *= 0.5
        if cost_new > cost - 1e-4:
            # no descent along the step (at the minimum to the precision of the model), or a
            # flat direction (a parameter the record does not determine: the warnings say so)
            if cost_new < cost:
                x, r, cost = x_new, r_new, cost_new
                jac = jacobian(x)
            break
        jac_new = jacobian(x_new)
        g_new = 2.0 * jac_new.T @ r_new
        sv, yv = x_new - x, g_new - g
        if sv @ yv > 0:
            hs = hess @ sv
            hess = hess - np.outer(hs, hs) / (sv @ hs) + np.outer(yv, yv) / (sv @ yv)
        x, r, jac, g, cost = x_new, r_new, jac_new, g_new, cost_new
        history.append(cost)
    else:
        raise RuntimeError(f"{name}: the waveform fit did not converge in 200 quasi-Newton steps")
    return x, jac, cost


def _first_breakaway(
    theta: FloatArray, names: tuple[str, ...], v0: float, load: float, t_peak: float
) -> float:
    """Breakaway time (s) that puts the model's force maximum on a measured peak at ``t_peak``."""
    ph = _physical(theta, names, v0, load)
    return t_peak - _time_of_max(ph, _cycle(ph["c"], ph["p"], ph["nu"])) * ph["time"]


def _time_of_max(ph: dict[str, float], row: AttractorRows) -> float:
    """Dimensionless time from breakaway to the spring-force maximum (w = nu, on the dense output)."""
    t_slip = float(row.period[0] - row.stick_time[0])
    tau = np.linspace(0.0, t_slip, 2001)
    _, _, ev, _ = run_trajectory(
        WEAKENING.kernel(), [ph["c"], ph["p"]], ph["nu"], 1.0, 0.0, tau[-1:], rtol=1e-10, atol=1e-12
    )
    hit = ev[ev[:, 1] == EventKind.FORCE_MAXIMUM.code]
    return float(hit[0, 0]) if hit.size else 0.0
