"""Radau IIA of order 5 for the inertial rate-and-state slider, compiled (numbers only).

The algorithm of SciPy's ``solve_ivp(method="Radau")`` (Hairer and Wanner, *Solving
Ordinary Differential Equations II*, Sec. IV.8), step for step: the simplified Newton
iteration on the collocation system in the eigenbasis of the Radau matrix (one real
and one complex linear system per iteration, the complex one solved as a real one of
twice the size, their LU factors kept while the step
size and the Jacobian stay), the embedded third-order error estimate (filtered
through the real system, and once more after a rejection), Gustafsson's predictive
step-size controller, the Jacobian recomputed only when Newton converges slowly, the
cubic collocation polynomial as dense output, SciPy's first-step guess, and
events found as ``solve_ivp`` finds them: a sign change of the event function
between two accepted steps, the root located on the dense output (here by the
Illinois method instead of Brent's, to the same bracket of a few ulps).

So the same steps as SciPy take, without a Python call per evaluation: the
inertial slider of ``simulate_rate_state`` took 160 000 right-hand sides and
18 000 steps through Python for the appendix; the kernel takes them in
milliseconds. The state of the integrator between two calls is kept in the
caller's arrays (:class:`Workspace`), so a run cut into calls (a
bound on the steps per call, an events buffer that filled up) takes exactly the
steps of an uninterrupted one.

The vector field is the inertial slider of :mod:`stickslip.core.ratestate`,
``y = (mu_s, v, theta_1..n)`` at a constant load-point velocity ``v_lp``; its two
event functions are the spring-force maximum (``v - v_lp`` crossing zero upward) and
the slip-velocity maximum (``mu_s - f(v, theta) - eta v`` crossing zero downward).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from .dop853 import illinois_propose, illinois_update
from .ratestate import P_ETA, in_friction, in_jac, in_rhs

S6 = 6**0.5
C = np.array([(4 - S6) / 10, (4 + S6) / 10, 1.0])
E = np.array([-13 - 7 * S6, -13 + 7 * S6, -1.0]) / 3
MU_REAL = 3 + 3 ** (2 / 3) - 3 ** (1 / 3)
MU_COMPLEX = 3 + 0.5 * (3 ** (1 / 3) - 3 ** (2 / 3)) - 0.5j * (3 ** (5 / 6) + 3 ** (7 / 6))
T = np.array(
    [
        [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
        [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
        [1.0, 1.0, 0.0],
    ]
)
TI = np.array(
    [
        [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
        [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
        [0.50287263494578682, -2.57192694985560522, 0.59603920482822492],
    ]
)
TI_REAL = TI[0].copy()
MU_COMPLEX_RE = MU_COMPLEX.real
MU_COMPLEX_IM = MU_COMPLEX.imag
PI = np.array(
    [
        [13 / 3 + 7 * S6 / 3, -23 / 3 - 22 * S6 / 3, 10 / 3 + 5 * S6],
        [13 / 3 - 7 * S6 / 3, -23 / 3 + 22 * S6 / 3, 10 / 3 - 5 * S6],
        [1 / 3, -8 / 3, 10 / 3],
    ]
)
NEWTON_MAXITER = 6
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
EPS = float(np.finfo(float).eps)

# outcomes
RD_DONE = 0  # reached t_end
RD_MAX_STEPS = 1  # this call's bound on steps reached (call again to go on)
RD_EVENTS_FULL = 2  # the events buffer is full (empty it and call again)
RD_STEP_TOO_SMALL = 3

# event kinds (columns of the events buffer: kind, t, y...)
EV_SPRING_PEAK = 0
EV_VELOCITY_PEAK = 1
N_EVENTS = 2  # the spring-force peak is an upward crossing, the velocity peak a downward one

# the scalar part of the workspace (``st``)
ST_T, ST_H, ST_H_OLD, ST_ERR_OLD, ST_T_OLD = 0, 1, 2, 3, 4
ST_STARTED, ST_CURRENT_JAC, ST_HAVE_LU, ST_HAVE_SOL = 5, 6, 7, 8
ST_NFEV, ST_NJEV, ST_NLU, ST_STEPS, ST_REJECTED = 9, 10, 11, 12, 13
N_ST = 16


class Workspace(NamedTuple):
    """Arrays that carry the integrator from one call of :func:`integrate_in` to the next.

    In the order of :func:`integrate_in`'s last arguments: call it with ``*workspace``.
    """

    st: np.ndarray
    f: np.ndarray
    y_old: np.ndarray
    jac: np.ndarray
    lu_real: np.ndarray
    piv_real: np.ndarray
    lu_complex: np.ndarray
    piv_complex: np.ndarray
    q: np.ndarray
    g: np.ndarray


def workspace(nv: int, t0: float = 0.0) -> Workspace:
    """Return a fresh workspace for ``nv`` variables, starting at time ``t0``."""
    ws = Workspace(
        st=np.zeros(N_ST),
        f=np.zeros(nv),
        y_old=np.zeros(nv),
        jac=np.zeros((nv, nv)),
        lu_real=np.zeros((nv, nv)),
        piv_real=np.zeros(nv, dtype=np.int64),
        lu_complex=np.zeros((2 * nv, 2 * nv)),
        piv_complex=np.zeros(2 * nv, dtype=np.int64),
        q=np.zeros((nv, 3)),
        g=np.zeros(N_EVENTS),
    )
    ws.st[ST_T] = t0
    return ws


@njit(cache=True, error_model="numpy")
def lu_factor(a, piv):  # type: ignore[no-untyped-def]
    """LU factors of ``a`` in place, with partial pivoting."""
    n = a.shape[0]
    for k in range(n):
        p = k
        best = abs(a[k, k])
        for i in range(k + 1, n):
            m = abs(a[i, k])
            if m > best:
                best = m
                p = i
        piv[k] = p
        if p != k:
            for j in range(n):
                tmp = a[k, j]
                a[k, j] = a[p, j]
                a[p, j] = tmp
        d = a[k, k]
        for i in range(k + 1, n):
            a[i, k] = a[i, k] / d
            lik = a[i, k]
            for j in range(k + 1, n):
                a[i, j] -= lik * a[k, j]


@njit(cache=True, error_model="numpy")
def lu_solve(a, piv, b):  # type: ignore[no-untyped-def]
    """Solve ``A x = b`` in place in ``b`` from the factors of :func:`lu_factor`."""
    n = a.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= a[i, j] * b[j]
        b[i] = acc
    for i in range(n - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, n):
            acc -= a[i, j] * b[j]
        b[i] = acc / a[i, i]


@njit(cache=True, error_model="numpy")
def _rms(x, scale, n):  # type: ignore[no-untyped-def]
    acc = 0.0
    for i in range(n):
        r = x[i] / scale[i]
        acc += r * r
    return math.sqrt(acc / n)


@njit(cache=True, error_model="numpy")
def _ulp(t):  # type: ignore[no-untyped-def]
    """``nextafter(t, inf) - t`` for ``t >= 0``."""
    if t == 0.0:
        return 5e-324
    _, e = math.frexp(t)
    return math.ldexp(1.0, e - 53)


@njit(cache=True, error_model="numpy")
def _events(P, S, n, v_lp, y, g):  # type: ignore[no-untyped-def]
    g[EV_SPRING_PEAK] = y[1] - v_lp
    g[EV_VELOCITY_PEAK] = y[0] - in_friction(y[1], y, S, n, P) - P[P_ETA] * y[1]


@njit(cache=True, error_model="numpy")
def _dense(q, y_old, t_old, h, t, nv, out):  # type: ignore[no-untyped-def]
    x = (t - t_old) / h
    x2 = x * x
    x3 = x2 * x
    for j in range(nv):
        out[j] = y_old[j] + (q[j, 0] * x + q[j, 1] * x2 + q[j, 2] * x3)


@njit(cache=True, error_model="numpy")
def _predict_factor(h_abs, h_abs_old, error_norm, error_norm_old):  # type: ignore[no-untyped-def]
    if error_norm_old < 0.0 or h_abs_old < 0.0 or error_norm == 0.0:
        multiplier = 1.0
    else:
        multiplier = h_abs / h_abs_old * (error_norm_old / error_norm) ** 0.25
    if error_norm == 0.0:
        return math.inf
    return min(1.0, multiplier) * error_norm**-0.25


@njit(cache=True, error_model="numpy")
def _collocation(P, S, n, v_lp, t, y, h, z, scale, tol, lu_r, piv_r, lu_c, piv_c, w, f3, dw, yt, fr, fc, nv):  # type: ignore[no-untyped-def]
    """Simplified Newton on the collocation system; ``z`` holds the guess, then the solution.

    Returns ``(converged, iterations, rate, evaluations)`` (``rate`` < 0: not measured).
    """
    m_real = MU_REAL / h
    mc_re = MU_COMPLEX_RE / h
    mc_im = MU_COMPLEX_IM / h
    for i in range(3):
        for j in range(nv):
            w[i, j] = TI[i, 0] * z[0, j] + TI[i, 1] * z[1, j] + TI[i, 2] * z[2, j]
    dw_norm_old = -1.0
    rate = -1.0
    converged = False
    nfev = 0
    k = 0
    for k in range(NEWTON_MAXITER):
        finite = True
        for i in range(3):
            for j in range(nv):
                yt[j] = y[j] + z[i, j]
            in_rhs(yt, P, S, n, v_lp, f3[i])
            nfev += 1
            for j in range(nv):
                if not math.isfinite(f3[i, j]):
                    finite = False
        if not finite:
            break
        for j in range(nv):
            fr[j] = f3[0, j] * TI_REAL[0] + f3[1, j] * TI_REAL[1] + f3[2, j] * TI_REAL[2] - m_real * w[0, j]
            fc[j] = (
                f3[0, j] * TI[1, 0]
                + f3[1, j] * TI[1, 1]
                + f3[2, j] * TI[1, 2]
                - (mc_re * w[1, j] - mc_im * w[2, j])
            )
            fc[nv + j] = (
                f3[0, j] * TI[2, 0]
                + f3[1, j] * TI[2, 1]
                + f3[2, j] * TI[2, 2]
                - (mc_re * w[2, j] + mc_im * w[1, j])
            )
        lu_solve(lu_r, piv_r, fr)
        lu_solve(lu_c, piv_c, fc)
        acc = 0.0
        for j in range(nv):
            dw[0, j] = fr[j]
            dw[1, j] = fc[j]
            dw[2, j] = fc[nv + j]
            for i in range(3):
                r = dw[i, j] / scale[j]
                acc += r * r
        dw_norm = math.sqrt(acc / (3 * nv))
        if dw_norm_old >= 0.0:
            rate = dw_norm / dw_norm_old
        if rate >= 0.0 and (rate >= 1.0 or rate ** (NEWTON_MAXITER - k) / (1.0 - rate) * dw_norm > tol):
            break
        for i in range(3):
            for j in range(nv):
                w[i, j] += dw[i, j]
        for i in range(3):
            for j in range(nv):
                z[i, j] = T[i, 0] * w[0, j] + T[i, 1] * w[1, j] + T[i, 2] * w[2, j]
        if dw_norm == 0.0 or (rate >= 0.0 and rate / (1.0 - rate) * dw_norm < tol):
            converged = True
            break
        dw_norm_old = dw_norm
    return converged, k + 1, rate, nfev


@njit(cache=True, error_model="numpy")
def _first_step(P, S, n, v_lp, t0, y0, f0, t_bound, rtol, atol, nv, y1, f1):  # type: ignore[no-untyped-def]
    """SciPy's ``select_initial_step`` for an error of order 3 (Hairer, Norsett and Wanner, II.4)."""
    interval = abs(t_bound - t0)
    if interval == 0.0:
        return 0.0
    d0 = 0.0
    d1 = 0.0
    for j in range(nv):
        sc = atol[j] + abs(y0[j]) * rtol
        d0 += (y0[j] / sc) ** 2
        d1 += (f0[j] / sc) ** 2
    d0 = math.sqrt(d0 / nv)
    d1 = math.sqrt(d1 / nv)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for j in range(nv):
        y1[j] = y0[j] + h0 * f0[j]
    in_rhs(y1, P, S, n, v_lp, f1)
    d2 = 0.0
    for j in range(nv):
        sc = atol[j] + abs(y0[j]) * rtol
        d2 += ((f1[j] - f0[j]) / sc) ** 2
    d2 = math.sqrt(d2 / nv) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** 0.25
    return min(100.0 * h0, h1, interval)


@njit(cache=True, error_model="numpy")
def _locate(P, S, n, v_lp, kind, q, y_old, t_old, h, ta, ga, tb, gb, nv, yt, g):  # type: ignore[no-untyped-def]
    """Root of event ``kind`` in ``[ta, tb]`` on the dense output (Illinois)."""
    if ga == 0.0:
        return ta
    if gb == 0.0:
        return tb
    side = 0
    tc = tb
    for _ in range(200):
        tc = illinois_propose(ta, ga, tb, gb)
        _dense(q, y_old, t_old, h, tc, nv, yt)
        _events(P, S, n, v_lp, yt, g)
        ta, ga, tb, gb, side, done = illinois_update(ta, ga, tb, gb, side, tc, g[kind])
        if done:
            break
    return tc


@njit(cache=True, error_model="numpy")
def integrate_in(  # type: ignore[no-untyped-def]
    P, S, n, v_lp, y, t_end, rtol, atol, t_eval, out, ev, max_steps,
    st, f, y_old, jac, lu_r, piv_r, lu_c, piv_c, q, g,
):  # fmt: skip
    """Integrate the inertial slider from ``st[ST_T]`` to ``t_end`` at load-point velocity ``v_lp``.

    ``y`` (``(mu_s, v, theta_1..n)``) is advanced in place; ``st`` ... ``g`` are the
    workspace of :func:`workspace` (zeros before the first call of a run).
    ``atol`` is a vector; ``t_eval`` the output times not yet written, ascending,
    their states written to the rows of ``out``; ``ev`` receives the events
    (kind, t, y). Returns ``(status, samples written, events written)``.
    """
    nv = y.size
    z = np.zeros((3, nv))
    w = np.empty((3, nv))
    f3 = np.empty((3, nv))
    dw = np.empty((3, nv))
    yt = np.empty(nv)
    y_new = np.empty(nv)
    f_new = np.empty(nv)
    fr = np.empty(nv)
    fc = np.empty(2 * nv)
    err = np.empty(nv)
    ze = np.empty(nv)
    scale = np.empty(nv)
    g_new = np.empty(N_EVENTS)
    g_tmp = np.empty(N_EVENTS)
    newton_tol = max(10.0 * EPS / rtol, min(0.03, rtol**0.5))
    nsamp = 0
    nev = 0
    t = st[ST_T]
    if st[ST_STARTED] == 0.0:
        in_rhs(y, P, S, n, v_lp, f)
        st[ST_H] = _first_step(P, S, n, v_lp, t, y, f, t_end, rtol, atol, nv, yt, f_new)
        st[ST_NFEV] = 2.0
        st[ST_H_OLD] = -1.0
        st[ST_ERR_OLD] = -1.0
        in_jac(y, P, S, n, jac)
        st[ST_NJEV] = 1.0
        st[ST_CURRENT_JAC] = 1.0
        st[ST_HAVE_LU] = 0.0
        st[ST_HAVE_SOL] = 0.0
        _events(P, S, n, v_lp, y, g)
        st[ST_STARTED] = 1.0
        # output times at the start (solve_ivp writes them from the first step's dense output,
        # which is y itself there)
        while nsamp < t_eval.size and t_eval[nsamp] <= t:
            for j in range(nv):
                out[nsamp, j] = y[j]
            nsamp += 1
    steps = 0
    while t < t_end:
        if steps >= max_steps:
            st[ST_T] = t
            return RD_MAX_STEPS, nsamp, nev
        if nev + N_EVENTS > ev.shape[0]:
            st[ST_T] = t
            return RD_EVENTS_FULL, nsamp, nev
        min_step = 10.0 * _ulp(t)
        h_abs = st[ST_H]
        if h_abs < min_step:
            h_abs = min_step
            h_abs_old = -1.0
            err_old = -1.0
        else:
            h_abs_old = st[ST_H_OLD]
            err_old = st[ST_ERR_OLD]
        current_jac = st[ST_CURRENT_JAC] != 0.0
        have_lu = st[ST_HAVE_LU] != 0.0
        rejected = False
        accepted = False
        t_new = t
        h = h_abs
        n_iter = 0
        rate = -1.0
        error_norm = 0.0
        safety = 0.9
        while not accepted:
            if h_abs < min_step:
                st[ST_T] = t
                return RD_STEP_TOO_SMALL, nsamp, nev
            h = h_abs
            t_new = t + h
            if t_new > t_end:
                t_new = t_end
            h = t_new - t
            h_abs = abs(h)
            if st[ST_HAVE_SOL] == 0.0:
                for i in range(3):
                    for j in range(nv):
                        z[i, j] = 0.0
            else:
                hs = t - st[ST_T_OLD]
                for i in range(3):
                    _dense(q, y_old, st[ST_T_OLD], hs, t + h * C[i], nv, yt)
                    for j in range(nv):
                        z[i, j] = yt[j] - y[j]
            for j in range(nv):
                scale[j] = atol[j] + abs(y[j]) * rtol
            converged = False
            while not converged:
                if not have_lu:
                    # the complex system (mu_c / h - J) as a real one of twice the size:
                    # [[a - J, -b], [b, a - J]] for mu_c / h = a + i b
                    for i in range(2 * nv):
                        for j in range(2 * nv):
                            lu_c[i, j] = 0.0
                    for i in range(nv):
                        for j in range(nv):
                            lu_r[i, j] = -jac[i, j]
                            lu_c[i, j] = -jac[i, j]
                            lu_c[nv + i, nv + j] = -jac[i, j]
                        lu_r[i, i] += MU_REAL / h
                        lu_c[i, i] += MU_COMPLEX_RE / h
                        lu_c[nv + i, nv + i] += MU_COMPLEX_RE / h
                        lu_c[i, nv + i] = -MU_COMPLEX_IM / h
                        lu_c[nv + i, i] = MU_COMPLEX_IM / h
                    lu_factor(lu_r, piv_r)
                    lu_factor(lu_c, piv_c)
                    st[ST_NLU] += 2.0
                    have_lu = True
                converged, n_iter, rate, nf = _collocation(
                    P, S, n, v_lp, t, y, h, z, scale, newton_tol, lu_r, piv_r, lu_c, piv_c,
                    w, f3, dw, yt, fr, fc, nv,
                )  # fmt: skip
                st[ST_NFEV] += nf
                if not converged:
                    if current_jac:
                        break
                    in_jac(y, P, S, n, jac)
                    st[ST_NJEV] += 1.0
                    current_jac = True
                    have_lu = False
            if not converged:
                h_abs *= 0.5
                have_lu = False
                continue
            for j in range(nv):
                y_new[j] = y[j] + z[2, j]
                ze[j] = (z[0, j] * E[0] + z[1, j] * E[1] + z[2, j] * E[2]) / h
                err[j] = f[j] + ze[j]
            lu_solve(lu_r, piv_r, err)
            for j in range(nv):
                scale[j] = atol[j] + max(abs(y[j]), abs(y_new[j])) * rtol
            error_norm = _rms(err, scale, nv)
            safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
            if rejected and error_norm > 1.0:
                for j in range(nv):
                    yt[j] = y[j] + err[j]
                in_rhs(yt, P, S, n, v_lp, err)
                st[ST_NFEV] += 1.0
                for j in range(nv):
                    err[j] += ze[j]
                lu_solve(lu_r, piv_r, err)
                error_norm = _rms(err, scale, nv)
            if error_norm > 1.0:
                factor = _predict_factor(h_abs, h_abs_old, error_norm, err_old)
                h_abs *= max(MIN_FACTOR, safety * factor)
                have_lu = False
                rejected = True
                st[ST_REJECTED] += 1.0
            else:
                accepted = True
        recompute_jac = n_iter > 2 and rate > 1e-3
        factor = _predict_factor(h_abs, h_abs_old, error_norm, err_old)
        factor = min(MAX_FACTOR, safety * factor)
        if not recompute_jac and factor < 1.2:
            factor = 1.0
        else:
            have_lu = False
        in_rhs(y_new, P, S, n, v_lp, f_new)
        st[ST_NFEV] += 1.0
        if recompute_jac:
            in_jac(y_new, P, S, n, jac)
            st[ST_NJEV] += 1.0
            current_jac = True
        else:
            current_jac = False
        st[ST_H_OLD] = st[ST_H]
        st[ST_ERR_OLD] = error_norm
        st[ST_H] = h_abs * factor
        st[ST_CURRENT_JAC] = 1.0 if current_jac else 0.0
        st[ST_HAVE_LU] = 1.0 if have_lu else 0.0
        # the dense output of this step: y_old + Q (x, x^2, x^3), x = (t - t_old) / h
        for j in range(nv):
            y_old[j] = y[j]
            for k in range(3):
                q[j, k] = z[0, j] * PI[0, k] + z[1, j] * PI[1, k] + z[2, j] * PI[2, k]
            y[j] = y_new[j]
            f[j] = f_new[j]
        t_old = t
        t = t_new
        st[ST_T_OLD] = t_old
        st[ST_HAVE_SOL] = 1.0
        st[ST_STEPS] += 1.0
        steps += 1
        # events, as solve_ivp: a sign change between the ends of the step, in the direction
        _events(P, S, n, v_lp, y, g_new)
        for kind in range(N_EVENTS):
            ga = g[kind]
            gb = g_new[kind]
            up = ga <= 0.0 and gb >= 0.0
            down = ga >= 0.0 and gb <= 0.0
            if (up and kind == EV_SPRING_PEAK) or (down and kind == EV_VELOCITY_PEAK):
                te = _locate(P, S, n, v_lp, kind, q, y_old, t_old, h, t_old, ga, t, gb, nv, yt, g_tmp)
                _dense(q, y_old, t_old, h, te, nv, yt)
                ev[nev, 0] = kind
                ev[nev, 1] = te
                for j in range(nv):
                    ev[nev, 2 + j] = yt[j]
                nev += 1
        for kind in range(N_EVENTS):
            g[kind] = g_new[kind]
        while nsamp < t_eval.size and t_eval[nsamp] <= t:
            _dense(q, y_old, t_old, h, t_eval[nsamp], nv, out[nsamp])
            nsamp += 1
    st[ST_T] = t
    return RD_DONE, nsamp, nev
