"""The model side of the fit of the paper's law: the model as a function of the fit's coordinates.

The fit's coordinates are the logarithms of ``mu_s, a, k, m`` (and ``b``, with ``d = a - b``
in place of ``a``; see :func:`_values`). From them: the model's steady stick-slip cycle
from breakaway, its cycle features (:data:`FEATURES`: peak and trough force, period, rise
slope, drop time) and its force waveform at given times, NaN where an optimiser's trial
step leaves the model's range or its stick-slip regime.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ..core.api import run_attractors, run_trajectory
from ..core.results import AttractorRows, EventKind, Regime, Status
from ..laws.weakening import WEAKENING

__all__ = ["FEATURES", "model_waveform"]

FloatArray = npt.NDArray[np.float64]
#: the cycle features the first stage fits, in this order
FEATURES = ("peak_force", "trough_force", "period", "rise_slope", "drop_time")


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
    except ValueError:  # a trial step beyond the engine's range (lp[0] = 2e23) fails the model, not the fit
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


def _first_breakaway(
    theta: FloatArray, names: tuple[str, ...], v0: float, load: float, t_peak: float, fixed_b: float = 0.0
) -> float:
    """Breakaway time (s) that puts the model's force maximum on a measured peak at ``t_peak``."""
    ph = _physical(theta, names, v0, load, fixed_b)
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
