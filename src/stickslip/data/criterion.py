"""The paper's criterion: the sign of d(log amplitude)/d(log driving velocity).

Szkutnik and Kułakowski (after Thomsen and Fidlin) propose that the amplitude
of friction oscillations grows with the driving velocity in the stick-slip
regime and shrinks with it in the pure-slip regime. :func:`classify` fits the
log-log slope of measured amplitudes against driving velocity, with a
confidence interval, and applies that rule, saying ``inconclusive`` when the
data cannot carry it: too few points, a slope consistent with zero, or a trend
that reverses inside the measured range.

What it cannot tell: the rule is a heuristic from one friction law (a cubic
law, in the weakly nonlinear limit); it is not a theorem for every law, and it
says nothing about data that mix regimes. See ``docs/criterion.md``.
"""

from __future__ import annotations

import math
import numbers
import os
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pint
from scipy import stats

from ..errors import ArgumentTypeError
from ..io.errors import DataError
from ..io.tables import read_table
from ..units import ureg

__all__ = ["CriterionResult", "classify", "classify_file"]


@dataclass(frozen=True)
class CriterionResult:
    """Verdict of the amplitude-velocity criterion.

    Attributes
    ----------
    verdict : str
        ``stick-slip`` (amplitude rises with velocity), ``pure-slip`` (it falls)
        or ``inconclusive``.
    slope : float
        d log(amplitude) / d log(velocity), least squares (weighted when errors are given).
    slope_ci : tuple of float
        Confidence interval of the slope (NaN when it cannot be estimated).
    confidence : float
        Confidence level of the interval.
    n_points : int
        Number of data points used.
    reason : str
        One line saying why.

    """

    verdict: str
    slope: float
    slope_ci: tuple[float, float]
    confidence: float
    n_points: int
    reason: str

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary (NaN becomes ``None``)."""
        d = asdict(self)
        d["slope"] = _finite_or_none(self.slope)
        d["slope_ci"] = [_finite_or_none(x) for x in self.slope_ci]
        return d


def _finite_or_none(x: float) -> float | None:
    return x if math.isfinite(x) else None


def _as_array(name: str, x: Any, unit: Any = None) -> npt.NDArray[np.float64]:
    if isinstance(x, pint.Quantity):  # its magnitudes in ``unit`` (numpy would strip the units)
        try:
            x = x.to(unit).magnitude if unit is not None else x.magnitude
        except pint.DimensionalityError:
            raise ValueError(f"{name}: units {x.units} do not convert to {unit}") from None
    if isinstance(x, str | bytes):
        raise ArgumentTypeError(f"{name}={x!r}: expected a 1-d sequence of numbers")
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}: expected numbers") from None
    if a.ndim == 0:  # one number (or None) for a sequence
        raise ArgumentTypeError(f"{name}={x!r}: expected a 1-d sequence of numbers")
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a 1-d sequence of numbers, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        i = int(np.argmax(~np.isfinite(a)))
        raise ValueError(f"{name}[{i}]={float(a[i])!r}: expected finite numbers")
    return a


def check_confidence(confidence: Any) -> None:
    """Raise unless ``confidence`` is a confidence level in [0.5, 1) (a number, not a bool)."""
    if isinstance(confidence, bool) or not isinstance(confidence, float | int):
        raise ArgumentTypeError(f"confidence={confidence!r}: expected a level in [0.5, 1), e.g. 0.95")
    if not 0.5 <= confidence < 1:
        raise ValueError(f"confidence={confidence!r}: expected a level in [0.5, 1), e.g. 0.95")


def classify(
    velocity: npt.ArrayLike,
    amplitude: npt.ArrayLike,
    amplitude_err: npt.ArrayLike | None = None,
    *,
    confidence: float = 0.95,
    min_points: int = 4,
) -> CriterionResult:
    """Apply the amplitude-velocity criterion to measured (or computed) data.

    Parameters
    ----------
    velocity : array_like
        Driving velocities (> 0), any unit: only the log-log slope matters.
    amplitude : array_like
        Oscillation amplitudes (> 0), any unit.
    amplitude_err : array_like, optional
        One-sigma errors of the amplitudes (same unit; pint quantities where the
        amplitudes are, converted to their unit); weights the fit.
    confidence : float, optional
        Confidence level of the slope interval. Default 0.95.
    min_points : int, optional
        Fewest points for a verdict. Default 4.

    Returns
    -------
    CriterionResult

    Raises
    ------
    ArgumentTypeError
        For an argument of the wrong type: text or one number for a sequence, entries
        that are not numbers, errors without units beside amplitudes with units (or the
        reverse), a ``confidence`` or ``min_points`` that is not a number.
    ValueError
        Different lengths, non-finite values, non-positive velocities or
        amplitudes, negative errors, units of the wrong dimension, or a ``confidence``
        or ``min_points`` out of range.

    """
    if isinstance(velocity, pint.Quantity) and not velocity.check("[length] / [time]"):
        raise ValueError(f"velocity: units {velocity.units}: expected a velocity, e.g. um/s")
    v = _as_array("velocity", velocity)
    a = _as_array("amplitude", amplitude)
    # the errors are converted to the amplitudes' unit: 10 mN beside amplitudes in N is 0.01 N, not 10 N
    a_unit = amplitude.units if isinstance(amplitude, pint.Quantity) else None
    if (a_unit is None) != (not isinstance(amplitude_err, pint.Quantity)) and amplitude_err is not None:
        raise ArgumentTypeError("amplitude and amplitude_err: give both with units, or neither")
    if v.shape != a.shape:
        raise ValueError(f"velocity has {v.size} values and amplitude {a.size}: expected equal lengths")
    if np.any(v <= 0):
        i = int(np.argmax(v <= 0))
        raise ValueError(f"velocity[{i}]={float(v[i])!r}: driving velocities must be positive")
    if np.any(a <= 0):
        i = int(np.argmax(a <= 0))
        raise ValueError(f"amplitude[{i}]={float(a[i])!r}: amplitudes must be positive")
    check_confidence(confidence)
    if isinstance(min_points, bool) or not isinstance(min_points, numbers.Integral):
        raise ArgumentTypeError(f"min_points={min_points!r}: expected an integer >= 3")
    if min_points < 3:
        raise ValueError(f"min_points={min_points!r}: expected an integer >= 3")
    sigma = None
    if amplitude_err is not None:
        e = _as_array("amplitude_err", amplitude_err, a_unit)
        if e.shape != a.shape:
            raise ValueError("amplitude_err: expected one error per amplitude")
        if np.any(e < 0):
            i = int(np.argmax(e < 0))
            raise ValueError(f"amplitude_err[{i}]={float(e[i])!r}: errors must be non-negative")
        # an error of 1e-320 overflows the weights (a / err)**2 ('SVD did not converge'); a
        # noise-free record's 1e-15 of its amplitude is fine
        tiny = (e > 0) & (e < 1e-100 * a)
        if np.any(tiny):
            i = int(np.argmax(tiny))
            raise ValueError(
                f"amplitude_err[{i}]={float(e[i])!r}: below 1e-100 of its amplitude, where the fit's "
                "weights overflow: give 0 for an amplitude known exactly"
            )
        if np.any(e > 0):
            sigma = np.where(e > 0, e / a, np.min(e[e > 0] / a[e > 0]))

    n = v.size
    x = np.log(v)
    y = np.log(a)
    nan_ci = (math.nan, math.nan)
    if n < 2 or np.ptp(x) == 0:
        return CriterionResult(
            "inconclusive",
            math.nan,
            nan_ci,
            confidence,
            n,
            f"too few distinct velocities ({np.unique(v).size}); need at least {min_points} points",
        )
    slope, se, dof = _fit(x, y, sigma, 1)
    lo, hi = _interval(slope, se, dof, confidence)
    trend = "rises" if slope > 0 else "falls"
    pct = f"{100 * confidence:g}%"
    summary = f"slope {slope:.3g}, {pct} CI [{lo:.3g}, {hi:.3g}], {n} points"
    if n < min_points:
        return CriterionResult(
            "inconclusive",
            slope,
            (lo, hi),
            confidence,
            n,
            f"too few points ({n}; need at least {min_points}): {summary}",
        )
    reversal = _reversal(x, y, sigma, confidence)
    if reversal is not None:
        return CriterionResult(
            "inconclusive",
            slope,
            (lo, hi),
            confidence,
            n,
            f"non-monotonic: the amplitude {reversal} ({summary})",
        )
    if lo <= 0.0 <= hi:
        return CriterionResult(
            "inconclusive", slope, (lo, hi), confidence, n, f"slope consistent with zero ({summary})"
        )
    verdict = "stick-slip" if slope > 0 else "pure-slip"
    return CriterionResult(
        verdict,
        slope,
        (lo, hi),
        confidence,
        n,
        f"amplitude {trend} with driving velocity ({summary}): {verdict}",
    )


def _polyfit(
    x: np.ndarray, y: np.ndarray, sigma: np.ndarray | None, degree: int
) -> tuple[np.ndarray, np.ndarray, int]:
    """Weighted polynomial fit in ``x - mean(x)``; return coefficients, covariance, dof.

    Without errors the covariance is scaled by the residual variance; with
    errors by the reduced chi-square when it exceeds 1 (errors too small).
    """
    n = x.size
    X = np.vander(x - x.mean(), degree + 1, increasing=True)
    sw = np.ones(n) if sigma is None else 1.0 / sigma
    # least squares on the design scaled by sqrt(w), by its SVD: the normal matrix X^T W X
    # squares the condition number, and with errors that differ by 1e9 (noise-free records:
    # 1e-15 next to 1e-5) its pseudo-inverse truncates it, and a rising half reads falling
    u, sv, vt = np.linalg.svd(X * sw[:, None], full_matrices=False)
    keep = sv > sv[0] * max(X.shape) * np.finfo(float).eps
    inv = np.where(keep, 1.0 / np.where(keep, sv, 1.0), 0.0)
    coef = vt.T @ (inv * (u.T @ (y * sw)))
    # a direction the data do not fix (every x equal) has no error, not an error of 0
    cov = (vt.T * inv**2) @ vt if keep.all() else np.full((degree + 1, degree + 1), math.nan)
    dof = n - degree - 1
    chi2 = float(np.sum((sw * (y - X @ coef)) ** 2))
    if dof <= 0:
        scale = math.nan if sigma is None else 1.0
    else:
        scale = chi2 / dof if sigma is None else max(1.0, chi2 / dof)
    return coef, cov * scale, dof


def _fit(x: np.ndarray, y: np.ndarray, sigma: np.ndarray | None, degree: int) -> tuple[float, float, int]:
    """Return the highest coefficient of a weighted polynomial fit, its standard error, dof."""
    coef, cov, dof = _polyfit(x, y, sigma, degree)
    return float(coef[degree]), math.sqrt(cov[degree, degree]) if cov[degree, degree] >= 0 else math.nan, dof


def _interval(b: float, se: float, dof: int, confidence: float) -> tuple[float, float]:
    if not math.isfinite(se) or dof <= 0:
        return (math.nan, math.nan)
    t = float(stats.t.ppf(0.5 + confidence / 2, dof))
    return (b - t * se, b + t * se)


def _reversal(x: np.ndarray, y: np.ndarray, sigma: np.ndarray | None, confidence: float) -> str | None:
    """Detect a trend that turns back inside the data.

    The points are split at the median velocity into a lower and an upper half
    (the middle point in both when their number is odd) and each half gets its
    own log-log slope. The trend turns back when the two slopes are of opposite
    sign and each excludes zero at ``confidence``. A monotonic but curved trend
    (steeper at one end) is not a reversal.
    """
    n = x.size
    if n < 6:
        return None
    order = np.argsort(x, kind="stable")
    half = (n + 1) // 2
    parts = [order[:half], order[n - half :]]
    bounds = []
    for idx in parts:
        if np.ptp(x[idx]) == 0:
            return None
        slope, se, dof = _fit(x[idx], y[idx], None if sigma is None else sigma[idx], 1)
        bounds.append(_interval(slope, se, dof, confidence))
    (lo1, hi1), (lo2, hi2) = bounds
    v_mid = math.exp(float(np.median(x)))
    if lo1 > 0 and hi2 < 0:
        return f"rises below and falls above velocity {v_mid:.3g}"
    if hi1 < 0 and lo2 > 0:
        return f"falls below and rises above velocity {v_mid:.3g}"
    return None


def classify_file(
    path: str | os.PathLike[str], *, confidence: float = 0.95, min_points: int = 4
) -> CriterionResult:
    """Apply :func:`classify` to a CSV with columns ``velocity``, ``amplitude`` [, ``amplitude_err``].

    Units in brackets in the header are honoured (``velocity [um/s]``,
    ``amplitude [mN]``): the velocity must be a velocity, and the error must have
    the amplitude's dimension (it is converted to the amplitude's unit).

    Raises
    ------
    ValueError
        For a malformed file (see :func:`stickslip.io.tables.read_table`),
        inconsistent units, or values the criterion cannot take.

    """
    if not isinstance(path, str | os.PathLike):
        raise ArgumentTypeError(f"path={path!r} (type {type(path).__name__}): expected a file's path")
    p = os.fspath(path)
    cols = read_table(p, ["velocity", "amplitude"], ["amplitude_err"])
    vel, amp = cols["velocity"], cols["amplitude"]
    if vel.unit is not None and not (1 * vel.unit).check("[length] / [time]"):
        raise DataError(f"{p}: column 'velocity' has unit [{vel.unit:~}], expected a velocity such as [um/s]")
    if amp.unit is not None and not any((1 * amp.unit).check(d) for d in ("[force]", "[length]", "[]")):
        q = 1 * amp.unit
        kind = "a velocity" if q.check("[length] / [time]") else f"of dimension {q.dimensionality}"
        raise DataError(
            f"{p}: column 'amplitude' has unit [{amp.unit:~}], {kind}: expected a force, a length or [a.u.]"
        )
    err = None
    if "amplitude_err" in cols:
        e = cols["amplitude_err"]
        if e.unit is not None and amp.unit is not None:
            if (1 * e.unit).dimensionality != (1 * amp.unit).dimensionality:
                raise DataError(
                    f"{p}: amplitude_err [{e.unit:~}] and amplitude [{amp.unit:~}] have inconsistent units"
                )
            err = ureg.Quantity(e.values, e.unit).to(amp.unit).magnitude
        elif (e.unit is None) != (amp.unit is None):
            raise DataError(f"{p}: give units for both amplitude and amplitude_err, or for neither")
        else:
            err = e.values
    if np.any(vel.values <= 0):
        i = int(np.argmax(vel.values <= 0))
        raise DataError(
            f"{p}: {vel.place(i)}: velocity {float(vel.values[i])!r} is not positive "
            "(driving velocities must be positive)"
        )
    if np.any(amp.values <= 0):
        i = int(np.argmax(amp.values <= 0))
        raise DataError(f"{p}: {amp.place(i)}: amplitude {float(amp.values[i])!r} is not positive")
    if err is not None and np.any(err < 0):
        i = int(np.argmax(err < 0))
        e = cols["amplitude_err"]
        raise DataError(
            f"{p}: {e.place(i)}: amplitude_err {float(e.values[i])!r} is negative (a one-sigma error)"
        )
    return classify(vel.values, amp.values, err, confidence=confidence, min_points=min_points)
