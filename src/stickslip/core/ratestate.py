"""Rate-and-state spring-slider: compiled vector fields, Jacobians and integrator (numbers only).

Friction with any number ``n`` of state variables (SI units, friction per normal
load or normal stress):

    f = mu0 + A ln(v/V_r) + sum_i B_i theta_i                         (form LOG)
    f = A asinh(v/(2 V_r) exp((mu0 + sum_i B_i theta_i)/A))            (form REGULARIZED)

with the log-states ``theta_i = ln(Phi_i V_r / L_i)``, where ``Phi_i`` is the state
(a time), ``L_i = D_c,i`` for the aging, slip and Nagata laws and ``L_i = 2 D_c,i``
for the Perrin-Rice-Zheng law, so that steady sliding at ``v`` is always
``theta_i = ln(V_r / v)`` and the log-state stays finite over any number of decades.
Evolution laws (``Phi`` forms in the docstring of :func:`state_rate`): aging
(Dieterich), slip (Ruina), Perrin-Rice-Zheng, Nagata.

Quasi-static or quasi-dynamic slider (``mu_s`` is the spring's stress per normal
stress, ``kw = k/W`` in 1/m, ``eta`` the radiation damping per normal stress in s/m):

    mu_s = f(v, theta) + eta v              (solved for v; closed form for LOG and eta = 0)
    mu_s' = kw (v_lp - v)

Inertial slider (``wm = W/m`` in m/s^2; always the regularized form, defined at v <= 0):

    v' = wm (mu_s - f(v, theta) - eta v),   mu_s' = kw (v_lp - v)

Parameter vector ``P = (A, V_r, mu0, kw, wm, eta, form)``; state table ``S`` (n x m):
``(B_i, D_c,i, law_i, c_i, length, program...)`` with ``c_i`` Nagata's coefficient and,
for a user's law, its ``Phi'`` as a postfix program of ``length`` (opcode, value) pairs.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._dop853_tableau import N_STAGES, N_STAGES_EXTENDED
from .dop853 import (
    dense_eval,
    illinois_propose,
    illinois_update,
    vec_advance,
    vec_dense_coeffs,
    vec_error,
    vec_stage,
)
from .engine import MAX_FACTOR, MIN_FACTOR, SAFETY, _root8

AGING = 0
SLIP = 1
PRZ = 2
NAGATA = 3
USER = 4  # Phi' from a program in the state table's row (see rpn_eval)

# opcodes of a user law's program (postfix: operands first)
OP_CONST, OP_V, OP_PHI, OP_DC, OP_VR, OP_MU_RATE = 0, 1, 2, 3, 4, 5
OP_ADD, OP_SUB, OP_MUL, OP_DIV, OP_POW = 10, 11, 12, 13, 14
OP_NEG, OP_EXP, OP_LOG, OP_SQRT, OP_ABS = 20, 21, 22, 23, 24
OP_TANH, OP_SINH, OP_COSH, OP_ASINH = 25, 26, 27, 28
PROGRAM_START = 5  # row[4] is the program's length, then (opcode, value) pairs

LOG = 0
REGULARIZED = 1

P_A, P_VR, P_MU0, P_KW, P_WM, P_ETA, P_FORM = range(7)
N_QUAD = 4  # slip, friction work, radiated energy, load work (per normal stress)

# integrator outcomes
RS_OK = 0
RS_RUNAWAY = 1
RS_MAX_STEPS = 2
RS_STEP_TOO_SMALL = 3
RS_NONFINITE = 4
RS_EVENTS_FULL = 5

# event kinds
EV_SPRING_PEAK = 0
EV_UP = 1
EV_DOWN = 2
EV_VELOCITY_PEAK = 3
EV_RUNAWAY = 4

# the rows integrate_qs writes; ``y`` is its state of ``nvar`` values, ``(mu_s, theta_1..n)``
# then the N_QUAD quadratures (read by name through stickslip.core.results)
EVC_KIND, EVC_T, EVC_U, EVC_Y = 0, 1, 2, 3  # events: (kind, t, u, y...)
RECC_T, RECC_U, RECC_Y = 0, 1, 2  # records of accepted steps: (t, u, y...)
# samples: (y..., u), u in the column after y


@njit(cache=True)
def psi(y, S, off, n):  # type: ignore[no-untyped-def]
    """Return ``sum_i B_i theta_i`` over the log-states ``y[off:off + n]``."""
    acc = 0.0
    for i in range(n):
        acc += S[i, 0] * y[off + i]
    return acc


@njit(cache=True)
def _reg(w):  # type: ignore[no-untyped-def]
    """Return ``(asinh(exp(w)/2), d/dw)`` without overflow."""
    if w > 40.0:
        return w, 1.0
    if w < -300.0:
        return 0.5 * math.exp(w), 0.5 * math.exp(w)
    e = math.exp(w)
    return math.asinh(0.5 * e), 0.5 * e / math.sqrt(1.0 + 0.25 * e * e)


@njit(cache=True)
def qs_lnv(mu_s, ps, P):  # type: ignore[no-untyped-def]
    """Return ``(u, r, D)``: ``u = ln(v/V_r)`` solving ``mu_s = f + eta v``, ``r = f_psi``, ``D = dmu_s/du``.

    ``ps`` is ``mu0 + sum_i B_i theta_i``. Closed form for the log form without
    damping; otherwise a safeguarded Newton iteration in ``u`` (``mu_s`` is
    increasing in ``u``). ``u`` is NaN where no positive velocity solves it.
    """
    a = P[P_A]
    vr = P[P_VR]
    eta = P[P_ETA]
    reg = P[P_FORM] == REGULARIZED
    if not reg and eta == 0.0:
        return (mu_s - ps) / a, 1.0, a
    if reg and mu_s <= 0.0:
        return math.nan, 1.0, a
    u = (mu_s - ps) / a
    if eta > 0.0 and mu_s > 0.0:
        u = min(u, math.log(mu_s / (eta * vr)))  # a bound for the regularized form, a guess for LOG
    lo = -math.inf
    hi = math.inf
    r = 1.0
    d = a
    for _ in range(200):
        ev = math.exp(u)
        if reg:
            g, r = _reg(u + ps / a)
            f = a * g
            df = a * r
        else:
            f = ps + a * u
            r = 1.0
            df = a
        fv = f + eta * vr * ev - mu_s
        d = df + eta * vr * ev
        if fv == 0.0:
            break
        if fv > 0.0:
            hi = u
        else:
            lo = u
        step = fv / d
        un = u - step
        # converged: the step is at u's rounding, or the residual at the sum's rounding. Taken
        # before the bracket's guard, which would move an update equal to a bracket's end by 1
        if abs(step) <= 1e-15 * max(1.0, abs(u)) or abs(fv) <= 1e-15 * (abs(mu_s) + abs(f) + eta * vr * ev):
            u = un
            break
        if not (lo < un < hi):
            if math.isinf(lo):
                un = max(un, u - 50.0)
                if not un < hi:
                    un = hi - 1.0
            elif math.isinf(hi):
                un = min(un, u + 50.0)
                if not un > lo:
                    un = lo + 1.0
            else:
                un = 0.5 * (lo + hi)
                if not lo < un < hi:  # the bracket is two neighbouring doubles
                    break
        u = un
    return u, r, d


@njit(cache=True, error_model="numpy")
def rpn_eval(row, v, phi, dc, vr, dmu):  # type: ignore[no-untyped-def]
    """Evaluate the postfix program stored in ``row`` (a user's ``Phi'``)."""
    m = int(row[4])
    stack = np.empty(max(m, 1))
    sp_ = 0
    for k in range(m):
        op = int(row[PROGRAM_START + 2 * k])
        if op < OP_ADD:
            if op == OP_CONST:
                x = row[PROGRAM_START + 2 * k + 1]
            elif op == OP_V:
                x = v
            elif op == OP_PHI:
                x = phi
            elif op == OP_DC:
                x = dc
            elif op == OP_VR:
                x = vr
            else:
                x = dmu
            stack[sp_] = x
            sp_ += 1
        elif op < OP_NEG:
            b = stack[sp_ - 1]
            a = stack[sp_ - 2]
            sp_ -= 1
            if op == OP_ADD:
                r = a + b
            elif op == OP_SUB:
                r = a - b
            elif op == OP_MUL:
                r = a * b
            elif op == OP_DIV:
                r = a / b
            else:
                r = a**b
            stack[sp_ - 1] = r
        else:
            a = stack[sp_ - 1]
            if op == OP_NEG:
                r = -a
            elif op == OP_EXP:
                r = math.exp(a)
            elif op == OP_LOG:
                r = math.log(a) if a > 0.0 else math.nan
            elif op == OP_SQRT:
                r = math.sqrt(a) if a >= 0.0 else math.nan
            elif op == OP_ABS:
                r = abs(a)
            elif op == OP_TANH:
                r = math.tanh(a)
            elif op == OP_SINH:
                r = math.sinh(a)
            elif op == OP_COSH:
                r = math.cosh(a)
            else:
                r = math.asinh(a)
            stack[sp_ - 1] = r
    return stack[0]


@njit(cache=True, error_model="numpy")
def state_rate(law, b, dc, c, th, u, v, vr, dmu, row):  # type: ignore[no-untyped-def]
    """Rate of the log-state ``theta`` (1/s) at ``u = ln(v/V_r)``.

    In terms of ``Phi`` (``L = D_c``, PRZ ``L = 2 D_c``):
    aging ``Phi' = 1 - v Phi/D_c``; slip ``Phi' = -(v Phi/D_c) ln(v Phi/D_c)``;
    PRZ ``Phi' = 1 - (v Phi/(2 D_c))^2``; Nagata ``Phi' = 1 - v Phi/D_c - (c/B) Phi mu'``
    with ``mu'`` the rate of the spring's stress per normal stress; a user's law
    ``Phi' = program(v, Phi, D_c, V_r, mu')`` from ``row``.
    """
    if law == SLIP:
        return -(v / dc) * (u + th)
    if law == PRZ:
        return (vr / (2.0 * dc)) * math.exp(-th) - (v * v / (2.0 * dc * vr)) * math.exp(th)
    if law == USER:
        phi = dc * math.exp(th) / vr
        return rpn_eval(row, v, phi, dc, vr, dmu) / phi
    r = (vr / dc) * math.exp(-th) - v / dc
    if law == NAGATA:
        r -= (c / b) * dmu
    return r


@njit(cache=True)
def _state_partials(law, b, dc, c, th, u, v, vr, kw, row):  # type: ignore[no-untyped-def]
    """Return ``(d rate/du, d rate/dtheta)`` of :func:`state_rate` (``mu' = kw (v_lp - v)``).

    A user's law by central differences (its dependence on ``mu'`` left out).
    """
    if law == SLIP:
        return -(v / dc) * (u + th + 1.0), -v / dc
    if law == PRZ:
        e = math.exp(th)
        return -(v * v / (dc * vr)) * e, -(vr / (2.0 * dc)) / e - (v * v / (2.0 * dc * vr)) * e
    if law == USER:
        hh = 1e-6
        ep = math.exp(hh)
        gu = (
            state_rate(law, b, dc, c, th, u + hh, v * ep, vr, 0.0, row)
            - state_rate(law, b, dc, c, th, u - hh, v / ep, vr, 0.0, row)
        ) / (2.0 * hh)
        gt = (
            state_rate(law, b, dc, c, th + hh, u, v, vr, 0.0, row)
            - state_rate(law, b, dc, c, th - hh, u, v, vr, 0.0, row)
        ) / (2.0 * hh)
        return gu, gt
    gu = -v / dc
    if law == NAGATA:
        gu += (c / b) * kw * v
    return gu, -(vr / dc) * math.exp(-th)


@njit(cache=True)
def qs_rhs(y, P, S, n, v_lp, out):  # type: ignore[no-untyped-def]
    """Quasi-static right-hand side of ``y = (mu_s, theta_1..n[, quadratures])``; returns ``u``.

    With ``out`` longer than ``1 + n`` also the rates of the slip, the friction
    work ``int f v dt``, the radiated energy ``int eta v^2 dt`` and the load
    work ``int mu_s v_lp dt`` (per normal stress).
    """
    vr = P[P_VR]
    kw = P[P_KW]
    mu_s = y[0]
    u, _, _ = qs_lnv(mu_s, P[P_MU0] + psi(y, S, 1, n), P)
    v = vr * math.exp(u)
    dmu = kw * (v_lp - v)
    out[0] = dmu
    for i in range(n):
        out[1 + i] = state_rate(int(S[i, 2]), S[i, 0], S[i, 1], S[i, 3], y[1 + i], u, v, vr, dmu, S[i])
    if out.shape[0] > 1 + n:
        eta = P[P_ETA]
        out[1 + n] = v
        out[2 + n] = (mu_s - eta * v) * v
        out[3 + n] = eta * v * v
        out[4 + n] = mu_s * v_lp
    return u


@njit(cache=True)
def qs_jac(y, P, S, n, out):  # type: ignore[no-untyped-def]
    """Jacobian of :func:`qs_rhs` with respect to ``(mu_s, theta_1..n)``."""
    vr = P[P_VR]
    kw = P[P_KW]
    u, r, d = qs_lnv(y[0], P[P_MU0] + psi(y, S, 1, n), P)
    v = vr * math.exp(u)
    out[0, 0] = -kw * v / d
    for j in range(n):
        out[0, 1 + j] = kw * v * r * S[j, 0] / d
    for i in range(n):
        gu, gt = _state_partials(int(S[i, 2]), S[i, 0], S[i, 1], S[i, 3], y[1 + i], u, v, vr, kw, S[i])
        out[1 + i, 0] = gu / d
        for j in range(n):
            out[1 + i, 1 + j] = -gu * r * S[j, 0] / d
        out[1 + i, 1 + i] += gt


@njit(cache=True)
def qs_velocity(mu_s, y, S, n, P):  # type: ignore[no-untyped-def]
    """Slip velocity (m/s) of the quasi-static slider at spring stress ``mu_s`` and log-states ``y[1:]``."""
    u, _, _ = qs_lnv(mu_s, P[P_MU0] + psi(y, S, 1, n), P)
    return P[P_VR] * math.exp(u)


@njit(cache=True)
def in_friction(v, y, S, n, P):  # type: ignore[no-untyped-def]
    """Regularised friction ``A asinh(v/(2 V_r) exp(psi/A))`` of the inertial slider (log-states y[2:])."""
    a = P[P_A]
    ps = P[P_MU0] + psi(y, S, 2, n)
    return a * math.asinh(v / (2.0 * P[P_VR]) * math.exp(ps / a))


@njit(cache=True)
def in_rhs(y, P, S, n, v_lp, out):  # type: ignore[no-untyped-def]
    """Inertial right-hand side of ``y = (mu_s, v, theta_1..n)``."""
    vr = P[P_VR]
    kw = P[P_KW]
    mus = y[0]
    v = y[1]
    dmu = kw * (v_lp - v)
    out[0] = dmu
    out[1] = P[P_WM] * (mus - in_friction(v, y, S, n, P) - P[P_ETA] * v)
    av = max(abs(v), 1e-300)
    u = math.log(av / vr)
    for i in range(n):
        out[2 + i] = state_rate(int(S[i, 2]), S[i, 0], S[i, 1], S[i, 3], y[2 + i], u, av, vr, dmu, S[i])


@njit(cache=True)
def in_jac(y, P, S, n, out):  # type: ignore[no-untyped-def]
    """Jacobian of :func:`in_rhs` with respect to ``(mu_s, v, theta_1..n)``."""
    a = P[P_A]
    vr = P[P_VR]
    kw = P[P_KW]
    wm = P[P_WM]
    v = y[1]
    ps = P[P_MU0] + psi(y, S, 2, n)
    e = math.exp(ps / a) / (2.0 * vr)
    z = v * e
    s = 1.0 / math.sqrt(1.0 + z * z)
    for i in range(n + 2):
        for j in range(n + 2):
            out[i, j] = 0.0
    out[0, 1] = -kw
    out[1, 0] = wm
    out[1, 1] = -wm * (a * e * s + P[P_ETA])
    for j in range(n):
        out[1, 2 + j] = -wm * s * z * S[j, 0]
    av = max(abs(v), 1e-300)
    sg = 1.0 if v >= 0 else -1.0
    u = math.log(av / vr)
    for i in range(n):
        gu, gt = _state_partials(int(S[i, 2]), S[i, 0], S[i, 1], S[i, 3], y[2 + i], u, av, vr, kw, S[i])
        out[2 + i, 1] = sg * gu / av
        out[2 + i, 2 + i] = gt


# ------------------------------------------------------------------ integrator


@njit(cache=True)
def _dense(P, S, n, v_lp, t, y, y_new, h, K, F, ytmp, nvar):  # type: ignore[no-untyped-def]
    """Fill ``F`` with the 7th-order interpolant of the step just taken (3 more stages)."""
    for j in range(N_STAGES + 1, N_STAGES_EXTENDED):
        vec_stage(y, K, h, j, nvar, ytmp)
        qs_rhs(ytmp, P, S, n, v_lp, K[j])
    vec_dense_coeffs(y, y_new, h, K, F, nvar)


@njit(cache=True)
def _interp(F, y, x, nvar, out):  # type: ignore[no-untyped-def]
    for c in range(nvar):
        out[c] = dense_eval(F, y, x, c)


@njit(cache=True)
def _g(kind, P, S, n, v_lp, level, F, y, x, nvar, ytmp, ftmp):  # type: ignore[no-untyped-def]
    """Event function ``kind`` at ``x`` in [0, 1] of the step (``level`` a ``ln(v/V_r)``)."""
    _interp(F, y, x, nvar, ytmp)
    if kind == EV_VELOCITY_PEAK:
        qs_rhs(ytmp, P, S, n, v_lp, ftmp)
        return ftmp[0] - psi(ftmp, S, 1, n)
    u, _, _ = qs_lnv(ytmp[0], P[P_MU0] + psi(ytmp, S, 1, n), P)
    return u - level


@njit(cache=True)
def _locate(kind, P, S, n, v_lp, level, F, y, ga, gb, nvar, ytmp, ftmp):  # type: ignore[no-untyped-def]
    """Root in [0, 1] of event function ``kind`` by the Illinois method on the interpolant."""
    xa = 0.0
    xb = 1.0
    if ga == 0.0:
        return xa
    if gb == 0.0:
        return xb
    side = 0
    xc = xb
    for _ in range(200):
        xc = illinois_propose(xa, ga, xb, gb)
        gc = _g(kind, P, S, n, v_lp, level, F, y, xc, nvar, ytmp, ftmp)
        xa, ga, xb, gb, side, done = illinois_update(xa, ga, xb, gb, side, xc, gc)
        if done:
            break
    return xc


@njit(cache=True)
def _record(ev, nev, kind, t, u, yv, nvar):  # type: ignore[no-untyped-def]
    if nev >= ev.shape[0]:
        return nev
    ev[nev, EVC_KIND] = kind
    ev[nev, EVC_T] = t
    ev[nev, EVC_U] = u
    for c in range(nvar):
        ev[nev, EVC_Y + c] = yv[c]
    return nev + 1


@njit(cache=True)
def _peak_fn(K, S, n, row):  # type: ignore[no-untyped-def]
    """Sign of ``d ln v/dt``: ``mu_s' - sum_i B_i theta_i'`` from a stage's rates."""
    return K[row, 0] - psi(K[row], S, 1, n)


@njit(cache=True)
def integrate_qs(  # type: ignore[no-untyped-def]
    P,
    S,
    n,
    seg_end,
    seg_v,
    y0,
    t0,
    samples,
    rtol,
    atol,
    h_max,
    max_steps,
    v_cap,
    v_event,
    peaks,
    sample_out,
    ev,
    rec,
    rec_every,
):
    """Integrate the quasi-static (or quasi-dynamic) slider through a load-point history.

    Parameters
    ----------
    P, S, n : arrays, int
        Parameters, state table and number of state variables.
    seg_end, seg_v : arrays
        End times (s) and load-point velocities (m/s) of the piecewise-constant history.
    t0 : float
        Start time (s).
    y0 : array
        ``(mu_s, theta_1..n)`` followed by ``N_QUAD`` quadratures (usually zero) at ``t0``;
        overwritten with the state at the returned time (to resume after ``RS_MAX_STEPS``).
    samples : array
        Increasing times (s) at which to write ``(y, u)`` from the dense output.
    rtol, atol, h_max, max_steps : float, float, float, int
        Tolerances (error control on ``mu_s`` and the log-states only), largest step, work bound.
    v_cap : float
        The integration stops (``RS_RUNAWAY``) when ``v`` exceeds it.
    v_event : float
        Record upward and downward crossings of this velocity and the velocity peaks above it (0: none).
    peaks : bool
        Record the spring-stress maxima (``v`` crossing ``v_lp`` upward).
    rec_every : int
        Record every ``rec_every``-th accepted step (0: none).
    sample_out, ev, rec : arrays
        Outputs: ``len(samples) x (nvar + 1)``; events ``(kind, t, u, y...)``; every
        ``rec_every``-th accepted step ``(t, u, y...)`` (as many as ``rec`` holds).

    Returns
    -------
    status, t, n_samples, n_events, n_rec, steps, rejected

    """
    nvar = y0.shape[0]
    nctl = 1 + n
    K = np.zeros((N_STAGES_EXTENDED, nvar))
    F = np.zeros((7, nvar))
    y = y0.copy()
    y_new = np.zeros(nvar)
    ytmp = np.zeros(nvar)
    ftmp = np.zeros(nvar)
    ns = samples.shape[0]
    js = 0
    # kinds and counters that are not literals, so that one specialization of _locate, _g
    # and _record serves every call (a literal argument compiles one per value)
    k0 = 0 * n
    ev_up = EV_UP + k0
    ev_peak = EV_VELOCITY_PEAK + k0
    nev = k0
    nrec = 0
    steps = 0
    rejected = 0
    accepted = 0
    t = t0
    ln_cap = math.log(v_cap / P[P_VR]) if v_cap > 0.0 else math.inf
    ln_ev = math.log(v_event / P[P_VR]) if v_event > 0.0 else math.nan
    kseg = 0
    nseg = seg_end.shape[0]
    while kseg < nseg and seg_end[kseg] <= t:
        kseg += 1
    v_lp = seg_v[min(kseg, nseg - 1)]
    u = qs_rhs(y, P, S, n, v_lp, K[0])
    while js < ns and samples[js] <= t:
        for c in range(nvar):
            sample_out[js, c] = y[c]
        sample_out[js, nvar] = u
        js += 1
    if rec.shape[0] > 0:
        rec[0, RECC_T] = t
        rec[0, RECC_U] = u
        for c in range(nvar):
            rec[0, RECC_Y + c] = y[c]
        nrec = 1
    if kseg >= nseg:
        return RS_OK, t, js, nev, nrec, steps, rejected
    # first step (Hairer, Norsett and Wanner, Sec. II.4)
    d0 = 0.0
    d1 = 0.0
    for c in range(nctl):
        sc = atol + abs(y[c]) * rtol
        d0 += (y[c] / sc) ** 2
        d1 += (K[0, c] / sc) ** 2
    d0 = math.sqrt(d0 / nctl)
    d1 = math.sqrt(d1 / nctl)
    h = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h = min(h, h_max, seg_end[kseg] - t)
    status = RS_OK
    while True:
        if steps >= max_steps:
            status = RS_MAX_STEPS
            break
        limit = seg_end[kseg] - t
        hit = False
        if h >= limit:
            h = limit
            hit = True
        for s in range(1, N_STAGES):
            vec_stage(y, K, h, s, nvar, ytmp)
            qs_rhs(ytmp, P, S, n, v_lp, K[s])
        vec_advance(y, K, h, nvar, y_new)
        u_new = qs_rhs(y_new, P, S, n, v_lp, K[N_STAGES])
        err = vec_error(y, y_new, K, h, nctl, rtol, atol)
        steps += 1
        if not math.isfinite(err) or not math.isfinite(u_new) or err > 1.0:
            rejected += 1
            if math.isfinite(err) and math.isfinite(u_new):
                h *= max(MIN_FACTOR, SAFETY / _root8(err))
            else:
                h *= MIN_FACTOR
            if h < 1e-14 * max(1.0, abs(t)):
                status = RS_STEP_TOO_SMALL if math.isfinite(err) else RS_NONFINITE
                break
            continue
        t_new = seg_end[kseg] if hit else t + h
        _dense(P, S, n, v_lp, t, y, y_new, h, K, F, ytmp, nvar)
        # ------------------------------------------------ events in the step
        stop = False
        if peaks and v_lp > 0.0:
            lvl = math.log(v_lp / P[P_VR])
            ga = u - lvl
            gb = u_new - lvl
            if ga < 0.0 <= gb:
                x = _locate(ev_up, P, S, n, v_lp, lvl, F, y, ga, gb, nvar, ytmp, ftmp)
                _interp(F, y, x, nvar, ytmp)
                uu, _, _ = qs_lnv(ytmp[0], P[P_MU0] + psi(ytmp, S, 1, n), P)
                nev = _record(ev, nev, EV_SPRING_PEAK + k0, t + x * h, uu, ytmp, nvar)
        if v_event > 0.0:
            ga = u - ln_ev
            gb = u_new - ln_ev
            if (ga < 0.0 <= gb) or (ga > 0.0 >= gb):
                kind = EV_UP if gb >= 0.0 else EV_DOWN
                x = _locate(ev_up, P, S, n, v_lp, ln_ev, F, y, ga, gb, nvar, ytmp, ftmp)
                _interp(F, y, x, nvar, ytmp)
                uu, _, _ = qs_lnv(ytmp[0], P[P_MU0] + psi(ytmp, S, 1, n), P)
                nev = _record(ev, nev, kind, t + x * h, uu, ytmp, nvar)
            if max(u, u_new) > ln_ev:
                pa = _peak_fn(K, S, n, 0)
                pb = _peak_fn(K, S, n, N_STAGES)
                if pa > 0.0 >= pb:
                    x = _locate(ev_peak, P, S, n, v_lp, 0.0, F, y, pa, pb, nvar, ytmp, ftmp)
                    _interp(F, y, x, nvar, ytmp)
                    uu, _, _ = qs_lnv(ytmp[0], P[P_MU0] + psi(ytmp, S, 1, n), P)
                    nev = _record(ev, nev, ev_peak, t + x * h, uu, ytmp, nvar)
        if u_new > ln_cap:
            x = _locate(ev_up, P, S, n, v_lp, ln_cap, F, y, u - ln_cap, u_new - ln_cap, nvar, ytmp, ftmp)
            _interp(F, y, x, nvar, ytmp)
            nev = _record(ev, nev, EV_RUNAWAY + k0, t + x * h, ln_cap, ytmp, nvar)
            t_stop = t + x * h
            while js < ns and samples[js] <= t_stop:
                _interp(F, y, (samples[js] - t) / h, nvar, ytmp)
                for c in range(nvar):
                    sample_out[js, c] = ytmp[c]
                sample_out[js, nvar], _, _ = qs_lnv(ytmp[0], P[P_MU0] + psi(ytmp, S, 1, n), P)
                js += 1
            t = t_stop
            status = RS_RUNAWAY
            stop = True
            for c in range(nvar):
                y[c] = ev[min(nev, ev.shape[0]) - 1, EVC_Y + c] if nev > 0 else y[c]
        if stop:
            break
        if nev >= ev.shape[0]:
            status = RS_EVENTS_FULL
        # ------------------------------------------------ samples in the step
        while js < ns and samples[js] <= t_new:
            x = (samples[js] - t) / h
            if samples[js] >= t_new:
                for c in range(nvar):
                    sample_out[js, c] = y_new[c]
                sample_out[js, nvar] = u_new
            else:
                _interp(F, y, x, nvar, ytmp)
                for c in range(nvar):
                    sample_out[js, c] = ytmp[c]
                sample_out[js, nvar], _, _ = qs_lnv(ytmp[0], P[P_MU0] + psi(ytmp, S, 1, n), P)
            js += 1
        # ------------------------------------------------ accept
        accepted += 1
        for c in range(nvar):
            y[c] = y_new[c]
            K[0, c] = K[N_STAGES, c]
        t = t_new
        u = u_new
        if rec_every > 0 and accepted % rec_every == 0 and nrec < rec.shape[0]:
            rec[nrec, RECC_T] = t
            rec[nrec, RECC_U] = u
            for c in range(nvar):
                rec[nrec, RECC_Y + c] = y[c]
            nrec += 1
        if status != RS_OK:
            break
        if err == 0.0:
            factor = MAX_FACTOR
        else:
            factor = min(MAX_FACTOR, SAFETY / _root8(err))
        h = min(h * factor, h_max)
        if hit:
            kseg += 1
            if kseg >= nseg:
                break
            v_lp = seg_v[kseg]
            u = qs_rhs(y, P, S, n, v_lp, K[0])
    for c in range(nvar):
        y0[c] = y[c]
    return status, t, js, nev, nrec, steps, rejected
