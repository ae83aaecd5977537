"""Compiled engine of the forced friction oscillator: stick in closed form, slip by DOP853.

The dimensionless model (PHYSICS.md §1's units: forces of ``mu_s W``, times of
``sqrt(m/k)``) with a harmonic drive, a harmonic force on the block and viscous
damping::

    s' = nu(tau) - w,          nu(tau) = nu0 + nu1 cos(omega tau + phi)
    w' = s + q cos(omega tau) - delta w - f(w)          (slip, w != 0)
    w = 0 while |s + q cos(omega tau)| <= 1             (stick)

``s`` is the spring force (the spring's far end has velocity ``nu(tau)``; a
support displacement ``Y sin(omega tau + phi)`` is ``nu1 = omega Y``), ``w`` the
block's velocity relative to the surface, ``q cos(omega tau)`` the external
force. The forcing vector ``fp`` is ``(nu0, nu1, omega, phi, q, delta)``
(``FP_*``). With ``nu1 = q = 0`` this is the one-block engine's model.

Stick is exact: ``s(tau) = s0 + nu0 (tau - tau0) + (nu1/omega) [sin(omega tau + phi)
- sin(omega tau0 + phi)]``, and breakaway, where ``|g| = |s + q cos(omega tau)|``
reaches the static threshold 1, is approached from inside by steps that cannot
jump over it: with ``|g''| <= M2 = |nu1| omega + |q| omega**2``, a step ``h`` with
``|g'| h + M2 h**2 / 2`` below the margin stays inside, and the steps converge
quadratically onto a transversal crossing. Slip phases are integrated by the
DOP853 pair of :mod:`stickslip.core.dop853` with time as argument; stops are
located on its 7th-order dense output; the end of a call (a stroboscopic
section) ends a step exactly.

With ``track`` the 2 x 2 Jacobian ``Phi = d(s, w)/d(s, w)_0`` rides along (the
variational equations ``Phi' = J Phi``, ``J = [[0, -1], [1, -delta - f'(w)]]``)
and is multiplied at each transition by its saltation matrix:

- slip to stick at ``w = 0``: ``[[1, 0], [0, 0]]`` (stick forgets ``w``);
- stick to slip where ``g = d`` (``d = +-1``): ``[[1, 0], [a / g', 1]]`` with ``a``
  the acceleration just after breakaway, ``d (1 - f_+(0))``, and ``g'`` the rate of
  ``g`` in stick;
- slip reversal at ``w = 0``: ``[[1, 0], [0, a_+ / a_-]]``, the accelerations after
  and before.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._dop853_tableau import N_STAGES, N_STAGES_EXTENDED, C
from .dop853 import (
    dense_eval,
    dense_slope,
    illinois_propose,
    illinois_update,
    vec_advance,
    vec_dense_coeffs,
    vec_error,
    vec_stage,
)
from .laws import df_plus, f_plus, friction_scalar, params

# the forcing vector
FP_NU0 = 0
FP_NU1 = 1
FP_OMEGA = 2
FP_PHI = 3
FP_Q = 4
FP_DELTA = 5
NFP = 6

# the state vector: time, spring force, velocity, mode (0 stick, +1 / -1 slip direction)
S_TAU = 0
S_S = 1
S_W = 2
S_MODE = 3
NSTATE = 4

# the statistics of a call (accumulated over calls until reset)
ST_STOPS = 0  # slip to stick
ST_BREAKS = 1  # stick to slip
ST_REVERSALS = 2  # slip reversed without stick
ST_STICK_TIME = 3
ST_STEPS = 4
ST_STATUS = 5
ST_NEXT = 6  # next sample to fill
ST_S_MIN = 7
ST_S_MAX = 8
ST_W_MIN = 9
ST_W_MAX = 10
ST_TOUCHES = 11  # w reached 0 with the net force still pushing on: slip goes on
NST = 12

# statuses
F_OK = 0
F_MAX_STEPS = 1
F_NONFINITE = 2
F_MAX_EVENTS = 3

NVAR_TRACK = 6  # s, w and Phi (row-major)
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
#: a breakaway is declared where the margin to the threshold is below this
STICK_TOL = 1e-13
#: steps of the stick locator before it declares a touch (geometric convergence onto a tangency)
STICK_ITER = 400
#: longest slip step, in forcing periods
MAX_STEP_PERIODS = 0.125


@njit(cache=True, inline="always")
def drive(fp, t):  # type: ignore[no-untyped-def]
    """Return the velocity of the spring's far end, ``nu0 + nu1 cos(omega t + phi)``."""
    if fp[1] == 0.0:  # no modulation: the same number without a cosine (a third of a stage's cost)
        return fp[0]
    return fp[0] + fp[1] * math.cos(fp[2] * t + fp[3])


@njit(cache=True, inline="always")
def external(fp, t):  # type: ignore[no-untyped-def]
    """Return the external force, ``q cos(omega t)``."""
    if fp[4] == 0.0:
        return 0.0
    return fp[4] * math.cos(fp[2] * t)


@njit(cache=True)
def stick_s(fp, s0, t0, t):  # type: ignore[no-untyped-def]
    """Return the spring force at ``t`` of a block stuck since ``t0`` with spring force ``s0``."""
    s = s0 + fp[0] * (t - t0)
    if fp[1] != 0.0:
        s += fp[1] / fp[2] * (math.sin(fp[2] * t + fp[3]) - math.sin(fp[2] * t0 + fp[3]))
    return s


@njit(cache=True, inline="always")
def _stick_rate(fp, t):  # type: ignore[no-untyped-def]
    """Return ``g'(t)`` in stick: the rate of the net force ``s + q cos(omega t)``."""
    return drive(fp, t) - fp[4] * fp[2] * math.sin(fp[2] * t)


@njit(cache=True, inline="always")
def _safe_step(gp, m2, margin):  # type: ignore[no-untyped-def]
    """Return the longest step over which ``g`` (rate ``gp``, ``|g''| <= m2``) cannot gain ``margin``."""
    if m2 > 0.0:
        root = math.sqrt(gp * gp + 2.0 * m2 * margin)
        if gp > 0.0:
            return 2.0 * margin / (gp + root)
        return (root - gp) / m2
    if gp > 0.0:
        return margin / gp
    return math.inf


@njit(cache=True)
def stick_end(fp, t0, s0, t_end):  # type: ignore[no-untyped-def]
    """Return ``(t, d)``: the breakaway time and direction of a block stuck at ``t0``, or ``(t_end, 0)``.

    ``d`` is the direction of the slip that follows (+1 where ``g`` reaches 1,
    -1 where it reaches -1). A block whose ``|g|`` already exceeds 1 breaks away
    at ``t0``.
    """
    om = fp[2]
    m2 = abs(fp[1]) * om + abs(fp[4]) * om * om
    t = t0
    for _ in range(STICK_ITER):
        g = stick_s(fp, s0, t0, t) + external(fp, t)
        gp = _stick_rate(fp, t)
        up = 1.0 - g
        lo = 1.0 + g
        if up <= STICK_TOL or lo <= STICK_TOL:
            d = 1 if up <= lo else -1
            margin = up if d == 1 else lo
            rate = gp if d == 1 else -gp
            if margin > 0.0 and rate > 0.0:
                t += margin / rate  # one Newton step onto the threshold
            return t, d
        h = min(_safe_step(gp, m2, up), _safe_step(-gp, m2, lo))
        if t + h >= t_end:
            return t_end, 0
        t += h
    # the margin shrank geometrically without a crossing: a tangency, where the block
    # leaves the threshold as soon as it reaches it
    g = stick_s(fp, s0, t0, t) + external(fp, t)
    return t, 1 if g > 0.0 else -1


@njit(cache=True)
def rhs(law, P, fp, d, t, y, n, out):  # type: ignore[no-untyped-def]
    """Evaluate the slip vector field in direction ``d`` at time ``t`` (with ``Phi' = J Phi`` if n = 6)."""
    s = y[0]
    w = y[1]
    out[0] = drive(fp, t) - w
    out[1] = s + external(fp, t) - fp[5] * w - friction_scalar(law, P, d, w)
    if n > 2:
        damp = fp[5] + df_plus(law, P, d * w)
        out[2] = -y[4]
        out[3] = -y[5]
        out[4] = y[2] - damp * y[4]
        out[5] = y[3] - damp * y[5]


@njit(cache=True)
def _fill_stick_samples(fp, t0, s0, t_hi, inclusive, ts, samples, stats):  # type: ignore[no-untyped-def]
    k = int(stats[ST_NEXT])
    while k < ts.shape[0] and (ts[k] < t_hi or (inclusive and ts[k] == t_hi)):
        samples[k, 0] = stick_s(fp, s0, t0, ts[k])
        samples[k, 1] = 0.0
        samples[k, 2] = 0.0
        k += 1
    stats[ST_NEXT] = k


@njit(cache=True)
def _fill_slip_samples(t, h, F, y, t_hi, inclusive, mode, ts, samples, stats):  # type: ignore[no-untyped-def]
    k = int(stats[ST_NEXT])
    while k < ts.shape[0] and (ts[k] < t_hi or (inclusive and ts[k] == t_hi)):
        x = (ts[k] - t) / h
        samples[k, 0] = dense_eval(F, y, x, 0)
        samples[k, 1] = dense_eval(F, y, x, 1)
        samples[k, 2] = mode
        k += 1
    stats[ST_NEXT] = k


@njit(cache=True)
def _extra_stages(law, P, fp, d, t, y, K, h, n, ytmp):  # type: ignore[no-untyped-def]
    """Fill the interpolant's three extra stages of ``K``."""
    for j in range(N_STAGES + 1, N_STAGES_EXTENDED):
        vec_stage(y, K, h, j, n, ytmp)
        rhs(law, P, fp, d, t + C[j] * h, ytmp, n, K[j])


@njit(cache=True)
def _note(stats, s, w):  # type: ignore[no-untyped-def]
    stats[ST_S_MIN] = min(stats[ST_S_MIN], s)
    stats[ST_S_MAX] = max(stats[ST_S_MAX], s)
    stats[ST_W_MIN] = min(stats[ST_W_MIN], w)
    stats[ST_W_MAX] = max(stats[ST_W_MAX], w)


@njit(cache=True)
def advance(law, lp, fp, st, phi, t_end, rtol, atol, track, ts, samples, stats, max_steps, work):  # type: ignore[no-untyped-def]
    """Advance the state ``st`` (``S_*``) to ``t_end`` exactly; return the status (``F_*``).

    ``phi`` (4, row-major) is multiplied by the Jacobian of the flow over the call
    when ``track``. Samples at the times ``ts`` (ascending) from ``stats[ST_NEXT]``
    on, inside the call's interval, are written to ``samples`` (``s, w, mode``).
    ``stats`` accumulates the events and extremes (``ST_*``); ``max_steps`` bounds
    the slip steps and phases of the call. ``work`` is the scratch array of
    :func:`new_work`.
    """
    P = params(lp)
    n = NVAR_TRACK if track else 2
    K = work[0:N_STAGES_EXTENDED]
    F = work[N_STAGES_EXTENDED : N_STAGES_EXTENDED + 7]
    y = work[N_STAGES_EXTENDED + 7]
    ynew = work[N_STAGES_EXTENDED + 8]
    ytmp = work[N_STAGES_EXTENDED + 9]
    t = st[S_TAU]
    s = st[S_S]
    w = st[S_W]
    mode = int(st[S_MODE])
    period = 2.0 * math.pi / fp[2]
    h_max = MAX_STEP_PERIODS * period
    steps = 0
    events = 0
    _note(stats, s, w)
    while t < t_end:
        if steps >= max_steps or events >= max_steps:
            stats[ST_STATUS] = F_MAX_STEPS if steps >= max_steps else F_MAX_EVENTS
            break
        if mode == 0:
            events += 1
            tb, d = stick_end(fp, t, s, t_end)
            _fill_stick_samples(fp, t, s, tb, d == 0, ts, samples, stats)
            s_b = stick_s(fp, s, t, tb)
            stats[ST_STICK_TIME] += tb - t
            _note(stats, s_b, 0.0)
            if d != 0:
                stats[ST_BREAKS] += 1
                if track:
                    gp = _stick_rate(fp, tb)
                    a = d * (1.0 - f_plus(law, P, 0.0))
                    if gp != 0.0 and a != 0.0:
                        phi[2] += a / gp * phi[0]
                        phi[3] += a / gp * phi[1]
                w = 0.0
                mode = d
            t = tb
            s = s_b
            continue
        # ---- a slip phase in direction d from (t, s, w)
        d = mode
        y[0] = s
        y[1] = w
        if track:
            for i in range(4):
                y[2 + i] = phi[i]
        rhs(law, P, fp, d, t, y, n, K[0])
        h = min(h_max, max(1e-6, 0.01 * period))
        ended = False
        while not ended:
            if steps >= max_steps:
                stats[ST_STATUS] = F_MAX_STEPS
                break
            last = t + h >= t_end
            if last:
                h = t_end - t
            for j in range(1, N_STAGES):
                vec_stage(y, K, h, j, n, ytmp)
                rhs(law, P, fp, d, t + C[j] * h, ytmp, n, K[j])
            vec_advance(y, K, h, n, ynew)
            rhs(law, P, fp, d, t + h, ynew, n, K[N_STAGES])
            err = vec_error(y, ynew, K, h, 2, rtol, atol)
            steps += 1
            if not (math.isfinite(err) and math.isfinite(ynew[0]) and math.isfinite(ynew[1])):
                if h < 1e-14:
                    stats[ST_STATUS] = F_NONFINITE
                    ended = True
                    t = t_end
                    break
                h *= MIN_FACTOR
                continue
            if err > 1.0:
                h *= max(MIN_FACTOR, SAFETY * err ** (-1.0 / 8.0))
                continue
            stopped = d * ynew[1] <= 0.0 and d * y[1] >= 0.0
            extremum = (K[0, 0] > 0.0) != (K[N_STAGES, 0] > 0.0)
            samples_due = int(stats[ST_NEXT]) < ts.shape[0] and ts[int(stats[ST_NEXT])] <= t + h
            if stopped or extremum or samples_due:
                _extra_stages(law, P, fp, d, t, y, K, h, n, ytmp)
                vec_dense_coeffs(y, ynew, h, K, F, n)
            x_stop = 1.0
            if stopped:
                # the first zero of d w on the interpolant (Illinois)
                xa = 0.0
                ga = d * y[1]
                xb = 1.0
                gb = d * ynew[1]
                if ga == 0.0:  # the phase began at rest: its first zero after the start
                    xa = 1e-9
                    ga = d * dense_eval(F, y, xa, 1)
                    if ga <= 0.0:
                        xb = xa
                        gb = ga
                        xa = 0.0
                        ga = 0.0
                x_stop = xb
                if ga != 0.0 and gb != 0.0:
                    side = 0
                    for _ in range(200):
                        xc = illinois_propose(xa, ga, xb, gb)
                        gc = d * dense_eval(F, y, xc, 1)
                        xa, ga, xb, gb, side, done = illinois_update(xa, ga, xb, gb, side, xc, gc)
                        x_stop = xc
                        if done:
                            break
                elif ga == 0.0:
                    x_stop = xa
            if extremum:
                # the extremum of s inside the step (where s' = nu(tau) - w = 0)
                xa = 0.0
                ga = K[0, 0]
                xb = x_stop
                gb = dense_slope(F, xb, 0) if x_stop < 1.0 else K[N_STAGES, 0]
                if (ga > 0.0) != (gb > 0.0) and ga != 0.0 and gb != 0.0:
                    side = 0
                    xc = xb
                    for _ in range(200):
                        xc = illinois_propose(xa, ga, xb, gb)
                        gc = dense_slope(F, xc, 0)
                        xa, ga, xb, gb, side, done = illinois_update(xa, ga, xb, gb, side, xc, gc)
                        if done:
                            break
                    _note(stats, dense_eval(F, y, xc, 0), dense_eval(F, y, xc, 1))
            if stopped:
                t_stop = t + x_stop * h
                if samples_due:
                    _fill_slip_samples(t, h, F, y, t_stop, False, d, ts, samples, stats)
                s = dense_eval(F, y, x_stop, 0)
                if track:
                    for i in range(4):
                        phi[i] = dense_eval(F, y, x_stop, 2 + i)
                w = 0.0
                t = t_stop
                _note(stats, s, 0.0)
                events += 1
                g = s + external(fp, t)
                f0 = f_plus(law, P, 0.0)
                if abs(g) <= 1.0:
                    mode = 0
                    stats[ST_STOPS] += 1
                    if track:
                        phi[2] = 0.0
                        phi[3] = 0.0
                elif d * g < 0.0:
                    a_before = g - d * f0
                    a_after = g + d * f0
                    mode = -d
                    stats[ST_REVERSALS] += 1
                    if track and a_before != 0.0:
                        phi[2] *= a_after / a_before
                        phi[3] *= a_after / a_before
                else:
                    # the net force still pushes on: w touched 0 and the slip goes on
                    stats[ST_TOUCHES] += 1
                ended = True
                break
            if samples_due:
                _fill_slip_samples(t, h, F, y, t + h, last, d, ts, samples, stats)
            t = t_end if last else t + h
            for i in range(n):
                y[i] = ynew[i]
                K[0, i] = K[N_STAGES, i]
            _note(stats, y[0], y[1])
            if last:
                s = y[0]
                w = y[1]
                if track:
                    for i in range(4):
                        phi[i] = y[2 + i]
                ended = True
                break
            if err == 0.0:
                fac = MAX_FACTOR
            else:
                fac = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err ** (-1.0 / 8.0)))
            h = min(h * fac, h_max)
        if stats[ST_STATUS] != F_OK:
            break
    st[S_TAU] = t
    st[S_S] = s
    st[S_W] = w
    st[S_MODE] = mode
    stats[ST_STEPS] += steps
    return int(stats[ST_STATUS])


@njit(cache=True)
def new_work():  # type: ignore[no-untyped-def]
    """Return the scratch array of :func:`advance`."""
    return np.zeros((N_STAGES_EXTENDED + 10, NVAR_TRACK))


@njit(cache=True)
def reset_stats(stats):  # type: ignore[no-untyped-def]
    """Zero the counters of ``stats`` and open its extremes."""
    for i in range(NST):
        stats[i] = 0.0
    stats[ST_S_MIN] = math.inf
    stats[ST_S_MAX] = -math.inf
    stats[ST_W_MIN] = math.inf
    stats[ST_W_MAX] = -math.inf


#: a start this close to zero velocity where static friction holds the block is at rest: a
#: section that falls on a stop gives Newton's iterates velocities of 1e-11, whose instants of
#: slip would count as stops of their own
W_REST = 1e-9


@njit(cache=True)
def start_state(fp, t0, s0, w0, st):  # type: ignore[no-untyped-def]
    """Set ``st`` to ``(t0, s0, w0)``: stuck where ``w0 = 0`` (breaking away at once if ``|g| > 1``).

    A velocity within :data:`W_REST` of zero where ``|g| <= 1`` is a block at rest.
    """
    st[S_TAU] = t0
    st[S_S] = s0
    if abs(w0) <= W_REST and abs(s0 + external(fp, t0)) <= 1.0:
        w0 = 0.0
    st[S_W] = w0
    if w0 > 0.0:
        st[S_MODE] = 1.0
    elif w0 < 0.0:
        st[S_MODE] = -1.0
    else:
        st[S_MODE] = 0.0


# -------------------------------------------------------------------------- rows


@njit(cache=True)
def trajectory(law, lp, fp, t0, s0, w0, ts, rtol, atol, max_steps, samples, stats):  # type: ignore[no-untyped-def]
    """Sample the motion from ``(t0, s0, w0)`` at the times ``ts`` (ascending, >= t0); return the status."""
    work = new_work()
    st = np.empty(NSTATE)
    phi = np.zeros(4)
    start_state(fp, t0, s0, w0, st)
    reset_stats(stats)
    k = 0
    while k < ts.shape[0] and ts[k] <= t0:
        samples[k, 0] = s0
        samples[k, 1] = w0
        samples[k, 2] = st[S_MODE]
        k += 1
    stats[ST_NEXT] = k
    if ts.shape[0] == 0:
        return F_OK
    return advance(
        law, lp, fp, st, phi, ts[ts.shape[0] - 1], rtol, atol, False, ts, samples, stats, max_steps, work
    )


@njit(cache=True)
def poincare(law, lp, fp, t0, x, n_periods, rtol, atol, max_steps, out, phi, stats):  # type: ignore[no-untyped-def]
    """Apply the stroboscopic map ``n_periods`` times to ``x = (s, w)`` from phase ``t0``.

    ``out`` receives ``(s, w, mode)`` after the periods, ``phi`` (4) the Jacobian
    with the saltation matrices, ``stats`` the events; returns the status.
    """
    work = new_work()
    st = np.empty(NSTATE)
    ts = np.empty(0)
    samples = np.empty((0, 3))
    start_state(fp, t0, x[0], x[1], st)
    reset_stats(stats)
    phi[0] = 1.0
    phi[1] = 0.0
    phi[2] = 0.0
    phi[3] = 1.0
    if st[S_MODE] == 0.0:
        phi[2] = 0.0
        phi[3] = 0.0
    period = 2.0 * math.pi / fp[2]
    status = F_OK
    for k in range(n_periods):
        status = advance(
            law, lp, fp, st, phi, t0 + (k + 1) * period, rtol, atol, True, ts, samples, stats, max_steps, work
        )
        if status != F_OK:
            break
    out[0] = st[S_S]
    out[1] = st[S_W]
    out[2] = st[S_MODE]
    return status


@njit(cache=True)
def _qr2(m, q):  # type: ignore[no-untyped-def]
    """Gram-Schmidt of the 2 x 2 ``m`` (row-major) into ``q`` (row-major); return ``(r11, r22)``."""
    a0 = m[0]
    a1 = m[2]
    r11 = math.sqrt(a0 * a0 + a1 * a1)
    if r11 == 0.0:
        q[0] = 1.0
        q[2] = 0.0
    else:
        q[0] = a0 / r11
        q[2] = a1 / r11
    b0 = m[1]
    b1 = m[3]
    r12 = q[0] * b0 + q[2] * b1
    b0 -= r12 * q[0]
    b1 -= r12 * q[2]
    r22 = math.sqrt(b0 * b0 + b1 * b1)
    # the second column of Q: orthogonal to the first, with the sign that keeps r22 >= 0
    q[1] = -q[2]
    q[3] = q[0]
    if r22 > 0.0 and q[1] * b0 + q[3] * b1 < 0.0:
        q[1] = -q[1]
        q[3] = -q[3]
    return r11, r22


@njit(cache=True)
def strobe_one(  # type: ignore[no-untyped-def]
    law, lp, fp, t0, s0, w0, n_transient, n_record, rtol, atol, max_steps, track, out, lyap, stats,
    work, st, phi, qm, m, ts, samples,
):  # fmt: skip
    """Stroboscopic samples of one row: ``n_record`` sections after ``n_transient`` periods.

    ``out`` (``n_record`` x 2) receives ``(s, w)`` at each section, ``stats`` the
    events over the recorded periods and the status. With ``track``, ``lyap``
    receives the Lyapunov exponents over the recorded periods (per unit
    dimensionless time): the Jacobian of each period (with its saltation matrices)
    is applied to an orthonormal frame, re-orthonormalised by QR (Benettin,
    Galgani, Giorgilli and Strelcyn 1980); the second is ``-inf`` once a stick
    phase has collapsed the frame (stick forgets the velocity: the Jacobian has
    rank one). The rest are work arrays (the CPU's rows and a GPU thread pass their
    own): ``work`` of :func:`new_work`, ``st`` (``NSTATE``), ``phi``, ``qm``, ``m`` (4),
    and an empty ``ts`` and ``samples``.
    """
    period = 2.0 * math.pi / fp[2]
    start_state(fp, t0, s0, w0, st)
    reset_stats(stats)
    status = F_OK
    for k in range(n_transient):
        status = advance(
            law,
            lp,
            fp,
            st,
            phi,
            t0 + (k + 1) * period,
            rtol,
            atol,
            False,
            ts,
            samples,
            stats,
            max_steps,
            work,
        )
        if status != F_OK:
            break
    reset_stats(stats)
    qm[0] = 1.0
    qm[1] = 0.0
    qm[2] = 0.0
    qm[3] = 1.0
    sum1 = 0.0
    sum2 = 0.0
    for k in range(n_record):
        stops_before = stats[ST_STOPS]
        if status == F_OK:
            if track:
                phi[0] = 1.0
                phi[1] = 0.0
                phi[2] = 0.0
                phi[3] = 0.0 if st[S_MODE] == 0.0 else 1.0
            status = advance(
                law, lp, fp, st, phi, t0 + (n_transient + k + 1) * period, rtol, atol, track, ts, samples,
                stats, max_steps, work,
            )  # fmt: skip
        if status == F_OK:
            out[k, 0] = st[S_S]
            out[k, 1] = st[S_W]
            if track:
                m[0] = phi[0] * qm[0] + phi[1] * qm[2]
                m[1] = phi[0] * qm[1] + phi[1] * qm[3]
                m[2] = phi[2] * qm[0] + phi[3] * qm[2]
                m[3] = phi[2] * qm[1] + phi[3] * qm[3]
                r11, r22 = _qr2(m, qm)
                sum1 += math.log(r11) if r11 > 0.0 else -math.inf
                # a stick phase zeroes the velocity's row: the Jacobian has rank one exactly,
                # and its second diagonal entry is rounding (about 1e-16), not a rate
                stuck = stats[ST_STOPS] > stops_before or st[S_MODE] == 0.0
                sum2 += math.log(r22) if r22 > 0.0 and not stuck else -math.inf
        else:
            out[k, 0] = math.nan
            out[k, 1] = math.nan
    total = n_record * period
    if track and status == F_OK and n_record > 0:
        lyap[0] = sum1 / total
        lyap[1] = sum2 / total
    else:
        lyap[0] = math.nan
        lyap[1] = math.nan
    stats[ST_STATUS] = status


@njit(cache=True, nogil=True)
def strobe_rows(law, lp, fp, t0, x0, n_transient, n_record, rtol, atol, max_steps, track, out, lyap, stats):  # type: ignore[no-untyped-def]
    """Run :func:`strobe_one` for every row (``lp[i]``, ``fp[i]``, start ``x0[i]``; results ``out[i]``, ...).

    It releases the GIL: :func:`stickslip.core.forced_api.forced_strobe` runs blocks
    of rows in a pool of threads.
    """
    work = new_work()
    st = np.empty(NSTATE)
    phi = np.zeros(4)
    qm = np.zeros(4)
    m = np.zeros(4)
    ts = np.empty(0)
    samples = np.empty((0, 3))
    for i in range(fp.shape[0]):
        strobe_one(
            law, lp[i], fp[i], t0, x0[i, 0], x0[i, 1], n_transient, n_record, rtol, atol, max_steps, track,
            out[i], lyap[i], stats[i], work, st, phi, qm, m, ts, samples,
        )  # fmt: skip
