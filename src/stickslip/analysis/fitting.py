"""Fitting the spring-block model to a measured stick-slip record.

The fit is on **cycle features**, not on the force time series: the peak force,
the trough force, the period, the slope of the stick ramp and the drop (fall)
time, each the median over the record's cycles with its standard error. Why:
a stick-slip record is mostly ramp, so a pointwise least-squares fit of the
time series is dominated by the stick phases and by the alignment of the drops
(a small period error shifts every later drop, and the residual surface is
full of local minima); the features carry the same information about the
parameters, directly: the peak is the static friction ``mu0 W``, the ramp's
slope is ``k v0`` exactly, the drop time sets ``sqrt(m/k)``, and the trough
and the period set the weakening ``a``.

Parameters: ``mu0``, ``a``, ``k``, ``m`` (and ``b`` on request), in log space
(all positive), by :func:`scipy.optimize.least_squares`; uncertainties and
correlations from the Jacobian at the optimum (residuals weighted by the
features' standard errors, the covariance scaled by the reduced chi-square when
it exceeds 1). A parameter whose relative uncertainty exceeds 50%, or two whose
correlation exceeds 0.99 in magnitude, are reported as not identifiable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy.optimize import least_squares

from ..core import engine
from ..core.api import run_attractors, run_trajectory
from ..io.records import Record
from ..models.friction import PhysicalWeakeningLaw
from ..models.parameters import PhysicalParameters
from ..models.units import Q_
from .records import RecordSummary, measure_record

__all__ = ["FitResult", "fit_record"]

FloatArray = npt.NDArray[np.float64]
FEATURES = ("peak_force", "trough_force", "period", "rise_slope", "drop_time")
UNITS = {"mu0": "", "a": "s/m", "b": "s/m", "k": "N/m", "m": "kg"}


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

    """

    values: dict[str, float]
    errors: dict[str, float]
    correlation: FloatArray
    names: tuple[str, ...]
    features: dict[str, tuple[float, float, float]]
    warnings: tuple[str, ...]
    parameters: PhysicalParameters
    summary: RecordSummary
    chi2_reduced: float = field(default=math.nan)

    def as_dict(self) -> dict[str, Any]:
        """Return a JSON-ready dictionary with units."""
        return {
            "parameters": {
                n: {"value": self.values[n], "error": self.errors[n], "unit": UNITS[n] or "1"}
                for n in self.names
            },
            "correlation": {
                a: {b: float(self.correlation[i, j]) for j, b in enumerate(self.names)}
                for i, a in enumerate(self.names)
            },
            "features": {
                k: {"measured": v[0], "error": v[1], "model": v[2]} for k, v in self.features.items()
            },
            "warnings": list(self.warnings),
            "chi2_reduced": self.chi2_reduced,
            "fit_on": "cycle features: " + ", ".join(FEATURES),
        }


def _fall_time_model(c: float, p: float, nu: float, t_slip: float, time_scale: float) -> float:
    """90%-10% fall time (s) of the model's force drop, from a dense trajectory of the slip."""
    tau = np.linspace(0.0, t_slip, 600)
    y, _, _, status = run_trajectory(0, [c, p, 0.0], nu, 1.0, 0.0, tau, rtol=1e-9, atol=1e-12)
    if status != 0:
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


def _model_features(
    theta: FloatArray, names: tuple[str, ...], fixed: dict[str, float], v0: float, load: float
) -> FloatArray:
    vals = dict(fixed)
    vals.update({n: math.exp(x) for n, x in zip(names, theta, strict=True)})
    mu0, a, b, k, m = vals["mu0"], vals["a"], vals.get("b", 0.0), vals["k"], vals["m"]
    force = mu0 * load
    beta = math.sqrt(k * m) / force
    nu = beta * v0
    c, p = a / beta, b / beta
    out = run_attractors(
        0, [c, p, 0.0], [nu], from_breakaway=True, rtol=1e-9, atol=1e-12, max_slip_time=1e4, conv_tol=1e-8
    )[0]
    if out[engine.O_REGIME] != engine.RG_STICK_SLIP or out[engine.O_STATUS] != engine.ST_OK:
        return np.full(len(FEATURES), np.nan)
    ts = math.sqrt(m / k)
    t_slip = out[engine.O_PERIOD] - out[engine.O_STICK_TIME]
    return np.array(
        [
            force * out[engine.O_SMAX],
            force * out[engine.O_SMIN],
            out[engine.O_PERIOD] * ts,
            k * v0,
            _fall_time_model(c, p, nu, t_slip, ts),
        ]
    )


def fit_record(record: Record, *, fit_b: bool = False, guess: dict[str, float] | None = None) -> FitResult:
    """Fit ``mu0``, ``a``, ``k``, ``m`` (and ``b``) of the paper's model to a stick-slip record.

    Parameters
    ----------
    record : Record
        A measured record with its driving velocity ``v0`` and normal load.
    fit_b : bool, optional
        Also fit the strengthening rate ``b`` of F2 (default: F1, ``b = 0``).
    guess : dict, optional
        Starting values (SI), by parameter name; default from the features.

    Raises
    ------
    ValueError
        Without ``v0`` or load, or when the record is not stick-slip-like.
    RuntimeError
        When the fit does not converge.

    """
    if record.v0 is None or record.load is None:
        raise ValueError(
            f"{record.name}: fitting needs the driving velocity and the normal load "
            "(give '# v0 = ...' and '# load = ...' header lines or --v0/--load)"
        )
    table, summary = measure_record(record)
    v0 = float(record.v0.to("m/s").magnitude)
    load = float(record.load.to("N").magnitude)
    n = summary.n_cycles
    data, err = [], []
    for key, arr in (
        ("peak_force", table.peak_force),
        ("trough_force", table.trough_force),
        ("period", table.period),
        ("rise_slope", table.rise_slope),
        ("drop_time", table.drop_time),
    ):
        med = float(np.median(arr))
        se = 1.2533 * float(np.std(arr, ddof=1)) / math.sqrt(n) if n > 1 else math.nan
        dt = float(np.median(np.diff(record.time)))
        floor = {"period": dt / math.sqrt(n), "drop_time": dt / math.sqrt(n)}.get(key, 0.0)
        data.append(med)
        err.append(max(se, floor, 1e-6 * abs(med)))
    data_a, err_a = np.array(data), np.array(err)
    names = ("mu0", "a", "k", "m", "b") if fit_b else ("mu0", "a", "k", "m")
    k0 = summary.rise_slope / v0
    mu0_0 = summary.peak_force / load
    m0 = k0 * (summary.drop_time / (0.6 * math.pi)) ** 2
    start = {"mu0": mu0_0, "a": 100.0, "k": k0, "m": max(m0, 1e-9), "b": 10.0}
    start.update(guess or {})
    if not all(math.isfinite(start[x]) and start[x] > 0 for x in names):
        raise ValueError(f"{record.name}: cannot start the fit from the features {start}")

    def residuals(theta: FloatArray) -> FloatArray:
        model = _model_features(theta, names, {"b": 0.0}, v0, load)
        r = (model - data_a) / err_a
        return np.where(np.isfinite(r), r, 1e6)

    best = None
    for a_start in (30.0, 100.0, 300.0, 1000.0):
        s0 = dict(start)
        if guess is None or "a" not in guess:
            s0["a"] = a_start
        theta0 = np.log([s0[x] for x in names])
        res = least_squares(residuals, theta0, method="trf", x_scale=1.0, diff_step=1e-6, max_nfev=400)
        if best is None or res.cost < best.cost:
            best = res
    assert best is not None
    if not best.success:
        raise RuntimeError(f"{record.name}: the fit did not converge ({best.message})")
    dof = max(1, len(FEATURES) - len(names))
    chi2 = 2.0 * best.cost / dof
    jac = best.jac
    cov_log = np.linalg.pinv(jac.T @ jac) * max(1.0, chi2)
    values = {x: float(math.exp(v)) for x, v in zip(names, best.x, strict=True)}
    rel = np.sqrt(np.clip(np.diag(cov_log), 0, None))
    errors = {x: values[x] * float(r) for x, r in zip(names, rel, strict=True)}
    d = np.sqrt(np.clip(np.diag(cov_log), 1e-300, None))
    corr = cov_log / np.outer(d, d)
    warnings = []
    for x, r in zip(names, rel, strict=True):
        if r > 0.5:
            warnings.append(
                f"{x} is not identifiable from these features (relative uncertainty "
                f"{r:.0%}); the record does not constrain it"
            )
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            if abs(corr[i, j]) > 0.99:
                warnings.append(
                    f"{names[i]} and {names[j]} are correlated ({corr[i, j]:+.3f}): "
                    "only a combination of them is determined"
                )
    model = _model_features(best.x, names, {"b": 0.0}, v0, load)
    feats = {k: (float(data_a[i]), float(err_a[i]), float(model[i])) for i, k in enumerate(FEATURES)}
    params = PhysicalParameters(
        mass=Q_(values["m"], "kg"),
        stiffness=Q_(values["k"], "N/m"),
        load=record.load,
        v0=record.v0,
        law=PhysicalWeakeningLaw(
            mu0=values["mu0"], a=Q_(values["a"], "s/m"), b=Q_(values.get("b", 0.0), "s/m")
        ),
    )
    return FitResult(values, errors, corr, names, feats, tuple(warnings), params, summary, chi2)
