"""Event-driven integration of the one-block spring-slider (numbers only).

Dimensionless model (PHYSICS.md §1-2): spring force ``s`` and block velocity
``w`` obey, while the block slips in direction ``d``,

    s' = nu - w,    w' = s - d f_+(d w),

and while it sticks (``w = 0``, ``|s| <= 1``) ``s`` grows at rate ``nu`` until it
reaches the static threshold: stick phases are solved in closed form. Slip
phases are integrated by DOP853 with dense output; events are located by root
finding on the interpolant:

* stop: ``w`` reaches 0 (including a dip to zero inside one step);
* spring-force extrema: ``w`` crosses ``nu`` (``s`` has a maximum when ``w``
  crosses upward, a minimum when downward), including double crossings inside
  a step;
* velocity extrema: ``dw/dtau = 0``.

After a stop the block sticks if ``-1 <= s < 1``, slips backward if ``s < -1``
and slips forward at once if ``s >= 1``; a backward slip stops likewise.

Everything here takes floats and arrays and returns floats and arrays.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._dop853_unrolled import dense_sw, step_sw, store_dense, store_step
from .dop853 import (
    LEVEL,
    N_STAGES,
    N_STAGES_EXTENDED,
    WEXT,
    dense_eval,
    illinois_sw,
    initial_step,
    poly7,
    rhs,
)
from .laws import STATIC_THRESHOLD, df_plus, f_plus, params

FS = STATIC_THRESHOLD

# Step-size controller. Kept in this file on purpose: numba's on-disk cache is
# invalidated by changes to the source file of the compiled function only, so a
# constant imported from another module would be silently stale.
ERROR_EXPONENT = -1.0 / 8.0  # computed by _root8 (three square roots), not pow
SAFETY = 0.9
MIN_FACTOR = 0.333
MAX_FACTOR = 3.0

# slip-phase outcomes
PH_STOPPED = 0
PH_T_END = 1
PH_CONVERGED = 2
PH_STEP_TOO_SMALL = 3
PH_TOO_MANY_STEPS = 4

# kernel status codes (stored in out[O_STATUS])
ST_OK = 0
ST_NOT_CONVERGED = 1
ST_STEP_TOO_SMALL = 2
ST_TOO_MANY_STEPS = 3
ST_TOO_MANY_PHASES = 4

# regimes (stored in out[O_REGIME])
RG_UNKNOWN = -1
RG_STICK_SLIP = 0
RG_PURE_SLIP = 1
RG_STEADY = 2

# event kinds (event log of trajectories)
EV_STOP = 1
EV_FORWARD = 2
EV_BACKWARD = 3
EV_SMAX = 4
EV_SMIN = 5
EV_STICK = 6

# tracker layout
T_SMAX = 0
T_SMIN = 1
T_WMAX = 2
T_WMIN = 3
T_NMAX = 4
T_TLAST = 5
T_SMIN_SINCE = 6
T_WMIN_SINCE = 7
T_WMAX_SINCE = 8
T_A0 = 9
T_A1 = 10
T_A2 = 11
T_P0 = 12
T_SMAXK = 13
T_SMINK = 14
T_WMAXK = 15
T_WMINK = 16
T_Q2LAST = 17
T_Q3LAST = 18
T_DQ2 = 19
T_DQ3 = 20
T_CONV = 21
T_NSTEP = 22
T_NREJ = 23
T_DFNU = 24
T_FNU = 25
T_NAMP = 26
T_NBACK_SINCE = 27  # backward slip phases since the last spring-force maximum
T_NBACK_K = 28  # ... in the last complete oscillation
NTRK = 29

# output layout of the attractor kernel
O_STATUS = 0
O_REGIME = 1
O_AMPLITUDE = 2
O_PERIOD = 3
O_STICK_TIME = 4
O_SMAX = 5
O_SMIN = 6
O_WMAX = 7
O_WMIN = 8
O_SSTOP = 9
O_NBACKWARD = 10
O_DRIVE_WORK = 11
O_FRICTION_WORK = 12
O_TRANSIENT = 13
O_S = 14
O_W = 15
O_T = 16
O_NSTEP = 17
O_NREJECT = 18
O_DFNU = 19  # f'(nu): steady sliding is linearly stable where it is positive
O_FNU = 20  # f(nu): the spring force of steady sliding
NOUT = 21

# a return map's orbit (return_map_rows): how it ended, and its output columns
RM_OK = 0
RM_FAILED = 1  # an integration failed: RM_AT the start's s, RM_DETAIL its status (ST_*)
RM_STICKS = 2  # the motion sticks: RM_AT the start's s
RM_NO_MAXIMUM = 3  # no force maximum: RM_AT the start's s, RM_DETAIL the time integrated
RM_STALLED = 4  # the secant iteration stalled
RM_NOT_CONVERGED = 5  # no fixed point in the iterations allowed: RM_DETAIL |P(s) - s|
RM_LEFT = 6  # an iterate left the states the engine takes (|s| > RM_MAX_STATE): RM_AT it
#: the largest spring force a return map starts from (core.checks.MAX_STATE)
RM_MAX_STATE = 1e13
RM_STATUS = 0
RM_S0 = 1
RM_PERIOD = 2
RM_MULT = 3
RM_RESIDUAL = 4
RM_AT = 5
RM_DETAIL = 6
NRM = 7
#: the steps allowed a return map's slip phase (run_trajectory's default)
RM_MAX_STEPS = 2_000_000

_ZERO7 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

# a decaying oscillation below this amplitude (units of static friction) about
# a linearly stable steady sliding state counts as steady sliding
AMPLITUDE_STEADY = 1e-7
MAX_PHASES = 100_000
# all slip phases of one run together (a phase alone has max_steps): about ten seconds of work,
# so that no call into the compiled code runs unbounded (Ctrl-C cannot reach it)
MAX_TOTAL_STEPS = 50_000_000


@njit(cache=True)
def _root8(x):  # type: ignore[no-untyped-def]
    """Return ``x ** (1/8)`` (the controller's ``-ERROR_EXPONENT``) for ``x >= 0``.

    Three correctly rounded square roots agree with ``pow`` to an ulp or two and
    cost a fraction of a libm ``pow`` call, which took a tenth of the run time.
    """
    return math.sqrt(math.sqrt(math.sqrt(x)))


@njit(cache=True, inline="always")
def _reset_tracker(trk):  # type: ignore[no-untyped-def]
    inf = math.inf
    trk[T_SMAX] = -inf
    trk[T_SMIN] = inf
    trk[T_WMAX] = -inf
    trk[T_WMIN] = inf
    trk[T_NMAX] = 0.0
    trk[T_TLAST] = 0.0
    trk[T_SMIN_SINCE] = inf
    trk[T_WMIN_SINCE] = inf
    trk[T_WMAX_SINCE] = -inf
    trk[T_A0] = math.nan
    trk[T_A1] = math.nan
    trk[T_A2] = math.nan
    trk[T_P0] = math.nan
    trk[T_SMAXK] = math.nan
    trk[T_SMINK] = math.nan
    trk[T_WMAXK] = math.nan
    trk[T_WMINK] = math.nan
    trk[T_Q2LAST] = 0.0
    trk[T_Q3LAST] = 0.0
    trk[T_DQ2] = math.nan
    trk[T_DQ3] = math.nan
    trk[T_CONV] = 0.0
    trk[T_NAMP] = 0.0
    trk[T_NBACK_SINCE] = 0.0
    trk[T_NBACK_K] = 0.0


@njit(cache=True, inline="always")
def _log(evbuf, evn, t, kind, value):  # type: ignore[no-untyped-def]
    k = evn[0]
    if k < evbuf.shape[0]:
        evbuf[k, 0] = t
        evbuf[k, 1] = kind
        evbuf[k, 2] = value
    evn[0] = k + 1


@njit(cache=True, inline="always")
def _on_w_extremum(trk, w):  # type: ignore[no-untyped-def]
    if w > trk[T_WMAX]:
        trk[T_WMAX] = w
    if w < trk[T_WMIN]:
        trk[T_WMIN] = w
    if w > trk[T_WMAX_SINCE]:
        trk[T_WMAX_SINCE] = w
    if w < trk[T_WMIN_SINCE]:
        trk[T_WMIN_SINCE] = w


@njit(cache=True, inline="always")
def _on_s_extremum(trk, is_max, te, sv, q2, q3, track, conv_tol):  # type: ignore[no-untyped-def]
    """Book-keep a spring-force extremum; test the oscillation for convergence."""
    if not is_max:
        if sv < trk[T_SMIN]:
            trk[T_SMIN] = sv
        if sv < trk[T_SMIN_SINCE]:
            trk[T_SMIN_SINCE] = sv
        return
    if sv > trk[T_SMAX]:
        trk[T_SMAX] = sv
    if trk[T_NMAX] >= 1.0 and trk[T_SMIN_SINCE] < math.inf:
        amp = sv - trk[T_SMIN_SINCE]
        trk[T_A2] = trk[T_A1]
        trk[T_A1] = trk[T_A0]
        trk[T_A0] = amp
        trk[T_NAMP] += 1.0
        trk[T_P0] = te - trk[T_TLAST]
        trk[T_SMAXK] = sv
        trk[T_SMINK] = trk[T_SMIN_SINCE]
        trk[T_WMAXK] = trk[T_WMAX_SINCE]
        trk[T_WMINK] = trk[T_WMIN_SINCE]
        trk[T_DQ2] = q2 - trk[T_Q2LAST]
        trk[T_DQ3] = q3 - trk[T_Q3LAST]
        trk[T_NBACK_K] = trk[T_NBACK_SINCE]
        if track and trk[T_NAMP] >= 3.0:
            a0 = trk[T_A0]
            a1 = trk[T_A1]
            d1 = a0 - a1
            d0 = a1 - trk[T_A2]
            if trk[T_DFNU] > 0.0 and a0 < AMPLITUDE_STEADY and a0 < a1:
                trk[T_CONV] = 2.0
            elif abs(d1) <= conv_tol * abs(a0):
                if d1 == 0.0 or d0 == 0.0:
                    trk[T_CONV] = 1.0
                else:
                    r = abs(d1 / d0)
                    if r < 1.0 and abs(d1) * r / (1.0 - r) <= conv_tol * abs(a0):
                        trk[T_CONV] = 1.0
    trk[T_NMAX] += 1.0
    trk[T_TLAST] = te
    trk[T_Q2LAST] = q2
    trk[T_Q3LAST] = q3
    trk[T_SMIN_SINCE] = math.inf
    trk[T_WMIN_SINCE] = math.inf
    trk[T_WMAX_SINCE] = -math.inf
    trk[T_NBACK_SINCE] = 0.0


@njit(cache=True)
def _slip_phase(  # type: ignore[no-untyped-def]
    law, lp, nu, d, t, y, t_end, rtol, atol, conv_tol,
    K, F, y_new, ytmp, trk, t_eval, out_y, out_mode, ie, evbuf, evn, max_steps,
):
    """Integrate one slip phase in direction ``d`` from ``(t, y)``.

    Returns ``(t, outcome, ie)``; ``y`` holds the final state. The phase ends at a
    stop (``w = 0``, which is set exactly), at ``t_end``, or, when ``conv_tol``
    is positive, when successive oscillations have converged (trajectories pass
    a negative ``conv_tol``: no flag argument, so that every caller shares one
    compiled specialization).

    The loop keeps the state ``(s, w)``, the stages and the interpolant as numbers
    and tuples and calls kernels that take no arrays: passing an array to a
    compiled function (inlined or not) costs two atomic reference-count updates,
    which took a fifth of the run time. ``K``, ``F`` and ``y_new`` are filled only
    with the quadratures (``y`` of length 4), which need their stages.
    """
    n = y.shape[0]
    diag = n > 2
    track = conv_tol > 0.0
    n_eval = t_eval.shape[0]
    rhs(law, lp, nu, d, y, K[0])
    if t_end - t <= 0.0:
        return t, PH_T_END, ie
    h = initial_step(law, lp, nu, d, y, K[0], rtol, atol, t_end - t, ytmp, y_new)
    P = params(lp)
    s = y[0]
    w = y[1]
    ks0 = K[0, 0]  # derivative at (s, w)
    kw0 = K[0, 1]
    cs = _ZERO7  # interpolant coefficients of s and w in the current step
    cw = _ZERO7
    rejected = False
    h_acc = 0.0
    err_acc = 0.0
    nsteps = 0
    while True:
        if nsteps >= max_steps:
            return t, PH_TOO_MANY_STEPS, ie
        remaining = t_end - t
        min_step = 10.0 * 2.220446049250313e-16 * max(abs(t), 1e-300)
        if remaining <= min_step:
            return t_end, PH_T_END, ie
        hh = h if h < remaining else remaining
        if hh < min_step:
            return t, PH_STEP_TOO_SMALL, ie
        err, s1, w1, ks, kw = step_sw(law, P, nu, d, s, w, ks0, kw0, hh, rtol, atol)
        if not (err <= 1.0):
            if err != err or err == math.inf:
                factor = MIN_FACTOR
            else:
                factor = max(MIN_FACTOR, SAFETY / _root8(err))
            h = hh * factor
            rejected = True
            trk[T_NREJ] += 1.0
            continue
        if err == 0.0:
            factor = MAX_FACTOR
        else:
            factor = min(MAX_FACTOR, SAFETY / _root8(err))
            if h_acc > 0.0 and err_acc > 0.0:
                # Gustafsson's predictive controller (as in Hairer's RADAU5): follows
                # an error constant that changes steadily from step to step, as it
                # does when a slip decelerates into the steep part of the law.
                pred = SAFETY * (hh / h_acc) * _root8(err_acc / (err * err))
                factor = max(MIN_FACTOR, min(factor, pred))
        if rejected:
            factor = min(1.0, factor)
        h_acc = hh
        err_acc = max(err, 1e-10)
        h_next = hh * factor
        rejected = False
        nsteps += 1
        trk[T_NSTEP] += 1.0
        if diag:
            store_step(law, lp, nu, d, y, hh, K, y_new, s1, w1, ks, kw)

        # ---- events inside the accepted step [t, t + hh] ----------------
        # The interpolant (dense_sw) is computed once, in a step where an event or a
        # sample needs it: the velocity turns (dw changes sign), the block stops (d*w
        # reaches zero), the spring force turns in forward slip (w crosses nu), or a
        # sample time falls in the step. (One call site: each costs compile time.)
        w0 = w
        dw0 = kw0
        dw1 = kw[N_STAGES]
        turns = (dw0 > 0.0 and dw1 < 0.0) or (dw0 < 0.0 and dw1 > 0.0)
        g0 = w0 - nu
        g1 = w1 - nu
        if (
            turns
            or (d * w0 > 0.0 and d * w1 <= 0.0)
            or (d > 0 and (g0 * g1 < 0.0 or (g1 == 0.0 and g0 != 0.0)))
            or (ie < n_eval and t_eval[ie] <= t + hh)
        ):
            cs, cw, ksx, kwx = dense_sw(law, P, nu, d, s, w, s1, w1, hh, ks, kw)
            if diag:
                store_dense(law, lp, nu, d, y, y_new, hh, K, F, cs, cw, ksx, kwx)
        x_wext = -1.0
        wext = 0.0
        if turns:
            x_wext = illinois_sw(law, P, d, cs, s, cw, w, WEXT + 0 * law, 0.0, 0.0, dw0, 1.0, dw1)
            wext = poly7(cw, w, x_wext)
        # stop: d*w reaches zero, bracketed in [x_lo, x_hi] (one root-finder call site)
        x_stop = 2.0
        stops = False
        x_lo = 0.0
        w_lo = w0
        x_hi = 1.0
        w_hi = w1
        if d * w0 > 0.0:
            if d * w1 <= 0.0:
                stops = True
            elif x_wext >= 0.0 and d * wext <= 0.0 and d * dw0 < 0.0:
                stops = True
                x_hi = x_wext
                w_hi = wext
        elif d * w0 == 0.0 and x_wext >= 0.0 and d * wext > 0.0 and d * w1 <= 0.0:
            # a phase that starts at rest (w = 0) with a weak push (after a stop just
            # past the static threshold) can end inside its first step: w leaves zero,
            # turns at x_wext and is back at zero before the step ends
            stops = True
            x_lo = x_wext
            w_lo = wext
        if stops:
            x_stop = illinois_sw(law, P, d, cs, s, cw, w, LEVEL + 0 * law, 0.0, x_lo, w_lo, x_hi, w_hi)
        x_end = x_stop if x_stop < 1.0 else 1.0
        # spring-force extrema (w = nu), forward slip only; velocity extrema
        # at most three events in the step, held as numbers (no array: the same source
        # compiles for a GPU, where a kernel allocates nothing)
        nev = 0
        ex0 = ex1 = ex2 = 0.0
        ek0 = ek1 = ek2 = 0
        if x_wext >= 0.0 and x_wext <= x_end:
            ex0 = x_wext
            ek0 = 0
            nev = 1
        if d > 0:
            # w - nu changes sign on [0, x_end], or on each side of a velocity extremum in it
            split = nev == 1 and x_wext < x_end
            x_lo = 0.0
            g_lo = g0
            for seg in range(2 if split else 1):
                if split and seg == 0:
                    x_hi = x_wext
                    g_hi = wext - nu
                else:
                    x_hi = x_end
                    g_hi = -nu if x_stop <= 1.0 else g1
                if g_lo * g_hi < 0.0 or (g_hi == 0.0 and g_lo != 0.0):
                    xr = illinois_sw(
                        law, P, d, cs, s, cw, w, LEVEL + 0 * law, nu, x_lo, g_lo, x_hi, g_hi
                    )
                    kr = 1 if g_lo < 0.0 else -1
                    if nev == 0:
                        ex0 = xr
                        ek0 = kr
                    elif nev == 1:
                        ex1 = xr
                        ek1 = kr
                    else:
                        ex2 = xr
                        ek2 = kr
                    nev += 1
                x_lo = x_hi
                g_lo = g_hi
        # process in time order: a stable sort of at most three (the order of an
        # insertion sort, ties kept in the order found)
        if nev >= 2 and ex0 > ex1:
            ex0, ex1 = ex1, ex0
            ek0, ek1 = ek1, ek0
        if nev == 3:
            if ex1 > ex2:
                ex1, ex2 = ex2, ex1
                ek1, ek2 = ek2, ek1
            if ex0 > ex1:
                ex0, ex1 = ex1, ex0
                ek0, ek1 = ek1, ek0
        for a in range(nev):
            xa = ex0 if a == 0 else (ex1 if a == 1 else ex2)
            ka = ek0 if a == 0 else (ek1 if a == 1 else ek2)
            if ka == 0:
                _on_w_extremum(trk, wext)
            else:
                te = t + xa * hh
                sv = poly7(cs, s, xa)
                q2 = 0.0
                q3 = 0.0
                if diag:
                    q2 = dense_eval(F, y, xa, 2)
                    q3 = dense_eval(F, y, xa, 3)
                is_max = ka > 0
                if evbuf.shape[0] > 0:
                    _log(evbuf, evn, te, EV_SMAX if is_max else EV_SMIN, sv)
                _on_s_extremum(trk, is_max, te, sv, q2, q3, track, conv_tol)
        # dense samples requested by the caller
        t_seg_end = t + x_end * hh
        while ie < n_eval and t_eval[ie] <= t_seg_end:
            xe = (t_eval[ie] - t) / hh
            if xe < 0.0:
                xe = 0.0
            out_y[ie, 0] = poly7(cs, s, xe)
            out_y[ie, 1] = poly7(cw, w, xe)
            out_mode[ie] = d
            ie += 1
        if x_stop <= 1.0:
            if diag:
                for i in range(2, n):
                    y[i] = dense_eval(F, y, x_stop, i)
            y[0] = poly7(cs, s, x_stop)
            y[1] = 0.0
            return t + x_stop * hh, PH_STOPPED, ie
        t = t + hh
        s = s1
        w = w1
        ks0 = ks[N_STAGES]
        kw0 = kw[N_STAGES]
        y[0] = s1
        y[1] = w1
        if diag:
            for i in range(2, n):
                y[i] = y_new[i]
        if track:
            if trk[T_CONV] != 0.0:
                return t, PH_CONVERGED, ie
            if (
                trk[T_DFNU] > 0.0
                and abs(y[1] - nu) < AMPLITUDE_STEADY
                and abs(y[0] - trk[T_FNU]) < AMPLITUDE_STEADY
            ):
                trk[T_CONV] = 2.0
                return t, PH_CONVERGED, ie
        if t >= t_end:
            return t_end, PH_T_END, ie
        h = h_next


@njit(cache=True)
def _mode_at(s, w):  # type: ignore[no-untyped-def]
    """Return the phase (0 stick, +1/-1 slip direction) a state at rest or moving is in."""
    if w > 0.0:
        return 1
    if w < 0.0:
        return -1
    if s >= FS:
        return 1
    if s < -FS:
        return -1
    return 0


@njit(cache=True)
def new_workspace(n):  # type: ignore[no-untyped-def]
    """Allocate the work arrays of one integration (``n`` = 2, or 4 with quadratures).

    The last five are the empty sample and event buffers of :func:`_slip_phase`
    (an attractor samples nothing) and the event counter.
    """
    return (
        np.empty((N_STAGES_EXTENDED, n)),
        np.empty((7, n)),
        np.empty(n),
        np.empty(n),
        np.empty(n),
        np.empty(NTRK),
        np.empty(0),
        np.empty((0, 2)),
        np.empty(0, dtype=np.int64),
        np.empty((0, 3)),
        np.zeros(1, dtype=np.int64),
    )


@njit(cache=True)
def attractor_ws(  # type: ignore[no-untyped-def]
    law, lp, nu, s0, w0, from_breakaway, rtol, atol, t_max, conv_tol, max_steps, out,
    K, F, y_new, ytmp, y, trk, t_eval, out_y, out_mode, evbuf, evn,
):
    """Follow the motion from ``(s0, w0)`` to its attractor and measure one steady cycle.

    With ``from_breakaway`` the start ``(1, 0)`` is taken as the beginning of a
    stick-slip cycle, so the first slip integration is measured at once: if it
    ends in a stick, that one slip integration is the whole steady stick-slip
    cycle (PHYSICS.md §2). Otherwise the motion is followed until it first
    sticks (after which it is on the stick-slip cycle, measured from the next
    breakaway). In both cases, a motion that does not stick is followed until
    successive oscillations converge (pure slip) or decay about a linearly
    stable steady state (steady sliding). ``t_max`` bounds the total slip time
    integrated. Results go to ``out`` (layout ``O_*``). The work arrays, ``K`` to
    ``evn``, are those of :func:`new_workspace` (allocated by the caller, so that
    this kernel compiles no allocation of its own).
    """
    n = y.shape[0]
    diag = n > 2
    for i in range(n):
        y[i] = 0.0
    _reset_tracker(trk)
    trk[T_NSTEP] = 0.0
    trk[T_NREJ] = 0.0
    trk[T_DFNU] = df_plus(law, params(lp), nu)
    trk[T_FNU] = f_plus(law, params(lp), nu)
    ie0 = np.int64(0)  # not the literal 0: one compiled _slip_phase for every caller
    for i in range(NOUT):
        out[i] = math.nan
    out[O_STATUS] = ST_OK
    out[O_REGIME] = RG_UNKNOWN
    if from_breakaway:
        s0 = FS
        w0 = 0.0
    y[0] = s0
    y[1] = w0
    t = 0.0
    slip_used = 0.0
    measuring = from_breakaway
    d = 1 if from_breakaway else _mode_at(s0, w0)
    t_c0 = 0.0
    n_back = 0
    out[O_TRANSIENT] = 0.0
    for _ in range(MAX_PHASES):
        if d == 0:
            s = y[0]
            dt = (FS - s) / nu
            if measuring:
                out[O_REGIME] = RG_STICK_SLIP
                out[O_AMPLITUDE] = max(trk[T_SMAX], FS) - min(trk[T_SMIN], s)
                out[O_PERIOD] = (t - t_c0) + dt
                out[O_STICK_TIME] = dt
                out[O_SMAX] = max(trk[T_SMAX], FS)
                out[O_SMIN] = min(trk[T_SMIN], s)
                out[O_WMAX] = max(trk[T_WMAX], 0.0)
                out[O_WMIN] = min(trk[T_WMIN], 0.0)
                out[O_SSTOP] = s
                out[O_NBACKWARD] = n_back
                if diag:
                    out[O_DRIVE_WORK] = nu * y[2] + nu * 0.5 * (s + FS) * dt
                    out[O_FRICTION_WORK] = y[3]
                out[O_S] = FS
                out[O_W] = 0.0
                out[O_T] = t + dt
                break
            t += dt
            out[O_TRANSIENT] = t
            measuring = True
            _reset_tracker(trk)
            for i in range(n):
                y[i] = 0.0
            y[0] = FS
            d = 1
            t_c0 = t
            n_back = 0
            continue
        t_start = t
        t, ph, _ie = _slip_phase(
            law, lp, nu, d, t, y, t + (t_max - slip_used), rtol, atol, conv_tol,
            K, F, y_new, ytmp, trk, t_eval, out_y, out_mode, ie0,
            evbuf, evn, max_steps,
        )
        slip_used += t - t_start
        if ph == PH_STOPPED:
            if trk[T_NSTEP] > MAX_TOTAL_STEPS:
                out[O_STATUS] = ST_TOO_MANY_STEPS
                break
            s = y[0]
            if s < -FS:
                d = -1
                n_back += 1
                trk[T_NBACK_SINCE] += 1.0
            elif s >= FS:
                d = 1
            else:
                d = 0
            continue
        out[O_S] = y[0]
        out[O_W] = y[1]
        out[O_T] = t
        if ph == PH_CONVERGED or ph == PH_T_END:
            if ph == PH_T_END:
                out[O_STATUS] = ST_NOT_CONVERGED
            if trk[T_CONV] == 2.0:
                out[O_REGIME] = RG_STEADY
                out[O_AMPLITUDE] = 0.0
                out[O_PERIOD] = math.nan
                out[O_STICK_TIME] = 0.0
                out[O_SMAX] = trk[T_FNU]
                out[O_SMIN] = trk[T_FNU]
                out[O_WMAX] = nu
                out[O_WMIN] = nu
                out[O_DRIVE_WORK] = 0.0
                out[O_FRICTION_WORK] = 0.0
            elif trk[T_NAMP] >= 1.0:
                out[O_REGIME] = RG_PURE_SLIP
                out[O_AMPLITUDE] = trk[T_A0]
                out[O_PERIOD] = trk[T_P0]
                out[O_STICK_TIME] = 0.0
                out[O_SMAX] = trk[T_SMAXK]
                out[O_SMIN] = trk[T_SMINK]
                out[O_WMAX] = trk[T_WMAXK]
                out[O_WMIN] = trk[T_WMINK]
                out[O_NBACKWARD] = trk[T_NBACK_K]
                if diag:
                    out[O_DRIVE_WORK] = nu * trk[T_DQ2]
                    out[O_FRICTION_WORK] = trk[T_DQ3]
            out[O_TRANSIENT] = t
        elif ph == PH_STEP_TOO_SMALL:
            out[O_STATUS] = ST_STEP_TOO_SMALL
        else:
            out[O_STATUS] = ST_TOO_MANY_STEPS
        break
    else:
        out[O_STATUS] = ST_TOO_MANY_PHASES
    out[O_NSTEP] = trk[T_NSTEP]
    out[O_NREJECT] = trk[T_NREJ]
    out[O_DFNU] = trk[T_DFNU]
    out[O_FNU] = trk[T_FNU]


@njit(cache=True, nogil=True)
def attractor_rows(  # type: ignore[no-untyped-def]
    law, lp, nu, s0, w0, from_breakaway, rtol, atol, t_max, conv_tol, diag, max_steps, out
):
    """Run :func:`attractor` for every row in this thread, with one workspace.

    It releases the GIL: :func:`stickslip.core.api.run_attractors` runs blocks of
    rows in a pool of threads. (A ``prange`` kernel did the same but took seconds
    more to compile on a first run, for each law.)
    """
    ws = new_workspace(4 if diag else 2)
    for i in range(nu.shape[0]):
        attractor_ws(
            law[i], lp[i], nu[i], s0[i], w0[i], from_breakaway, rtol, atol, t_max,
            conv_tol, max_steps, out[i], ws[0], ws[1], ws[2], ws[3], ws[4], ws[5],
            ws[6], ws[7], ws[8], ws[9], ws[10],
        )


@njit(cache=True)
def trajectory(  # type: ignore[no-untyped-def]
    law, lp, nu, s0, w0, t_eval, rtol, atol, max_steps, out_y, out_mode, evbuf, evn
):
    """Integrate from ``(s0, w0)`` at time 0 and sample at the sorted times ``t_eval``.

    ``out_y[:, 0]`` is the spring force, ``out_y[:, 1]`` the velocity and
    ``out_mode`` the phase (0 stick, +1 forward slip, -1 backward slip). Events
    go to ``evbuf`` (rows ``t, kind, s``); ``evn[0]`` counts them even past the
    buffer's capacity. Returns a status code (``ST_*``).
    """
    n = 2
    K = np.empty((N_STAGES_EXTENDED, n))
    F = np.empty((7, n))
    y_new = np.empty(n)
    ytmp = np.empty(n)
    y = np.zeros(n)
    trk = np.empty(NTRK)
    _reset_tracker(trk)
    trk[T_NSTEP] = 0.0
    trk[T_NREJ] = 0.0
    trk[T_DFNU] = 0.0
    trk[T_FNU] = 0.0
    y[0] = s0
    y[1] = w0
    n_eval = t_eval.shape[0]
    t_end = t_eval[n_eval - 1]
    t = 0.0
    ie = np.int64(0)
    d = _mode_at(s0, w0)
    if w0 == 0.0 and d != 0:  # a start at rest beyond a threshold breaks away at t = 0, as after a stop
        _log(evbuf, evn, 0.0, EV_FORWARD if d == 1 else EV_BACKWARD, s0)
    for _ in range(MAX_PHASES + n_eval):
        if ie >= n_eval:
            return ST_OK
        if d == 0:
            s = y[0]
            t_b = t + (FS - s) / nu
            while ie < n_eval and t_eval[ie] <= t_b:
                out_y[ie, 0] = s + nu * (t_eval[ie] - t)
                out_y[ie, 1] = 0.0
                out_mode[ie] = 0
                ie += 1
            if t_b >= t_end:
                return ST_OK
            t = t_b
            y[0] = FS
            y[1] = 0.0
            d = 1
            _log(evbuf, evn, t, EV_FORWARD, FS)
            continue
        t, ph, ie = _slip_phase(
            law, lp, nu, d, t, y, t_end, rtol, atol, -1.0, K, F, y_new, ytmp,
            trk, t_eval, out_y, out_mode, ie, evbuf, evn, max_steps,
        )
        if ph == PH_STOPPED:
            if trk[T_NSTEP] > MAX_TOTAL_STEPS:
                return ST_TOO_MANY_STEPS
            s = y[0]
            _log(evbuf, evn, t, EV_STOP, s)
            if s < -FS:
                d = -1
                _log(evbuf, evn, t, EV_BACKWARD, s)
            elif s >= FS:
                d = 1
                _log(evbuf, evn, t, EV_FORWARD, s)
            else:
                d = 0
                _log(evbuf, evn, t, EV_STICK, s)
            continue
        if ph == PH_T_END:
            while ie < n_eval:
                out_y[ie, 0] = y[0]
                out_y[ie, 1] = y[1]
                out_mode[ie] = d
                ie += 1
            return ST_OK
        if ph == PH_STEP_TOO_SMALL:
            return ST_STEP_TOO_SMALL
        return ST_TOO_MANY_STEPS
    return ST_TOO_MANY_PHASES


@njit(cache=True)
def _next_force_maximum(law, lp, nu, s0, t_guess, rtol, atol, t_eval, y, mode, res):  # type: ignore[no-untyped-def]
    """Put in ``res`` the return map on ``w = nu``: ``(s, t)`` at the next force maximum from ``(s0, nu)``.

    Returns ``RM_OK``, or why there is none (``res[0]`` then the start's ``s``,
    ``res[1]`` the integration's status or the time integrated). The trajectory
    runs to ``2.5 t_guess``, doubled up to seven times until a maximum is passed;
    a stop into a stick phase on the way is not a non-sticking orbit.
    """
    t_end = 2.5 * t_guess
    for _ in range(8):
        t_eval[0] = t_end
        cap = 64
        while True:
            ev = np.empty((cap, 3))
            evn = np.zeros(1, dtype=np.int64)
            status = trajectory(law, lp, nu, s0, nu, t_eval, rtol, atol, RM_MAX_STEPS, y, mode, ev, evn)
            if evn[0] <= cap:
                break
            cap = evn[0]
        if status != ST_OK:
            res[0] = s0
            res[1] = status
            return RM_FAILED
        for k in range(evn[0]):
            if ev[k, 1] == EV_STICK:
                res[0] = s0
                return RM_STICKS
        for k in range(evn[0]):
            if ev[k, 1] == EV_SMAX and ev[k, 0] > 0.0:
                res[0] = ev[k, 2]
                res[1] = ev[k, 0]
                return RM_OK
        t_end *= 2.0
    res[0] = s0
    res[1] = t_end
    return RM_NO_MAXIMUM


@njit(cache=True)
def return_map_orbit(law, lp, nu, s_guess, t_guess, tol, max_iter, out):  # type: ignore[no-untyped-def]
    """Find a non-sticking periodic orbit as a fixed point of the return map on ``w = nu`` (into ``out``).

    Secant iterations on ``P(s) - s`` from ``s_guess`` and ``s_guess + 1e-6``
    (relative), the flow at ``tol / 100``; the multiplier ``P'`` by central
    differences at ``h`` and ``h / 2`` extrapolated (Richardson), ``h = 1e-5``
    (relative). ``out`` (``NRM`` numbers): status ``RM_*``, ``s0``, period,
    multiplier, residual ``|P(s0) - s0|``, and what a failure was.
    """
    for j in range(NRM):
        out[j] = np.nan
    rtol = tol * 1e-2
    atol = tol * 1e-4
    t_eval = np.empty(1)
    y = np.empty((1, 2))
    mode = np.empty(1, dtype=np.int64)
    res = np.empty(2)
    ws = (t_eval, y, mode, res)
    scale = max(1.0, abs(s_guess))
    x0 = s_guess
    x1 = x0 + 1e-6 * scale
    if not _map_step(law, lp, nu, x0, t_guess, rtol, atol, ws, out):
        return
    g0 = res[0]
    if not _map_step(law, lp, nu, x1, t_guess, rtol, atol, ws, out):
        return
    g1, t1 = res[0], res[1]
    converged = False
    for _ in range(max_iter):
        if abs(g1) < tol * scale:
            converged = True
            break
        if g1 == g0:
            out[RM_STATUS] = RM_STALLED
            return
        x0, x1, g0 = x1, x1 - g1 * (x1 - x0) / (g1 - g0), g1
        if not _map_step(law, lp, nu, x1, t_guess, rtol, atol, ws, out):
            return
        g1, t1 = res[0], res[1]
    if not converged:
        out[RM_STATUS] = RM_NOT_CONVERGED
        out[RM_DETAIL] = abs(g1)
        return
    # the map is strongly curved near sticking: at h = 1e-5 alone its derivative was off by
    # 1e-7 to 3e-7; extrapolated from h and h / 2, by 7.5e-12 and 6.9e-9 at two orbits
    h = 1e-5 * scale
    central = np.empty(2)
    for m in range(2):
        step = 0.5 * h if m == 0 else h
        if not _map_step(law, lp, nu, x1 + step, t_guess, rtol, atol, ws, out):
            return
        up = res[0]
        if not _map_step(law, lp, nu, x1 - step, t_guess, rtol, atol, ws, out):
            return
        central[m] = (up - res[0]) / (2.0 * step)
    out[RM_STATUS] = RM_OK
    out[RM_S0] = x1
    out[RM_PERIOD] = t1
    out[RM_MULT] = 1.0 + (4.0 * central[0] - central[1]) / 3.0
    out[RM_RESIDUAL] = abs(g1)


@njit(cache=True)
def _map_step(law, lp, nu, s, t_guess, rtol, atol, ws, out):  # type: ignore[no-untyped-def]
    """Put ``(P(s) - s, t)`` in ``ws[3]`` and return True; or say in ``out`` why there is no ``P(s)``."""
    t_eval, y, mode, res = ws
    if not abs(s) <= RM_MAX_STATE:  # NaN too
        out[RM_STATUS], out[RM_AT] = RM_LEFT, s
        return False
    code = _next_force_maximum(law, lp, nu, s, t_guess, rtol, atol, t_eval, y, mode, res)
    if code != RM_OK:
        out[RM_STATUS], out[RM_AT], out[RM_DETAIL] = code, res[0], res[1]
        return False
    res[0] = res[0] - s
    return True

@njit(cache=True, nogil=True)
def return_map_rows(law, lp, nu, s_guess, t_guess, tol, max_iter, out):  # type: ignore[no-untyped-def]
    """Run :func:`return_map_orbit` for every row in this thread (it releases the GIL)."""
    for i in range(nu.shape[0]):
        return_map_orbit(law[i], lp[i], nu[i], s_guess[i], t_guess[i], tol, max_iter, out[i])
