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

from numba import njit

from ._dop853_tableau import A, B
from ._dop853_unrolled import dense_sw, step_sw
from .dop853 import illinois_sw, poly7
from .laws import df_branch, slip_accel

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
    for j in range(12):
        ww = y[1]
        for k in range(j):
            ww += h * A[j, k] * kw[k]
        df = df_branch(law, lp, ww)
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
def flow_variational(law, lp, nu, y, T, rtol, atol, max_steps, measure, KV, extras):  # type: ignore[no-untyped-def]
    """Integrate ``y`` (length ``NVAR``, updated in place) from ``tau = 0`` to ``T``.

    ``measure`` asks for the dense-output measurements in ``extras``
    (``X_S_MIN``, ``X_W_MIN``, ``X_W_MAX``); ``extras[X_STEPS]`` and
    ``extras[X_STATUS]`` are always set.
    """
    p0 = lp[0]
    p1 = lp[1]
    s = y[0]
    w = y[1]
    ks0 = nu - w
    kw0 = slip_accel(law, p0, p1, 1.0, s, w)
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
        err, s1, w1, ks, kw = step_sw(law, p0, p1, nu, 1.0, s, w, ks0, kw0, h, rtol, atol)
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
        _var_stages(law, lp, y, h, kw, KV)
        for i in range(7):
            acc = 0.0
            for j in range(12):
                acc += B[j] * KV[j, i]
            y[2 + i] += h * acc
        if measure:
            if (
                (w - nu > 0.0 and w1 - nu <= 0.0)
                or (kw[0] < 0.0 and kw[12] >= 0.0)
                or (kw[0] > 0.0 and kw[12] <= 0.0)
            ):
                cs, cw, _ksx, _kwx = dense_sw(law, p0, p1, nu, 1.0, s, w, s1, w1, h, ks, kw)
                if w - nu > 0.0 and w1 - nu <= 0.0:
                    x = illinois_sw(law, p0, p1, 1.0, cs, s, cw, w, 1, nu, 0.0, w - nu, 1.0, w1 - nu)
                    sv = poly7(cs, s, x)
                    if not (extras[X_S_MIN] <= sv):
                        extras[X_S_MIN] = sv
                if (kw[0] < 0.0 and kw[12] >= 0.0) or (kw[0] > 0.0 and kw[12] <= 0.0):
                    x = illinois_sw(law, p0, p1, 1.0, cs, s, cw, w, 2, 0.0, 0.0, kw[0], 1.0, kw[12])
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
