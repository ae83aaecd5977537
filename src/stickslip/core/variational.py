"""Compiled slip-phase flow with its variational equations, for shooting.

State ``y`` (length :data:`NVAR`)::

    y[0], y[1]          s, w                       (the slip flow, direction +1)
    y[2:6]              Phi = d(s, w)/d(s0, w0)    (row-major 2 x 2)
    y[6], y[7]          z = d(s, w)/d nu            (at fixed initial state)
    y[8]                integral of f'(w) dtau

with ``Phi' = J Phi``, ``z' = J z + (1, 0)``, ``J = [[0, -1], [1, -f'(w)]]``.
The ``(s, w)`` part is stepped by the same unrolled DOP853 as the engine
(:func:`step_sw`) and its error alone controls the step; the variational
components ride along with the same Runge-Kutta stages (they are linear, so
their relative error follows that of the flow). The integration ends exactly at
``tau = T``. On request the pass also records, from the 7th-order dense output,
the spring force where ``w`` crosses ``nu`` downward (the minimum of ``s``) and
the extremes of ``w``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._dop853_tableau import A, B
from ._dop853_unrolled import dense_sw, step_sw
from .dop853 import LEVEL, WEXT, illinois_sw, poly7
from .laws import df_plus, params, slip_accel

NVAR = 9
# extras layout
X_S_MIN = 0
X_W_MIN = 1
X_W_MAX = 2
X_STEPS = 3
X_STATUS = 4
NX = 5
# statuses
VS_OK = 0
VS_MAX_STEPS = 1
VS_NONFINITE = 2

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0


@njit(cache=True)
def _var_stages(law, lp, y, h, kw, KV):  # type: ignore[no-untyped-def]
    """Fill ``KV`` (12 x 7) with the stage derivatives of the variational components."""
    P = params(lp)
    for j in range(12):
        ww = y[1]
        for k in range(j):
            ww += h * A[j, k] * kw[k]
        df = df_plus(law, P, ww)
        v0 = y[2]
        v1 = y[3]
        v2 = y[4]
        v3 = y[5]
        v4 = y[6]
        v5 = y[7]
        for k in range(j):
            a = h * A[j, k]
            v0 += a * KV[k, 0]
            v1 += a * KV[k, 1]
            v2 += a * KV[k, 2]
            v3 += a * KV[k, 3]
            v4 += a * KV[k, 4]
            v5 += a * KV[k, 5]
        KV[j, 0] = -v2
        KV[j, 1] = -v3
        KV[j, 2] = v0 - df * v2
        KV[j, 3] = v1 - df * v3
        KV[j, 4] = 1.0 - v5
        KV[j, 5] = v4 - df * v5
        KV[j, 6] = df


@njit(cache=True)
def flow_variational(law, lp, nu, y, T, rtol, atol, max_steps, measure, direction, KV, extras):  # type: ignore[no-untyped-def]
    """Integrate ``y`` (length ``NVAR``, updated in place) from ``tau = 0`` to ``direction * T``.

    ``direction`` is +1.0 (forward) or -1.0 (backward in time: the flow of an unstable
    orbit contracts onto it, so that shooting it is as well-conditioned as shooting a
    stable one forward; the variational components then hold the backward flow's
    derivatives and ``y[8]`` minus the integral of ``f'`` over the forward-time
    interval). ``measure`` asks for the dense-output measurements in ``extras``
    (``X_S_MIN``: the spring force where ``w`` crosses ``nu`` downward in forward time,
    ``X_W_MIN``, ``X_W_MAX``); ``extras[X_STEPS]`` and ``extras[X_STATUS]`` are always set.
    """
    P = params(lp)
    # forward slip, as the integer direction of the one-block engine (1 + 0 * law: not a
    # literal), so that both share the compiled step, interpolant and root finder
    fwd = 1 + 0 * law
    s = y[0]
    w = y[1]
    ks0 = nu - w
    kw0 = slip_accel(law, P, fwd, s, w)
    extras[X_S_MIN] = math.nan
    extras[X_W_MIN] = w
    extras[X_W_MAX] = w
    extras[X_STATUS] = VS_OK
    t = 0.0
    h = min(T, 0.05)
    n = 0
    while t < T:
        if n >= max_steps:
            extras[X_STATUS] = VS_MAX_STEPS
            break
        last = False
        if t + h >= T:
            h = T - t
            last = True
        hd = direction * h
        err, s1, w1, ks, kw = step_sw(law, P, nu, fwd, s, w, ks0, kw0, hd, rtol, atol)
        n += 1
        if not (math.isfinite(err) and math.isfinite(s1) and math.isfinite(w1)):
            if h < 1e-14:
                extras[X_STATUS] = VS_NONFINITE
                break
            h *= MIN_FACTOR
            continue
        if err > 1.0:
            h *= max(MIN_FACTOR, SAFETY * err ** (-1.0 / 8.0))
            continue
        _var_stages(law, lp, y, hd, kw, KV)
        for i in range(7):
            acc = 0.0
            for j in range(12):
                acc += B[j] * KV[j, i]
            y[2 + i] += hd * acc
        if measure:
            # w crosses nu downward in forward time: from above to below along a forward
            # step, from below to above along a backward one
            down = (w - nu > 0.0 and w1 - nu <= 0.0) if direction > 0.0 else (w - nu < 0.0 and w1 - nu >= 0.0)
            if down or (kw[0] < 0.0 and kw[12] >= 0.0) or (kw[0] > 0.0 and kw[12] <= 0.0):
                cs, cw, _ksx, _kwx = dense_sw(law, P, nu, fwd, s, w, s1, w1, hd, ks, kw)
                if down:
                    x = illinois_sw(law, P, fwd, cs, s, cw, w, LEVEL + 0 * law, nu, 0.0, w - nu, 1.0, w1 - nu)
                    sv = poly7(cs, s, x)
                    if not (extras[X_S_MIN] <= sv):
                        extras[X_S_MIN] = sv
                if (kw[0] < 0.0 and kw[12] >= 0.0) or (kw[0] > 0.0 and kw[12] <= 0.0):
                    x = illinois_sw(law, P, fwd, cs, s, cw, w, WEXT + 0 * law, 0.0, 0.0, kw[0], 1.0, kw[12])
                    wv = poly7(cw, w, x)
                    extras[X_W_MIN] = min(extras[X_W_MIN], wv)
                    extras[X_W_MAX] = max(extras[X_W_MAX], wv)
            extras[X_W_MIN] = min(extras[X_W_MIN], w1)
            extras[X_W_MAX] = max(extras[X_W_MAX], w1)
        t = T if last else t + h
        s = s1
        w = w1
        ks0 = ks[12]
        kw0 = kw[12]
        y[0] = s
        y[1] = w
        if err == 0.0:
            fac = MAX_FACTOR
        else:
            fac = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err ** (-1.0 / 8.0)))
        h *= fac
    extras[X_STEPS] = n


# ----------------------------------------------------------------------------- shooting

# output layout of :func:`shoot`
SH_STATUS = 0
SH_S0 = 1  # spring force where the orbit crosses w = nu upward (its maximum)
SH_PERIOD = 2
SH_AMPLITUDE = 3
SH_W_MIN = 4
SH_W_MAX = 5
SH_DIV_MULT = 6  # exp(-integral of f'(w)): the nontrivial Floquet multiplier
SH_PHI = 7  # monodromy matrix, row-major, 4 entries
SH_ITER = 11
SH_RESIDUAL = 12
SH_ERR_S0 = 13  # estimated error of s0 (from the change under a tighter integration)
SH_ERR_PERIOD = 14  # ... of the period
NSH = 15
# shooting statuses
SHOOT_OK = 0
SHOOT_NO_CONVERGENCE = 1
SHOOT_DIVERGED = 2
SHOOT_FLOW_FAILED = 3
SHOOT_GRAZES = 4  # the orbit found reaches w <= 0: not a pure-slip orbit
SHOOT_TRIVIAL = 5  # Newton fell onto steady sliding (zero amplitude)

_TRIVIAL_AMPLITUDE = 1e-7
_REFINE = 1.0 / 16.0  # the error estimate integrates at this fraction of the tolerance


@njit(cache=True)
def _start(y, s0, nu):  # type: ignore[no-untyped-def]
    for i in range(NVAR):
        y[i] = 0.0
    y[0] = s0
    y[1] = nu
    y[2] = 1.0
    y[5] = 1.0


@njit(cache=True)
def _newton_step(law, lp, nu, s0, period, rtol, max_steps, y, kv, extras):  # type: ignore[no-untyped-def]
    """Integrate one period from ``(s0, nu)``; return ``(ok, residual, ds0, dT)`` of one Newton step."""
    _start(y, s0, nu)
    # law < 0 is False (law ids are not negative) but not a literal: one specialization for every caller
    flow_variational(
        law, lp, nu, y, period, rtol, rtol * 1e-2, max_steps, law < 0, 1.0 + 0.0 * law, kv, extras
    )
    if extras[X_STATUS] != VS_OK:
        return False, math.nan, math.nan, math.nan
    g0 = y[0] - s0
    g1 = y[1] - nu
    a = y[2] - 1.0
    c = y[4]
    f0 = nu - y[1]
    f1 = slip_accel(law, params(lp), 1 + 0 * law, y[0], y[1])
    det = a * f1 - f0 * c
    if det == 0.0 or not math.isfinite(det):
        return False, math.sqrt(g0 * g0 + g1 * g1), math.nan, math.nan
    return True, math.sqrt(g0 * g0 + g1 * g1), (-g0 * f1 + f0 * g1) / det, (-a * g1 + c * g0) / det


@njit(cache=True)
def shoot(law, lp, nu, s0, period, tol, max_iter, max_steps, out):  # type: ignore[no-untyped-def]
    """Solve for the pure-slip orbit through ``(s0, w = nu)`` by Newton shooting from a guess.

    The unknowns are ``s0`` (the spring-force maximum, where ``w`` crosses ``nu``
    upward) and the period ``T``; the residual is ``phi_T(s0, nu) - (s0, nu)`` and
    its Jacobian ``[Phi e_s - e_s, F(phi_T)]`` comes from the variational
    equations. The flow is integrated at ``tol / 100``; Newton stops when its
    correction is below ``tol`` (relative). The fixed-point problem is
    ill-conditioned near a Hopf point (its error is the integration error over
    ``1 - multiplier``), so one more Newton step integrated 16 times more
    tightly is taken, and its size gives the error estimate ``SH_ERR_*`` (the
    integration error being proportional to the tolerance). A last
    pass measures the orbit on the dense output. Results go to ``out`` (layout
    ``SH_*``).
    """
    y = np.empty(NVAR)
    kv = np.empty((12, 7))
    extras = np.empty(NX)
    rtol = tol * 1e-2
    for i in range(NSH):
        out[i] = math.nan
    out[SH_STATUS] = SHOOT_NO_CONVERGENCE
    f_nu = s0 - slip_accel(law, params(lp), 1 + 0 * law, s0, nu)  # f(nu)
    residual = math.inf
    it = 0
    converged = False
    while it < max_iter:
        it += 1
        if not (math.isfinite(s0) and math.isfinite(period) and period > 0.0):
            out[SH_STATUS] = SHOOT_DIVERGED
            break
        if abs(s0 - f_nu) < _TRIVIAL_AMPLITUDE:
            out[SH_STATUS] = SHOOT_TRIVIAL
            break
        ok, residual, ds, dt = _newton_step(law, lp, nu, s0, period, rtol, max_steps, y, kv, extras)
        if not ok:
            out[SH_STATUS] = SHOOT_FLOW_FAILED if extras[X_STATUS] != VS_OK else SHOOT_DIVERGED
            break
        s0 += ds
        period += dt
        if abs(ds) <= tol * max(1.0, abs(s0)) and abs(dt) <= tol * max(1.0, abs(period)):
            converged = True
            break
    out[SH_ITER] = it
    out[SH_RESIDUAL] = residual
    if not converged:
        return
    fine = rtol * _REFINE
    ok, residual, ds, dt = _newton_step(law, lp, nu, s0, period, fine, max_steps, y, kv, extras)
    if not ok:
        out[SH_STATUS] = SHOOT_FLOW_FAILED
        return
    s0 += ds
    period += dt
    out[SH_RESIDUAL] = residual
    # the integration error is proportional to the tolerance: the step from the coarse to
    # the fine solution is (1 - _REFINE) of the coarse error, the fine error _REFINE of it
    out[SH_ERR_S0] = abs(ds) * _REFINE / (1.0 - _REFINE)
    out[SH_ERR_PERIOD] = abs(dt) * _REFINE / (1.0 - _REFINE)
    if abs(s0 - f_nu) < _TRIVIAL_AMPLITUDE:
        out[SH_STATUS] = SHOOT_TRIVIAL
        return
    _start(y, s0, nu)
    flow_variational(
        law, lp, nu, y, period, fine, fine * 1e-2, max_steps, law >= 0, 1.0 + 0.0 * law, kv, extras
    )
    if extras[X_STATUS] != VS_OK:
        out[SH_STATUS] = SHOOT_FLOW_FAILED
        return
    out[SH_S0] = s0
    out[SH_PERIOD] = period
    out[SH_AMPLITUDE] = s0 - extras[X_S_MIN]
    out[SH_W_MIN] = extras[X_W_MIN]
    out[SH_W_MAX] = extras[X_W_MAX]
    out[SH_DIV_MULT] = math.exp(-y[8])
    for i in range(4):
        out[SH_PHI + i] = y[2 + i]
    out[SH_STATUS] = SHOOT_GRAZES if extras[X_W_MIN] <= 0.0 else SHOOT_OK


@njit(cache=True, nogil=True)
def shoot_rows(law, lp, nu, s0, period, tol, max_iter, max_steps, out):  # type: ignore[no-untyped-def]
    """Run :func:`shoot` for every row (``law``, ``lp``, ``nu``, ``s0``, ``period`` per row).

    It releases the GIL: :func:`stickslip.core.api.run_shooting` runs blocks of rows
    in a pool of threads.
    """
    for i in range(nu.shape[0]):
        shoot(law[i], lp[i], nu[i], s0[i], period[i], tol, max_iter, max_steps, out[i])
