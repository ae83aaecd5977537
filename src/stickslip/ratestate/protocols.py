"""Rate-and-state spring-slider: loading histories, laboratory protocols, stability.

:func:`simulate_rate_state` follows the slider through any piecewise-constant
history of the load-point velocity; :func:`velocity_steps` and
:func:`slide_hold_slide` build the two standard laboratory protocols on it.
The quasi-static model is the paper's appendix; with a mass the slider is
inertial (see :mod:`stickslip.core.ratestate`). The quasi-static slider is
integrated by the compiled DOP853 of :func:`stickslip.core.ratestate.integrate_qs`;
the inertial one, stiff (the velocity depends exponentially on friction), by the
compiled Radau IIA of :func:`stickslip.core.radau.integrate_in` with the analytic
Jacobian (SciPy's algorithm, step for step). A case the solver
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
import pint
import xarray as xr

from ..core import radau
from ..core import ratestate as core
from ..units import Q_, parse_quantity
from ..userwarnings import warn
from .model import MAX_DURATION, RateStateParameters, jacobian, steady_state

__all__ = [
    "RateStateStopped",
    "Stability",
    "linear_stability",
    "simulate_rate_state",
    "slide_hold_slide",
    "velocity_steps",
]

FloatArray = npt.NDArray[np.float64]


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
        seconds = float(d.to("s").magnitude)
        if not seconds <= MAX_DURATION:  # '1e308 s' ran out of steps, 'too stiff'
            raise ValueError(
                f"history[{i}] duration={seconds:.4g} s: expected at most 1e9 yr "
                f"({MAX_DURATION:.3g} s) a stage"
            )
        out.append((seconds, float(v.to("m/s").magnitude)))
    if not out:
        raise ValueError("history is empty: give at least one (duration, velocity) pair")
    return out


def _steady_state(params: RateStateParameters, v: float) -> FloatArray:
    """Steady sliding at load-point velocity ``v`` (m/s) in the core's variables."""
    P, S = params.core_arrays()
    return steady_state(params, v, P, S)


def sample_times(sample: Any, total: float) -> FloatArray:
    """Return the times (s) of ``sample``: a step (``"1 s"``: 0, 1, 2, ... to ``total``) or the times."""
    if isinstance(sample, str) or (isinstance(sample, pint.Quantity) and np.ndim(sample.magnitude) == 0):
        dt = float(parse_quantity(sample, "sample", "[time]", "1 s").to("s").magnitude)
        n = math.floor(total / dt * (1.0 + 1e-12)) + 1
        if n > 50_000_000:
            raise ValueError(
                f"sample={sample!r}: {n} samples over {total:g} s, more than 5e7; give a longer step"
            )
        return np.arange(n, dtype=np.float64) * dt
    if isinstance(sample, pint.Quantity):
        t = np.asarray(sample.to("s").magnitude, dtype=float)
    else:
        t = np.asarray(sample, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0) or t[0] < 0:
        raise ValueError(f"sample={sample!r}: expected a step such as '1 s' or increasing times (s) from 0")
    if t[-1] > total * (1.0 + 1e-12):
        raise ValueError(f"sample: the last time {t[-1]:g} s is after the end of the history ({total:g} s)")
    return t


def simulate_rate_state(
    params: RateStateParameters,
    history: Sequence[tuple[Any, Any]],
    *,
    initial: str | tuple[float, Any] = "steady",
    n_points: int = 400,
    sample: Any = None,
    at_changes: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = 2_000_000,
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
        spring friction value and a state ``Phi`` (a time, e.g. ``(0.6, "10 s")``;
        a sequence of times with several state variables).
    n_points : int, optional
        Samples per segment of the history (without ``sample``).
    sample : time or sequence of times, optional
        Output at exactly these times from the integrator's dense output:
        ``"1 s"`` gives 0, 1, 2, ... s to the end; or the times themselves (s).
    at_changes : bool, optional
        With ``sample``, output also at each change of the load-point velocity and at
        the end of the history: a record whose velocity holds until the next row
        (``ratestate.csv``) then changes it at its true time, not at the next sample.
    rtol, atol : float, optional
        Relative and absolute tolerances (on the spring friction and the log-states;
        with inertia the velocity's is ``atol`` times the fastest load-point velocity);
        ``rtol`` defaults to 3e-13 for the quasi-static slider (velocities to about 1e-9
        relative: the velocity is exponential in friction / A) and 1e-10 with inertia,
        ``atol`` to 1e-15 for the quasi-static slider and with inertia to 1e-12 on the
        friction and 1e-10 on the log-states.
    max_steps, max_seconds : optional
        Bounds on the work: beyond them the integration stops with an error.

    Returns
    -------
    xarray.Dataset
        Over ``time`` (s): ``friction``, ``slip_velocity`` (m/s), ``state`` (Phi of the
        first state variable, s; ``state_2``, ... for the others), ``slider_displacement``
        and ``load_point_displacement`` (m, from the start), ``load_point_velocity``
        (m/s), ``spring_friction`` (spring force / W); the spring-force maxima located on
        the dense output (``spring_peak_*``) and, with inertia, the velocity maxima.

    Raises
    ------
    ValueError
        Malformed history, samples or initial state.
    RuntimeError
        The solver failed or exceeded its bounds (the message says which).

    Notes
    -----
    The quasi-static slider is integrated by the compiled DOP853 of
    :func:`stickslip.core.ratestate.integrate_qs` (error control on the spring
    friction and the log-states, events located on the 7th-order dense output,
    each change of the load-point velocity a step boundary); the inertial slider,
    stiff at low velocity, by Radau IIA of order 5 (SciPy's algorithm, compiled:
    :func:`stickslip.core.radau.integrate_in`) with the analytic Jacobian.

    """
    if not isinstance(params, RateStateParameters):
        raise ValueError(f"params={params!r}: expected RateStateParameters")
    hist = _history(history)
    if isinstance(n_points, bool) or not isinstance(n_points, int) or n_points < 2:
        raise ValueError(f"n_points={n_points!r}: expected an integer >= 2")
    if rtol is None:
        rtol = 1e-10 if params.inertial else 3e-13
    if not (isinstance(rtol, float | int) and 1e-13 <= rtol <= 1e-3):
        raise ValueError(f"rtol={rtol!r}: expected a relative tolerance between 1e-13 and 1e-3")
    if atol is not None and not (isinstance(atol, float | int) and 0 < atol <= 1e-3):
        raise ValueError(f"atol={atol!r}: expected an absolute tolerance in (0, 1e-3]")
    if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer) or max_steps < 1:
        raise ValueError(f"max_steps={max_steps!r}: expected a positive integer")
    if not isinstance(at_changes, bool | np.bool_):
        raise ValueError(f"at_changes={at_changes!r}: expected True or False")
    if isinstance(max_seconds, bool) or not (isinstance(max_seconds, float | int) and max_seconds > 0):
        raise ValueError(f"max_seconds={max_seconds!r}: expected a positive number of seconds")
    P, S = params.core_arrays()
    n = params.n_states
    vr = float(P[core.P_VR])
    if isinstance(initial, str):
        if initial != "steady":
            raise ValueError(f"initial={initial!r}: expected 'steady' or (friction, state)")
        if hist[0][1] <= 0:
            raise ValueError(
                "initial='steady' needs a positive first velocity (there is no steady "
                "sliding at zero velocity); start the history with a slide (on the command line: "
                "a first step or a --history row at a positive velocity), or give initial=(friction, "
                "state) in Python"
            )
        y = _steady_state(params, hist[0][1])
    else:
        try:
            mu_i, phi_i = initial
        except (TypeError, ValueError):
            raise ValueError(f"initial={initial!r}: expected 'steady' or (friction, state)") from None
        phis = list(phi_i) if isinstance(phi_i, list | tuple) else [phi_i] * n
        if len(phis) != n:
            raise ValueError(f"initial state: {len(phis)} value(s) for {n} state variables")
        theta = np.array(
            [
                math.log(
                    float(parse_quantity(ph, "initial state", "[time]", "10 s").to("s").magnitude)
                    * vr
                    / params.state_scale(i)
                )
                for i, ph in enumerate(phis)
            ]
        )
        mu_v = float(mu_i)
        if not math.isfinite(mu_v):
            raise ValueError(f"initial friction {mu_i!r}: expected a finite number")
        if params.inertial:
            v_i = core.qs_velocity(mu_v, np.concatenate([[mu_v], theta]), S, n, _log_form(P))
            y = np.concatenate([[mu_v, v_i], theta])
        else:
            y = np.concatenate([[mu_v], theta])
    total = float(sum(d for d, _ in hist))
    bounds = np.concatenate([[0.0], np.cumsum([d for d, _ in hist])])
    if sample is None:
        t_s = np.unique(
            np.concatenate([np.linspace(bounds[k], bounds[k + 1], n_points) for k in range(len(hist))])
        )
    else:
        t_s = sample_times(sample, total)
        if at_changes:  # a sample within rounding of a change is the change
            j = np.clip(np.searchsorted(bounds, t_s), 1, bounds.size - 1)  # the changes around each
            gap = np.minimum(t_s - bounds[j - 1], bounds[j] - t_s)
            t_s = np.unique(np.concatenate([t_s[np.abs(gap) > 1e-12 * max(total, 1.0)], bounds]))
    if params.inertial:
        t_out, y_out, vlp, peaks = _radau(params, hist, y, t_s, rtol, atol, max_steps, max_seconds)
        u_out = None
    else:
        t_out, y_out, u_out, vlp, peaks = _dop853(
            params, hist, y, t_s, rtol, 1e-15 if atol is None else atol, max_steps, max_seconds
        )
    ds = _dataset(params, t_out, y_out, u_out, vlp, hist)
    return _with_peaks(ds, params, peaks)


def _log_form(P: FloatArray) -> FloatArray:
    out = P.copy()
    out[core.P_FORM] = core.LOG
    out[core.P_ETA] = 0.0
    return out


def _segments(hist: list[tuple[float, float]]) -> tuple[FloatArray, FloatArray]:
    return np.cumsum([d for d, _ in hist]), np.array([v for _, v in hist])


def _history_velocity(hist: list[tuple[float, float]], t: FloatArray) -> FloatArray:
    """Return the load-point velocity of ``hist`` at the times ``t`` (a change's own time: the new one)."""
    seg_end, seg_v = _segments(hist)
    return seg_v[np.clip(np.searchsorted(seg_end, t, side="right"), 0, len(hist) - 1)]


def _record_velocity(ds: xr.Dataset, t: float) -> float:
    """Return the load-point velocity of the record ``ds`` at ``t`` (held from each row to the next)."""
    t_s = ds.time.values
    return float(ds.load_point_velocity.values[max(0, int(np.searchsorted(t_s, t, side="right")) - 1)])


class RateStateStopped(RuntimeError):
    """The integration stopped before the end of the history.

    ``reason`` says why, in a word: ``"runaway"`` (the slider accelerates without
    bound), ``"max-steps"`` (the bound on the work), ``"step-too-small"`` or
    ``"not-finite"``; ``time`` (s) is where it stopped and ``velocity`` (m/s) the slip
    velocity it passed there (a runaway's cap; NaN otherwise); the message says it in full.
    """

    def __init__(self, message: str, reason: str, time: float = math.nan, velocity: float = math.nan) -> None:
        super().__init__(message)
        self.reason = reason
        self.time = time
        self.velocity = velocity


#: the compiled integrator's codes, in words
STOP_REASONS = {
    core.RS_RUNAWAY: "runaway",
    core.RS_MAX_STEPS: "max-steps",
    core.RS_STEP_TOO_SMALL: "step-too-small",
    core.RS_NONFINITE: "not-finite",
    core.RS_EVENTS_FULL: "events-full",
}


def _status_message(status: int, t: float, v_cap: float, steps: int, seconds: float) -> str:
    if status == core.RS_RUNAWAY:
        return (
            f"at t = {t:.6g} s the slip velocity passed {v_cap:.3g} m/s and was still rising: the "
            "quasi-static slider accelerates without bound (an instability: below the critical "
            "stiffness, or with the slip law after a large perturbation). Give the slider a mass "
            "to follow the slip event with inertia, or radiation damping (quasi-dynamic)."
        )
    if status == core.RS_MAX_STEPS:
        return (
            f"stopped after {steps} steps / {seconds:.1f} s at t = {t:.6g} s without finishing; the "
            "case is too stiff at this tolerance (try a larger rtol, or a larger max_steps)"
        )
    if status == core.RS_NONFINITE:
        return f"at t = {t:.6g} s the solution overflowed: the slider accelerates without bound"
    return (
        f"at t = {t:.6g} s the step size fell below the precision of t: the solution changes "
        "faster than the clock resolves (an instability, or a Dc very small for this history)"
    )


def _dop853(
    params: RateStateParameters,
    hist: list[tuple[float, float]],
    y: FloatArray,
    t_s: FloatArray,
    rtol: float,
    atol: float,
    max_steps: int,
    max_seconds: float,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, dict[str, list[tuple[float, FloatArray]]]]:
    P, S = params.core_arrays()
    n = params.n_states
    vr = float(P[core.P_VR])
    seg_end, seg_v = _segments(hist)
    v_scale = max([v for _, v in hist if v > 0], default=vr)
    v_cap = 1e6 * max(v_scale, vr)
    y0 = np.concatenate([y, np.zeros(core.N_QUAD)])
    nvar = y0.size
    out = np.full((t_s.size, nvar + 1), np.nan)
    ev = np.zeros((4096, 3 + nvar))
    rec = np.zeros((0, 2 + nvar))
    events: list[FloatArray] = []
    started = time.monotonic()
    t, js, steps_total = 0.0, 0, 0
    chunk = 50_000
    status = core.RS_OK
    while True:
        status, t, nsamp, nev, _, steps, _ = core.integrate_qs(
            P,
            S,
            n,
            seg_end,
            seg_v,
            y0,
            t,
            t_s[js:],
            rtol,
            atol,
            math.inf,
            min(chunk, max_steps - steps_total),
            v_cap,
            0.0,
            True,
            out[js:],
            ev,
            rec,
            0,
        )
        events.append(ev[:nev].copy())
        js += nsamp
        steps_total += steps
        if status == core.RS_EVENTS_FULL:
            continue
        if (
            status == core.RS_MAX_STEPS
            and steps_total < max_steps
            and time.monotonic() - started < max_seconds
        ):
            continue
        break
    if status == core.RS_STEP_TOO_SMALL:
        # a slider already far faster than its drive when the step collapses is running away
        # (a formula law's runaway read "step size fell below the precision of t" at 6.5 m/s, on its
        # way past 10 m/s: the rate-and-state audit)
        v_end = float(core.qs_velocity(y0[0], y0, S, n, P))
        if not v_end < 1e-3 * v_cap:
            status, v_cap = core.RS_RUNAWAY, v_end  # the message says the speed it reached
    if status != core.RS_OK:
        message = _status_message(status, t, v_cap, steps_total, time.monotonic() - started)
        reason = STOP_REASONS.get(status, "step-too-small")
        raise RateStateStopped(message, reason, float(t), float(v_cap) if reason == "runaway" else math.nan)
    evs = np.concatenate(events) if events else np.zeros((0, 3 + nvar))
    peaks = {
        "spring": [(float(r[1]), r[3 : 3 + 1 + n].copy()) for r in evs if int(r[0]) == core.EV_SPRING_PEAK],
        "velocity": [],
    }
    t_out = t_s[:js]
    return t_out, out[:js, : 1 + n].T, out[:js, nvar], _history_velocity(hist, t_out), peaks


def _radau(
    params: RateStateParameters,
    hist: list[tuple[float, float]],
    y: FloatArray,
    t_s: FloatArray,
    rtol: float,
    atol: float | None,
    max_steps: int,
    max_seconds: float,
) -> tuple[FloatArray, FloatArray, FloatArray, dict[str, list[tuple[float, FloatArray]]]]:
    """Radau IIA (SciPy's algorithm, compiled: :func:`stickslip.core.radau.integrate_in`) per segment."""
    P, S = params.core_arrays()
    n = params.n_states
    nv = y.size
    vr = float(P[core.P_VR])
    v_scale = max([v for _, v in hist if v > 0], default=vr)
    a_mu, a_theta = (1e-12, 1e-10) if atol is None else (atol, atol)
    atols = np.concatenate([[a_mu, a_mu * v_scale], np.full(n, a_theta)])
    started = time.monotonic()
    steps_total = 0
    times: list[FloatArray] = []
    states: list[FloatArray] = []
    # the spring force peaks where v crosses v_lp upward; the slider's velocity where the
    # spring force falls below friction (both located on the solver's dense output)
    peaks: dict[str, list[tuple[float, FloatArray]]] = {"spring": [], "velocity": []}
    names = {radau.EV_SPRING_PEAK: "spring", radau.EV_VELOCITY_PEAK: "velocity"}
    ev = np.zeros((1024, 2 + nv))
    y = np.array(y, dtype=float)
    t0 = 0.0
    for k, (dur, v_lp) in enumerate(hist):
        t1 = t0 + dur
        sel = ((t_s > t0) | (k == 0)) & (t_s >= t0) & (t_s <= t1)
        wanted = t_s[sel]
        extra = wanted.size == 0 or wanted[-1] < t1
        t_eval = np.append(wanted, t1) if extra else wanted
        out = np.full((t_eval.size, nv), np.nan)
        ws = radau.workspace(nv, t0)
        js = 0
        while True:
            # at most 20 000 steps per call, and never past the bound on the whole run
            budget = min(20_000, max_steps - steps_total - int(ws.st[radau.ST_STEPS]))
            status, nsamp, nev = radau.integrate_in(
                P, S, n, float(v_lp), y, t1, rtol, atols, t_eval[js:], out[js:], ev, max(budget, 0), *ws
            )
            js += nsamp
            for r in ev[:nev]:
                peaks[names[int(r[0])]].append((float(r[1]), r[2:].copy()))
            if status == radau.RD_DONE:
                break
            if status == radau.RD_EVENTS_FULL:
                continue
            steps = steps_total + int(ws.st[radau.ST_STEPS])
            if status == radau.RD_MAX_STEPS:
                if steps < max_steps and time.monotonic() - started < max_seconds and np.all(np.isfinite(y)):
                    continue
                raise RateStateStopped(
                    f"segment {k} (v_lp = {v_lp:g} m/s for {dur:g} s): stopped after "
                    f"{steps} steps / {time.monotonic() - started:.1f} s without "
                    "finishing; the case is too stiff at this tolerance (try a larger rtol or a "
                    "smaller step)",
                    "max-steps",
                )
            raise RuntimeError(
                f"segment {k} (v_lp = {v_lp:g} m/s): the solver stopped at "
                f"t = {ws.st[radau.ST_T]:.6g} s: the required step size is less than spacing "
                "between numbers"
            )
        steps_total += int(ws.st[radau.ST_STEPS])
        if not np.all(np.isfinite(out)) or not np.all(np.isfinite(y)):
            raise RuntimeError(f"segment {k} (v_lp = {v_lp:g} m/s): the solution overflowed")
        y = out[-1].copy()  # as solve_ivp: the next segment starts from the dense output at t1
        keep = slice(0, -1) if extra else slice(None)
        times.append(t_eval[keep])
        states.append(out[keep].T)
        t0 = t1
    t_out = np.concatenate(times)
    # a sample at a change of the load-point velocity carries the new velocity, as the
    # quasi-static record's does: the record holds each row's velocity until the next row, and
    # the old one put every change a sample late (a fit of it ran away: the rate-and-state audit)
    return t_out, np.concatenate(states, axis=1), _history_velocity(hist, t_out), peaks


#: a spring-force maximum less than this above steady sliding's spring force is rounding, not a peak
PEAK_FLOOR = 1e-9


def _above_steady(
    ds: xr.Dataset, params: RateStateParameters, spring: list[tuple[float, FloatArray]]
) -> list[tuple[float, FloatArray]]:
    """Drop spring-force 'maxima' within ``PEAK_FLOOR`` of steady sliding at the load-point velocity.

    On steady sliding the slip velocity wiggles about the load point's at rounding level, and
    each upward crossing was reported as a maximum (7 of them 3e-14 above steady sliding after
    a velocity step settled: the rate-and-state audit).
    """
    if not spring:
        return spring
    eta = 0.0 if params.radiation_damping is None else float(params.radiation_damping.to("s/m").magnitude)
    kept = []
    for t, y in spring:
        v_lp = _record_velocity(ds, t)
        if not v_lp > 0:
            kept.append((t, y))
            continue
        steady = float(params.steady_state_friction(Q_(v_lp, "m/s"))) + eta * v_lp
        if float(y[0]) - steady > PEAK_FLOOR:
            kept.append((t, y))
    return kept


def _with_peaks(
    ds: xr.Dataset, params: RateStateParameters, peaks: dict[str, list[tuple[float, FloatArray]]]
) -> xr.Dataset:
    """Add the located extrema: spring-force peaks and, with inertia, slip-velocity peaks."""
    P, S = params.core_arrays()
    n = params.n_states
    sp = _above_steady(ds, params, peaks["spring"])
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
    v_at = [float(y[1]) if params.inertial else core.qs_velocity(y[0], y, S, n, P) for _, y in sp]
    ds["spring_peak_velocity"] = (
        "spring_peak",
        np.array(v_at),
        {"units": "m/s", "long_name": "slip velocity at the spring-force maximum (= load-point velocity)"},
    )
    if params.inertial:
        # a 'maximum' of the slip velocity within 1e-8 of the load point's, on steady sliding, is
        # rounding (four of them at v = 1.0000000000e-4 in a settled start: the rate-and-state audit)
        vp = []
        for t, y in peaks["velocity"]:
            v_lp = _record_velocity(ds, t)
            if not abs(float(y[1]) - v_lp) <= 1e-8 * v_lp:
                vp.append((t, y))
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
            np.array([core.in_friction(float(y[1]), y, S, n, P) for _, y in vp]),
            {"units": "1", "long_name": "friction at the slip-velocity maximum"},
        )
    return ds


def _dataset(
    params: RateStateParameters,
    t: FloatArray,
    y: FloatArray,
    u: FloatArray | None,
    vlp: FloatArray,
    hist: list[tuple[float, float]],
) -> xr.Dataset:
    P, S = params.core_arrays()
    n = params.n_states
    vr, kw, eta = float(P[core.P_VR]), float(P[core.P_KW]), float(P[core.P_ETA])
    # load-point displacement: integral of the piecewise-constant velocity
    bounds = np.concatenate([[0.0], np.cumsum([d for d, _ in hist])])
    disp = np.concatenate([[0.0], np.cumsum([d * v for d, v in hist])])
    seg = np.clip(np.searchsorted(bounds, t, side="right") - 1, 0, len(hist) - 1)
    x_lp = disp[seg] + (t - bounds[seg]) * np.array([v for _, v in hist])[seg]
    if params.inertial:
        spring, v, theta = y[0], y[1], y[2:]
        mu = np.array([core.in_friction(y[1, i], y[:, i], S, n, P) for i in range(t.size)])
    else:
        spring, theta = y[0], y[1:]
        assert u is not None
        v = vr * np.exp(u)
        mu = spring - eta * v
    x = x_lp - spring / kw
    data: dict[str, Any] = {
        "friction": ("time", mu, {"units": "1", "long_name": "friction coefficient"}),
        "slip_velocity": ("time", v, {"units": "m/s", "long_name": "slider velocity"}),
        "slider_displacement": ("time", x - x[0], {"units": "m", "long_name": "slider displacement"}),
        "load_point_displacement": ("time", x_lp, {"units": "m", "long_name": "load-point displacement"}),
        "load_point_velocity": ("time", vlp, {"units": "m/s", "long_name": "load-point velocity"}),
        "spring_friction": ("time", spring, {"units": "1", "long_name": "spring force / W"}),
    }
    for i in range(n):
        name = "state" if i == 0 else f"state_{i + 1}"
        data[name] = (
            "time",
            np.exp(theta[i]) * params.state_scale(i) / vr,
            {
                "units": "s",
                "long_name": f"state Phi{'' if n == 1 else f'_{i + 1}'} ({params.laws[i]} law)",
            },
        )
    return xr.Dataset(
        data,
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
        attrs={
            "model": "inertial" if params.inertial else ("quasi-dynamic" if eta > 0 else "quasi-static"),
            "state_law": ",".join(params.laws),
            "state_variables": n,
            "parameters": repr(params),
        },
    )


def step_history(
    velocities: Sequence[Any],
    *,
    durations: Sequence[Any] | None = None,
    displacements: Sequence[Any] | None = None,
    displacement: Any = None,
    default_displacement: Any = None,
) -> list[tuple[Any, Any]]:
    """Build ``(duration, velocity)`` pairs of a velocity-step test.

    Each velocity is held for its duration (``durations``), for its load-point
    displacement (``displacements``), or for one displacement for all
    (``displacement``, else ``default_displacement``). A velocity of 0 (a hold)
    needs a duration.
    """
    if isinstance(velocities, str) or len(velocities) < 1:
        raise ValueError(f"velocities={velocities!r}: expected a sequence of velocities")
    if durations is not None and displacements is not None:
        raise ValueError("give durations or displacements for the steps, not both")
    if displacement is not None and (durations is not None or displacements is not None):
        raise ValueError(
            f"displacement={displacement!r}: one displacement for every step, or durations/displacements "
            "for each, not both"
        )
    for name, seq in (("durations", durations), ("displacements", displacements)):
        if seq is not None and (isinstance(seq, str) or len(seq) != len(velocities)):
            raise ValueError(f"{name}={seq!r}: expected one per velocity ({len(velocities)} velocities)")
    hist: list[tuple[Any, Any]] = []
    for i, v in enumerate(velocities):
        vq = parse_quantity(
            v, f"velocities[{i}]", "[length] / [time]", "1 um/s", allow_zero=durations is not None
        )
        if durations is not None:
            hist.append((parse_quantity(durations[i], f"durations[{i}]", "[time]", "10 s"), vq))
            continue
        if displacements is not None:
            d = parse_quantity(displacements[i], f"displacements[{i}]", "[length]", "100 um")
        elif displacement is not None:
            d = parse_quantity(displacement, "displacement", "[length]", "100 um")
        else:
            d = default_displacement
        hist.append(((d / vq).to("s"), vq))
    return hist


def velocity_steps(
    params: RateStateParameters,
    velocities: Sequence[Any],
    *,
    displacement: Any = None,
    durations: Sequence[Any] | None = None,
    displacements: Sequence[Any] | None = None,
    n_points: int = 400,
    sample: Any = None,
    at_changes: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
) -> xr.Dataset:
    """Run a velocity-step test: each load-point velocity held for a duration or a displacement.

    Parameters
    ----------
    params : RateStateParameters
        The slider.
    velocities : sequence of velocities
        E.g. ``["1 um/s", "10 um/s", "1 um/s"]``; starts in steady sliding at the first.
    displacement : length, optional
        Load-point displacement of every step; default ``20 D_c`` (the largest ``D_c``).
    durations : sequence of times, optional
        Duration of each step instead, e.g. ``["10 s", "30 s"]``.
    displacements : sequence of lengths, optional
        Load-point displacement of each step instead.
    n_points, sample, at_changes, rtol, atol : optional
        As in :func:`simulate_rate_state`.

    Examples
    --------
    rsfmodel's one-state velocity step (``k = 1e-3 /um``, a step to 10 um/s at 10 s),
    sampled every second:

    >>> p = RateStateParameters(a=0.005, b=0.01, dc="10 um", v_ref="1 um/s", mu0=0.6,
    ...                         stiffness_per_load="1e-3 1/um")
    >>> ds = velocity_steps(p, ["1 um/s", "10 um/s"], durations=["10 s", "30 s"], sample="1 s")
    >>> round(float(ds.friction.sel(time=11.0)), 8)
    0.60720485

    """
    hist = step_history(
        velocities,
        durations=durations,
        displacements=displacements,
        displacement=displacement,
        default_displacement=params.dc_max * 20,
    )
    return simulate_rate_state(
        params, hist, n_points=n_points, sample=sample, at_changes=at_changes, rtol=rtol, atol=atol
    )


#: a slide before a hold counts as unsettled when its end is this far from steady sliding,
#: relative to the healing measured from it
UNSETTLED = 0.01


def slide_hold_slide(
    params: RateStateParameters,
    v_slide: Any,
    holds: Sequence[Any],
    *,
    displacement: Any = None,
    n_points: int = 400,
    sample: Any = None,
    at_changes: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
) -> xr.Dataset:
    """Run a slide-hold-slide test: slide, then for each hold time hold and slide again.

    Returns the time series and, over a ``hold`` dimension, ``hold_time`` (s) and
    ``peak_friction_change`` (the peak of the spring force / W on reloading minus its
    value at the end of the slide before the hold: the healing; quasi-statically, without
    damping, the friction's). That value is steady sliding's once the slide has settled; a
    warning says when it is more than :data:`UNSETTLED` of the healing away (near the
    critical stiffness the slider rings for many ``Dc``: lengthen the slides).
    ``n_points``, ``sample``, ``at_changes``, ``rtol`` and ``atol`` are those of
    :func:`simulate_rate_state`.
    """
    v = parse_quantity(v_slide, "v_slide", "[length] / [time]", "1 um/s")
    d = (
        params.dc_max * 20
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
    ds = simulate_rate_state(
        params, hist, n_points=n_points, sample=sample, at_changes=at_changes, rtol=rtol, atol=atol
    )
    t = ds.time.values
    bounds = np.concatenate([[0.0], np.cumsum([_history([h])[0][0] for h in hist])])
    # the spring force on both sides (what a machine measures): the peak is the spring
    # force's; the rate-and-state friction before the hold differs from it by eta v with
    # radiation damping, which the healing took in whole (+0.01 of 0.015 at 1000 s/m, 10 um/s:
    # the rate-and-state audit), and with a mass where the slide has not settled
    spring = ds.spring_friction.values
    t_peak = ds.spring_peak_time.values
    mu_peak = ds.spring_peak_friction.values
    peaks = []
    eta = 0.0 if params.radiation_damping is None else float(params.radiation_damping.to("s/m").magnitude)
    v_si = float(v.to("m/s").magnitude)
    steady = float(params.steady_state_friction(v)) + eta * v_si  # the spring's, with damping's eta v
    for j in range(len(hold_s)):
        # steady sliding just before the hold: the segment's last sample, at its very end
        before = spring[np.searchsorted(t, bounds[2 * j + 1], side="right") - 1]
        lo, hi = bounds[2 * j + 2], bounds[2 * j + 3]
        sel = (t_peak > lo) & (t_peak <= hi)
        if not sel.any():
            # no healing to measure (b = 0, a hold of nanoseconds): said, and the run kept (it
            # stopped the whole run without output: the rate-and-state audit)
            warn(
                f"hold {j} ({hold_s[j]:g} s): no spring-force peak on reloading within the slide (no "
                "healing to measure: b = 0, or a hold too short to age the contact); its peak "
                "friction change is NaN",
                UserWarning,
            )
            peaks.append(math.nan)
            continue
        peaks.append(float(mu_peak[np.flatnonzero(sel)[0]] - before))
        off = before - steady
        if abs(off) > UNSETTLED * abs(peaks[-1]):  # k near k_c rings for many Dc (the audit)
            warn(
                f"hold {j} ({hold_s[j]:g} s): the slide before it has not settled: the spring force / W "
                f"is {before:.6g} at its end, {off:+.2g} from steady sliding's {steady:.6g}, so the "
                f"healing {peaks[-1]:.4g} is measured from an unsettled level; lengthen the slides "
                f"(displacement=, --displacement; now {float(d.to('m').magnitude):.3g} m)",
                UserWarning,
            )
    ds["hold_time"] = ("hold", np.array(hold_s), {"units": "s", "long_name": "hold time"})
    ds["peak_friction_change"] = (
        "hold",
        np.array(peaks),
        {"units": "1", "long_name": "peak spring force / W after the hold minus its steady value before it"},
    )
    return ds


@dataclass(frozen=True)
class Stability:
    """Linear stability of steady sliding (quasi-static or inertial model).

    Attributes
    ----------
    eigenvalues : tuple of complex
        Eigenvalues of the linearised system (1/s).
    growth_rate : float
        Largest real part (1/s): positive means unstable.
    angular_frequency : float
        Imaginary part of the leading pair (rad/s), 0 if real.
    kw_critical : float
        Critical ``k/W`` (1/m) at this velocity: ``(B - A)/D0`` for one state
        variable without damping or mass; with them, where the growth rate at this
        velocity crosses zero (:meth:`RateStateParameters.critical_kw_at`). 0: stable
        at any stiffness.

    """

    eigenvalues: tuple[complex, ...]
    growth_rate: float
    angular_frequency: float
    kw_critical: float


def linear_stability(params: RateStateParameters, v0: Any) -> Stability:
    """Linearise the model about steady sliding at ``v0`` (with a mass: the inertial model).

    Raises
    ------
    ValueError
        For a non-positive ``v0``.

    """
    v = parse_quantity(v0, "v0", "[length] / [time]", "1 um/s")
    ev = np.linalg.eigvals(jacobian(params, float(v.to("m/s").magnitude)))
    lead = ev[np.argmax(ev.real)]
    return Stability(
        tuple(complex(e) for e in ev),
        float(lead.real),
        float(abs(lead.imag)),
        float(params.critical_kw_at(v).to("1/m").magnitude),
    )
