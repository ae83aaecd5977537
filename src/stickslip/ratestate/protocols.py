"""Rate-and-state spring-slider: loading histories, laboratory protocols, stability.

:func:`simulate_rate_state` follows the slider through any piecewise-constant
history of the load-point velocity; :func:`velocity_steps` and
:func:`slide_hold_slide` build the two standard laboratory protocols on it.
The quasi-static model is the paper's appendix; with a mass the slider is
inertial (see :mod:`stickslip.core.ratestate`). Integration is by SciPy's
Radau (the system is stiff: the velocity depends exponentially on friction)
with the compiled right-hand side and its analytic Jacobian. A case the solver
cannot handle fails with a message after a bounded number of steps or seconds,
never hangs.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import xarray as xr
from scipy.integrate import solve_ivp

from ..core import ratestate as core
from ..units import Q_, parse_quantity
from .model import RateStateParameters

__all__ = [
    "Stability",
    "linear_stability",
    "simulate_rate_state",
    "slide_hold_slide",
    "velocity_steps",
]

FloatArray = npt.NDArray[np.float64]


class _Abort(Exception):
    pass


def _history(history: Any) -> list[tuple[float, float]]:
    """Parse ``[(duration, velocity), ...]`` into SI pairs."""
    if isinstance(history, str) or not hasattr(history, "__iter__"):
        raise ValueError(f"history={history!r}: expected a sequence of (duration, velocity) pairs")
    out = []
    for i, item in enumerate(history):
        try:
            dur, vel = item
        except (TypeError, ValueError):
            raise ValueError(f"history[{i}]={item!r}: expected a (duration, velocity) pair") from None
        d = parse_quantity(dur, f"history[{i}] duration", "[time]", "10 s")
        v = parse_quantity(vel, f"history[{i}] velocity", "[length] / [time]", "1 um/s", allow_zero=True)
        out.append((float(d.to("s").magnitude), float(v.to("m/s").magnitude)))
    if not out:
        raise ValueError("history is empty: give at least one (duration, velocity) pair")
    return out


def _steady_state(params: RateStateParameters, v: float) -> FloatArray:
    """Steady sliding at load-point velocity ``v`` (m/s) in the core's variables."""
    vr = params.v_ref.to("m/s").magnitude
    theta = math.log(vr / v)
    mu = params.mu0 + (params.a - params.b) * math.log(v / vr)
    if not params.inertial:
        return np.array([mu, theta])
    p = params.core_params()
    return np.array([core.inertial_friction(v, theta, p), v, theta])


def simulate_rate_state(
    params: RateStateParameters,
    history: Sequence[tuple[Any, Any]],
    *,
    initial: str | tuple[float, Any] = "steady",
    n_points: int = 400,
    rtol: float = 1e-10,
    max_steps: int = 200_000,
    max_seconds: float = 60.0,
) -> xr.Dataset:
    """Follow the slider through a history of load-point velocities.

    Parameters
    ----------
    params : RateStateParameters
        The slider (quasi-static, or inertial when it has a mass).
    history : sequence of (duration, velocity)
        Load-point velocity held for each duration, e.g.
        ``[("100 s", "1 um/s"), ("10 s", "10 um/s")]``; a velocity of 0 is a hold.
    initial : "steady" or (friction, state)
        Start in steady sliding at the first velocity (default), or from a
        friction value and a state ``Phi`` (a time, e.g. ``(0.6, "10 s")``).
    n_points : int, optional
        Samples per segment of the history.
    rtol : float, optional
        Relative tolerance of the integration.
    max_steps, max_seconds : optional
        Bounds on the work: beyond them the integration stops with an error.

    Returns
    -------
    xarray.Dataset
        Over ``time`` (s): ``friction``, ``slip_velocity`` (m/s), ``state`` (Phi, s),
        ``slider_displacement`` and ``load_point_displacement`` (m, from the start),
        ``load_point_velocity`` (m/s); for the inertial model also ``spring_friction``.

    Raises
    ------
    ValueError
        Malformed history or initial state.
    RuntimeError
        The solver failed or exceeded its bounds (the message says which).

    """
    if not isinstance(params, RateStateParameters):
        raise ValueError(f"params={params!r}: expected RateStateParameters")
    hist = _history(history)
    if isinstance(n_points, bool) or not isinstance(n_points, int) or n_points < 2:
        raise ValueError(f"n_points={n_points!r}: expected an integer >= 2")
    if not (isinstance(rtol, float | int) and 1e-13 <= rtol <= 1e-3):
        raise ValueError(f"rtol={rtol!r}: expected a relative tolerance between 1e-13 and 1e-3")
    p = params.core_params()
    law = params.law_id
    vr = float(p[3])
    if isinstance(initial, str):
        if initial != "steady":
            raise ValueError(f"initial={initial!r}: expected 'steady' or (friction, state)")
        if hist[0][1] <= 0:
            raise ValueError(
                "initial='steady' needs a positive first velocity (there is no steady "
                "sliding at zero velocity); give initial=(friction, state)"
            )
        y = _steady_state(params, hist[0][1])
    else:
        try:
            mu_i, phi_i = initial
        except (TypeError, ValueError):
            raise ValueError(f"initial={initial!r}: expected 'steady' or (friction, state)") from None
        phi = parse_quantity(phi_i, "initial state", "[time]", "10 s")
        theta = math.log(float(phi.to("s").magnitude) * vr / float(p[2]))
        mu_v = float(mu_i)
        if not math.isfinite(mu_v):
            raise ValueError(f"initial friction {mu_i!r}: expected a finite number")
        if params.inertial:
            v_i = core.qs_velocity(mu_v, theta, p)
            y = np.array([mu_v, v_i, theta])
        else:
            y = np.array([mu_v, theta])

    n = y.size
    rhs = core.in_rhs if params.inertial else core.qs_rhs
    jac = core.in_jac if params.inertial else core.qs_jac
    # absolute tolerances: friction, (velocity,) log-state
    v_scale = max([v for _, v in hist if v > 0], default=vr)
    atol = np.array([1e-12, 1e-12 * v_scale, 1e-10]) if n == 3 else np.array([1e-12, 1e-10])
    started = time.monotonic()
    count = [0]

    def fun(_t: float, yy: FloatArray, v_lp: float) -> FloatArray:
        count[0] += 1
        if count[0] > 20 * max_steps or time.monotonic() - started > max_seconds:
            raise _Abort
        out = np.empty(n)
        rhs(yy, p, law, v_lp, out)
        return out

    def jacobian(_t: float, yy: FloatArray, v_lp: float) -> FloatArray:
        out = np.empty((n, n))
        jac(yy, p, law, out)
        return out

    # a quasi-static slider that runs away: stop when v exceeds 1e6 times the largest speed in play
    v_cap = 1e6 * max(v_scale, vr)
    ln_cap = math.log(v_cap / vr)

    def runaway(_t: float, yy: FloatArray, _v_lp: float) -> float:
        return (yy[0] - params.mu0 - params.b * yy[1]) / params.a - ln_cap

    runaway.terminal = True  # type: ignore[attr-defined]
    runaway.direction = 1  # type: ignore[attr-defined]

    # extrema located by the solver's root finding on its dense output, not read off samples:
    # the spring force peaks where v crosses v_lp upward (its rate kw (v_lp - v) turns negative);
    # with inertia the slider's velocity peaks where the spring force falls below friction
    def spring_peak(_t: float, yy: FloatArray, v_lp: float) -> float:
        if params.inertial:
            return float(yy[1]) - v_lp
        if v_lp <= 0.0:
            return -1.0  # a hold: the slider only creeps, the spring only unloads
        return (yy[0] - params.mu0 - params.b * yy[1]) / params.a - math.log(v_lp / vr)

    spring_peak.direction = 1  # type: ignore[attr-defined]

    def velocity_peak(_t: float, yy: FloatArray, _v_lp: float) -> float:
        return float(yy[0]) - core.inertial_friction(yy[1], yy[2], p)

    velocity_peak.direction = -1  # type: ignore[attr-defined]

    times: list[FloatArray] = []
    states: list[FloatArray] = []
    vlp: list[FloatArray] = []
    peaks: dict[str, list[tuple[float, FloatArray]]] = {"spring": [], "velocity": []}
    t0 = 0.0
    for k, (dur, v_lp) in enumerate(hist):
        t_eval = np.linspace(t0, t0 + dur, n_points)
        events = [spring_peak, velocity_peak] if params.inertial else [spring_peak, runaway]
        try:
            sol = solve_ivp(
                fun,
                (t0, t0 + dur),
                y,
                method="Radau",
                jac=jacobian,
                args=(v_lp,),
                t_eval=t_eval,
                rtol=rtol,
                atol=atol,
                events=events,
            )
        except _Abort:
            raise RuntimeError(
                f"segment {k} (v_lp = {v_lp:g} m/s for {dur:g} s): stopped after "
                f"{count[0]} evaluations / {time.monotonic() - started:.1f} s without finishing; "
                "the case is too stiff at this tolerance (try a larger rtol or a smaller step)"
            ) from None
        except (OverflowError, FloatingPointError) as exc:
            raise RuntimeError(
                f"segment {k}: the solution overflowed ({exc}); the slider "
                "accelerates without bound (unstable, quasi-static)"
            ) from None
        for name, i_ev in (("spring", 0), ("velocity", 1)) if params.inertial else (("spring", 0),):
            peaks[name] += [
                (float(te), ye) for te, ye in zip(sol.t_events[i_ev], sol.y_events[i_ev], strict=True)
            ]
        if sol.status == 1:
            raise RuntimeError(
                f"segment {k} (v_lp = {v_lp:g} m/s): at t = {sol.t_events[1][0]:.6g} s the slip "
                f"velocity passed {v_cap:.3g} m/s and was still rising: the quasi-static slider "
                "accelerates without bound (an instability: below the critical stiffness, or with "
                "the slip law after a large perturbation). Give the slider a mass to follow the "
                "slip event with inertia."
            )
        if sol.status != 0 or not np.all(np.isfinite(sol.y)):
            raise RuntimeError(
                f"segment {k} (v_lp = {v_lp:g} m/s): the solver stopped at "
                f"t = {sol.t[-1]:.6g} s: {sol.message}"
            )
        keep = slice(1, None) if k > 0 else slice(None)
        times.append(sol.t[keep])
        states.append(sol.y[:, keep])
        vlp.append(np.full(sol.t[keep].size, v_lp))
        y = sol.y[:, -1].copy()
        t0 += dur
    ds = _dataset(params, np.concatenate(times), np.concatenate(states, axis=1), np.concatenate(vlp), hist)
    return _with_peaks(ds, params, peaks)


def _with_peaks(
    ds: xr.Dataset, params: RateStateParameters, peaks: dict[str, list[tuple[float, FloatArray]]]
) -> xr.Dataset:
    """Add the located extrema: spring-force peaks and, with inertia, slip-velocity peaks."""
    p = params.core_params()
    sp = peaks["spring"]
    ds["spring_peak_time"] = (
        "spring_peak",
        np.array([t for t, _ in sp]),
        {"units": "s", "long_name": "time of a spring-force maximum (event on the dense output)"},
    )
    ds["spring_peak_friction"] = (
        "spring_peak",
        np.array([float(y[0]) for _, y in sp]),
        {"units": "1", "long_name": "spring force / W at its maximum (the friction, quasi-statically)"},
    )
    vr = float(p[3])
    v_at = [
        float(y[1]) if params.inertial else vr * math.exp((y[0] - params.mu0 - params.b * y[1]) / params.a)
        for _, y in sp
    ]
    ds["spring_peak_velocity"] = (
        "spring_peak",
        np.array(v_at),
        {"units": "m/s", "long_name": "slip velocity at the spring-force maximum (= load-point velocity)"},
    )
    if params.inertial:
        vp = peaks["velocity"]
        ds["velocity_peak_time"] = (
            "velocity_peak",
            np.array([t for t, _ in vp]),
            {"units": "s", "long_name": "time of a slip-velocity maximum (event on the dense output)"},
        )
        ds["velocity_peak"] = (
            "velocity_peak",
            np.array([float(y[1]) for _, y in vp]),
            {"units": "m/s", "long_name": "slip velocity at its maximum"},
        )
        ds["velocity_peak_friction"] = (
            "velocity_peak",
            np.array([core.inertial_friction(float(y[1]), float(y[2]), p) for _, y in vp]),
            {"units": "1", "long_name": "friction at the slip-velocity maximum"},
        )
    return ds


def _dataset(
    params: RateStateParameters,
    t: FloatArray,
    y: FloatArray,
    vlp: FloatArray,
    hist: list[tuple[float, float]],
) -> xr.Dataset:
    p = params.core_params()
    dc, vr, kw = float(p[2]), float(p[3]), float(p[5])
    # load-point displacement: integral of the piecewise-constant velocity
    bounds = np.concatenate([[0.0], np.cumsum([d for d, _ in hist])])
    disp = np.concatenate([[0.0], np.cumsum([d * v for d, v in hist])])
    seg = np.clip(np.searchsorted(bounds, t, side="right") - 1, 0, len(hist) - 1)
    x_lp = disp[seg] + (t - bounds[seg]) * np.array([v for _, v in hist])[seg]
    if params.inertial:
        mus, v, theta = y
        mu = np.array([core.inertial_friction(vi, ti, p) for vi, ti in zip(v, theta, strict=True)])
        spring = mus
    else:
        mu, theta = y
        v = vr * np.exp((mu - params.mu0 - params.b * theta) / params.a)
        spring = mu
    x = x_lp - spring / kw
    data = {
        "friction": ("time", mu, {"units": "1", "long_name": "friction coefficient"}),
        "slip_velocity": ("time", v, {"units": "m/s", "long_name": "slider velocity"}),
        "state": ("time", np.exp(theta) * dc / vr, {"units": "s", "long_name": "state Phi"}),
        "slider_displacement": ("time", x - x[0], {"units": "m", "long_name": "slider displacement"}),
        "load_point_displacement": ("time", x_lp, {"units": "m", "long_name": "load-point displacement"}),
        "load_point_velocity": ("time", vlp, {"units": "m/s", "long_name": "load-point velocity"}),
    }
    if params.inertial:
        data["spring_friction"] = ("time", spring, {"units": "1", "long_name": "spring force / W"})
    return xr.Dataset(
        data,
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
        attrs={
            "model": "inertial" if params.inertial else "quasi-static",
            "state_law": params.state_law,
            "parameters": repr(params),
        },
    )


def velocity_steps(
    params: RateStateParameters,
    velocities: Sequence[Any],
    *,
    displacement: Any = None,
    n_points: int = 400,
    rtol: float = 1e-10,
) -> xr.Dataset:
    """Run a velocity-step test: each load-point velocity held for a load-point displacement.

    Parameters
    ----------
    params : RateStateParameters
        The slider.
    velocities : sequence of velocities
        E.g. ``["1 um/s", "10 um/s", "1 um/s"]``; starts in steady sliding at the first.
    displacement : length, optional
        Load-point displacement per step; default ``20 D0``.
    n_points, rtol : optional
        As in :func:`simulate_rate_state`.

    """
    if isinstance(velocities, str) or len(velocities) < 1:
        raise ValueError(f"velocities={velocities!r}: expected a sequence of velocities")
    d = (
        params.dc * 20
        if displacement is None
        else parse_quantity(displacement, "displacement", "[length]", "100 um")
    )
    hist = []
    for i, v in enumerate(velocities):
        vq = parse_quantity(v, f"velocities[{i}]", "[length] / [time]", "1 um/s")
        hist.append(((d / vq).to("s"), vq))
    return simulate_rate_state(params, hist, n_points=n_points, rtol=rtol)


def slide_hold_slide(
    params: RateStateParameters,
    v_slide: Any,
    holds: Sequence[Any],
    *,
    displacement: Any = None,
    n_points: int = 400,
    rtol: float = 1e-10,
) -> xr.Dataset:
    """Run a slide-hold-slide test: slide, then for each hold time hold and slide again.

    Returns the time series and, over a ``hold`` dimension, ``hold_time`` (s) and
    ``peak_friction_change`` (the peak friction on reloading minus the steady
    friction before the hold: the healing).
    """
    v = parse_quantity(v_slide, "v_slide", "[length] / [time]", "1 um/s")
    d = (
        params.dc * 20
        if displacement is None
        else parse_quantity(displacement, "displacement", "[length]", "100 um")
    )
    slide = ((d / v).to("s"), v)
    hist: list[tuple[Any, Any]] = [slide]
    hold_s = []
    for i, h in enumerate(holds):
        hq = parse_quantity(h, f"holds[{i}]", "[time]", "10 s")
        hold_s.append(float(hq.to("s").magnitude))
        hist += [(hq, Q_(0.0, "m/s")), slide]
    if not hold_s:
        raise ValueError("holds is empty: give at least one hold time")
    ds = simulate_rate_state(params, hist, n_points=n_points, rtol=rtol)
    t = ds.time.values
    bounds = np.concatenate([[0.0], np.cumsum([_history([h])[0][0] for h in hist])])
    mu = ds.friction.values
    t_peak = ds.spring_peak_time.values
    mu_peak = ds.spring_peak_friction.values
    peaks = []
    for j in range(len(hold_s)):
        # steady friction just before the hold: the segment's last sample, at its very end
        before = mu[np.searchsorted(t, bounds[2 * j + 1], side="right") - 1]
        lo, hi = bounds[2 * j + 2], bounds[2 * j + 3]
        sel = (t_peak > lo) & (t_peak <= hi)
        if not sel.any():
            raise RuntimeError(f"hold {j}: no friction peak on reloading within the slide")
        peaks.append(float(mu_peak[np.flatnonzero(sel)[0]] - before))
    ds["hold_time"] = ("hold", np.array(hold_s), {"units": "s", "long_name": "hold time"})
    ds["peak_friction_change"] = (
        "hold",
        np.array(peaks),
        {"units": "1", "long_name": "peak friction after the hold minus steady friction before it"},
    )
    return ds


@dataclass(frozen=True)
class Stability:
    """Linear stability of steady sliding (quasi-static model).

    Attributes
    ----------
    eigenvalues : tuple of complex
        Eigenvalues of the linearised system (1/s).
    growth_rate : float
        Largest real part (1/s): positive means unstable.
    angular_frequency : float
        Imaginary part of the leading pair (rad/s), 0 if real.
    kw_critical : float
        Critical ``k/W = (B - A)/D0`` (1/m).

    """

    eigenvalues: tuple[complex, ...]
    growth_rate: float
    angular_frequency: float
    kw_critical: float


def linear_stability(params: RateStateParameters, v0: Any) -> Stability:
    """Linearise the quasi-static model about steady sliding at ``v0``.

    Raises
    ------
    ValueError
        For a non-positive ``v0`` or an inertial parameter set.

    """
    if params.inertial:
        raise ValueError("linear_stability is for the quasi-static model (params without mass)")
    v = parse_quantity(v0, "v0", "[length] / [time]", "1 um/s")
    y = _steady_state(params, float(v.to("m/s").magnitude))
    jac = np.empty((2, 2))
    core.qs_jac(y, params.core_params(), params.law_id, jac)
    ev = np.linalg.eigvals(jac)
    lead = ev[np.argmax(ev.real)]
    return Stability(
        tuple(complex(e) for e in ev),
        float(lead.real),
        float(abs(lead.imag)),
        float(params.critical_kw.to("1/m").magnitude),
    )
