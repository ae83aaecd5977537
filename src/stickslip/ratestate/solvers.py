"""The compiled integrators of the rate-and-state slider, driven through a load-point history.

The quasi-static (and quasi-dynamic) slider is integrated by the compiled DOP853 of
:func:`stickslip.core.ratestate.integrate_qs`; the inertial one, stiff (the velocity
depends exponentially on friction), by the compiled Radau IIA of
:func:`stickslip.core.radau.integrate_in` with the analytic Jacobian (SciPy's algorithm,
step for step). Both run in calls of a bounded number of steps, so that a case the
solver cannot handle stops with :class:`RateStateStopped` (or a RuntimeError) and a
message after a bounded number of steps or seconds, never hangs. What the kernels
return is read through :mod:`stickslip.core.results`.
"""

from __future__ import annotations

import math
import time

import numpy as np
import numpy.typing as npt

from ..core import ratestate_api as core
from ..core.results import (
    RadauEvent,
    RadauEventRows,
    RadauStatus,
    RateStateEvent,
    RateStateEventRows,
    RateStateRecordRows,
    RateStateSampleRows,
    RateStateStatus,
    radau_progress,
)
from .model import RateStateParameters

__all__ = ["STOP_REASONS", "RateStateStopped"]

FloatArray = npt.NDArray[np.float64]


def _segments(hist: list[tuple[float, float]]) -> tuple[FloatArray, FloatArray]:
    return np.cumsum([d for d, _ in hist]), np.array([v for _, v in hist])


def _history_velocity(hist: list[tuple[float, float]], t: FloatArray) -> FloatArray:
    """Return the load-point velocity of ``hist`` at the times ``t`` (a change's own time: the new one)."""
    seg_end, seg_v = _segments(hist)
    return seg_v[np.clip(np.searchsorted(seg_end, t, side="right"), 0, len(hist) - 1)]


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


#: the compiled integrator's codes, in words: :attr:`RateStateStopped.reason` (its statuses' labels)
STOP_REASONS = {s.code: s.value for s in RateStateStatus if s is not RateStateStatus.OK}


def _status_message(status: RateStateStatus, t: float, v_cap: float, steps: int, seconds: float) -> str:
    """Say why the quasi-static integration stopped at ``t``, with what to try."""
    if status is RateStateStatus.RUNAWAY:
        return (
            f"at t = {t:.6g} s the slip velocity passed {v_cap:.3g} m/s and was still rising: the "
            "quasi-static slider accelerates without bound (an instability: below the critical "
            "stiffness, or with the slip law after a large perturbation). Give the slider a mass "
            "to follow the slip event with inertia, or radiation damping (quasi-dynamic)."
        )
    if status is RateStateStatus.MAX_STEPS:
        return (
            f"stopped after {steps} steps / {seconds:.1f} s at t = {t:.6g} s without finishing; the "
            "case is too stiff at this tolerance (try a larger rtol, or a larger max_steps)"
        )
    if status is RateStateStatus.NONFINITE:
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
    out = RateStateSampleRows.empty(t_s.size, n, nvar, fill=np.nan)
    ev = RateStateEventRows.empty(4096, n, nvar)
    rec = RateStateRecordRows.empty(0, n, nvar)
    events: list[FloatArray] = []
    started = time.monotonic()
    t, js, steps_total = 0.0, 0, 0
    chunk = 50_000
    status = RateStateStatus.OK
    while True:
        code, t, nsamp, nev, _, steps, _ = core.integrate_qs(
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
            out.raw[js:],
            ev.raw,
            rec.raw,
            0,
        )
        status = RateStateStatus.from_code(code)
        events.append(ev.raw[:nev].copy())
        js += nsamp
        steps_total += steps
        if status is RateStateStatus.EVENTS_FULL:
            continue
        if (
            status is RateStateStatus.MAX_STEPS
            and steps_total < max_steps
            and time.monotonic() - started < max_seconds
        ):
            continue
        break
    if status is RateStateStatus.STEP_TOO_SMALL:
        # a slider already far faster than its drive when the step collapses is running away, and
        # is said to (a formula law's runaway collapses the step at 6.5 m/s on its way past 10 m/s)
        v_end = float(core.qs_velocity(y0[0], y0, S, n, P))
        if not v_end < 1e-3 * v_cap:
            status, v_cap = RateStateStatus.RUNAWAY, v_end  # the message says the speed it reached
    if status is not RateStateStatus.OK:
        message = _status_message(status, t, v_cap, steps_total, time.monotonic() - started)
        runaway = status is RateStateStatus.RUNAWAY
        raise RateStateStopped(message, status.value, float(t), float(v_cap) if runaway else math.nan)
    spring = RateStateEventRows(np.concatenate(events), n).of_kind(RateStateEvent.SPRING_PEAK)
    peaks: dict[str, list[tuple[float, FloatArray]]] = {
        "spring": [(float(tp), yp.copy()) for tp, yp in zip(spring.time, spring.slider, strict=True)],
        "velocity": [],
    }
    t_out = t_s[:js]
    got = out[:js]
    return t_out, got.slider.T, got.u, _history_velocity(hist, t_out), peaks


#: the located maxima by the event that locates them (the spring force peaks where v crosses
#: v_lp upward; the slip velocity where the spring force falls below friction)
_PEAKS = {RadauEvent.SPRING_PEAK: "spring", RadauEvent.VELOCITY_PEAK: "velocity"}


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
    # both maxima located on the solver's dense output (_PEAKS)
    peaks: dict[str, list[tuple[float, FloatArray]]] = {"spring": [], "velocity": []}
    ev = RadauEventRows.empty(1024, n, nv)
    y = np.array(y, dtype=float)
    t0 = 0.0
    for k, (dur, v_lp) in enumerate(hist):
        t1 = t0 + dur
        sel = ((t_s > t0) | (k == 0)) & (t_s >= t0) & (t_s <= t1)
        wanted = t_s[sel]
        extra = wanted.size == 0 or wanted[-1] < t1
        t_eval = np.append(wanted, t1) if extra else wanted
        out = np.full((t_eval.size, nv), np.nan)
        ws = core.workspace(nv, t0)
        js = 0
        while True:
            # at most 20 000 steps per call, and never past the bound on the whole run
            budget = min(20_000, max_steps - steps_total - radau_progress(ws)[1])
            code, nsamp, nev = core.integrate_in(
                P, S, n, float(v_lp), y, t1, rtol, atols, t_eval[js:], out[js:], ev.raw, max(budget, 0), *ws
            )
            status = RadauStatus.from_code(code)
            js += nsamp
            found = ev[:nev]
            for kind, t_e, y_e in zip(found.kinds(), found.time, found.y, strict=True):
                peaks[_PEAKS[kind]].append((float(t_e), y_e.copy()))
            if status is RadauStatus.DONE:
                break
            if status is RadauStatus.EVENTS_FULL:
                continue
            t_ws, steps_ws = radau_progress(ws)
            steps = steps_total + steps_ws
            if status is RadauStatus.MAX_STEPS:
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
                f"segment {k} (v_lp = {v_lp:g} m/s): the solver stopped at t = {t_ws:.6g} s: {status.message}"
            )
        steps_total += radau_progress(ws)[1]
        if not np.all(np.isfinite(out)) or not np.all(np.isfinite(y)):
            raise RuntimeError(f"segment {k} (v_lp = {v_lp:g} m/s): the solution overflowed")
        y = out[-1].copy()  # as solve_ivp: the next segment starts from the dense output at t1
        keep = slice(0, -1) if extra else slice(None)
        times.append(t_eval[keep])
        states.append(out[keep].T)
        t0 = t1
    t_out = np.concatenate(times)
    # a sample at a change of the load-point velocity carries the new velocity, as the
    # quasi-static record's does: the record holds each row's velocity until the next row, so a
    # change carried a sample late would put every step a sample late (a fit of that record runs away)
    return t_out, np.concatenate(states, axis=1), _history_velocity(hist, t_out), peaks
