"""Compiled DOP853 step, error estimate and dense output for the slip phase.

The slip-phase state is ``y = (s, w)`` (spring force, block velocity), optionally
followed by two quadratures ``(integral of s, integral of f(w) w)`` used for the
energy balance. Error control acts on ``(s, w)`` only, so asking for the
quadratures never changes the trajectory.

The step-size controller, the error norm and the dense output follow
E. Hairer, S. P. Nørsett and G. Wanner, *Solving Ordinary Differential
Equations I*, Sec. II.10, as implemented in ``scipy.integrate.DOP853``.
"""

from __future__ import annotations

import math

from numba import njit

from ._dop853_tableau import E3, E5, N_STAGES, N_STAGES_EXTENDED, A, B, D
from .laws import friction_scalar, params

#: what :func:`illinois_sw` finds: a level of ``w``, or an extremum of ``w``. Callers pass
#: ``LEVEL + 0 * law``: not a literal, so that one specialization serves every call (a
#: literal argument would compile one per value on the first use)
LEVEL = 1
WEXT = 2

__all__ = [
    "LEVEL",
    "N_STAGES",
    "N_STAGES_EXTENDED",
    "WEXT",
    "dense_eval",
    "dense_slope",
    "illinois_propose",
    "illinois_sw",
    "illinois_update",
    "initial_step",
    "poly7",
    "rhs",
    "vec_advance",
    "vec_dense_coeffs",
    "vec_error",
    "vec_stage",
]

@njit(cache=True)
def rhs(law, lp, nu, d, y, out):  # type: ignore[no-untyped-def]
    """Evaluate the slip-phase vector field in direction ``d`` into ``out``."""
    s = y[0]
    w = y[1]
    fr = friction_scalar(law, params(lp), d, w)
    out[0] = nu - w
    out[1] = s - fr
    if y.shape[0] > 2:
        out[2] = s
        out[3] = fr * w


@njit(cache=True)
def _rms2(a0, a1):  # type: ignore[no-untyped-def]
    return math.sqrt(0.5 * (a0 * a0 + a1 * a1))


@njit(cache=True)
def initial_step(law, lp, nu, d, y, f0, rtol, atol, h_max, ytmp, ftmp):  # type: ignore[no-untyped-def]
    """Choose a first step as in Hairer, Nørsett and Wanner, Sec. II.4."""
    sc0 = atol + abs(y[0]) * rtol
    sc1 = atol + abs(y[1]) * rtol
    d0 = _rms2(y[0] / sc0, y[1] / sc1)
    d1 = _rms2(f0[0] / sc0, f0[1] / sc1)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, h_max)
    for i in range(y.shape[0]):
        ytmp[i] = y[i] + h0 * f0[i]
    rhs(law, lp, nu, d, ytmp, ftmp)
    d2 = _rms2((ftmp[0] - f0[0]) / sc0, (ftmp[1] - f0[1]) / sc1) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100.0 * h0, h1, h_max)


@njit(cache=True, inline="always")
def dense_eval(F, y_old, x, i):  # type: ignore[no-untyped-def]
    """Evaluate component ``i`` of the interpolant at ``x`` in [0, 1] of the step."""
    x1 = 1.0 - x
    acc = F[6, i] * x
    acc = (acc + F[5, i]) * x1
    acc = (acc + F[4, i]) * x
    acc = (acc + F[3, i]) * x1
    acc = (acc + F[2, i]) * x
    acc = (acc + F[1, i]) * x1
    acc = (acc + F[0, i]) * x
    return y_old[i] + acc


# Scalar versions for the slip-phase loop: the interpolant of one component is a
# tuple of seven coefficients, so that no array (and no atomic reference count
# update) crosses a call.


@njit(cache=True)
def poly7(c, y0, x):  # type: ignore[no-untyped-def]
    """Evaluate at ``x`` the interpolant with coefficients ``c`` (7-tuple) from ``y0``.

    Same operations, in the same order, as :func:`dense_eval`.
    """
    x1 = 1.0 - x
    acc = c[6] * x
    acc = (acc + c[5]) * x1
    acc = (acc + c[4]) * x
    acc = (acc + c[3]) * x1
    acc = (acc + c[2]) * x
    acc = (acc + c[1]) * x1
    acc = (acc + c[0]) * x
    return y0 + acc


# The Illinois iteration in two halves, shared by every event locator (this
# module's ``illinois_sw`` for one block, the chain engine's for each block):
# the caller evaluates its own function at the proposed point in between.


@njit(cache=True, inline="always")
def illinois_propose(xa, ga, xb, gb):  # type: ignore[no-untyped-def]
    """Return the next point of the Illinois (modified regula falsi) iteration on ``[xa, xb]``."""
    xc = (xa * gb - xb * ga) / (gb - ga)
    if not (xa < xc < xb):
        xc = 0.5 * (xa + xb)
    return xc


@njit(cache=True, inline="always")
def illinois_update(xa, ga, xb, gb, side, xc, gc):  # type: ignore[no-untyped-def]
    """Shrink the bracket with the value ``gc`` at ``xc``.

    Returns ``(xa, ga, xb, gb, side, done)``; ``done`` when ``gc`` is zero or the
    bracket is as small as double precision allows (the root is then ``xc``).
    """
    if gc == 0.0:
        return xa, ga, xb, gb, side, True
    if (gc > 0.0) == (gb > 0.0):
        xb = xc
        gb = gc
        if side == -1:
            ga *= 0.5
        side = -1
    else:
        xa = xc
        ga = gc
        if side == 1:
            gb *= 0.5
        side = 1
    return xa, ga, xb, gb, side, xb - xa <= 4e-16 * max(1.0, abs(xc))


@njit(cache=True)
def illinois_sw(law, P, d, cs, s0, cw, w0, what, level, xa, ga, xb, gb):  # type: ignore[no-untyped-def]
    """Find a root by the Illinois method on the interpolants of ``s`` and ``w``.

    ``(cs, s0)`` and ``(cw, w0)`` are the coefficient tuples and start values of
    the interpolants of ``s`` and ``w`` (see :func:`poly7`); ``ga`` and ``gb``
    are the function values at ``xa`` and ``xb``, of opposite sign.

    ``what = 1`` finds ``w(x) = level``; ``what = 2`` finds ``dw/dtau(x) = 0``.
    """
    if ga == 0.0:
        return xa
    if gb == 0.0:
        return xb
    side = 0
    xc = xb
    for _ in range(200):
        xc = illinois_propose(xa, ga, xb, gb)
        if what == 1:
            gc = poly7(cw, w0, xc) - level
        else:
            gc = poly7(cs, s0, xc) - friction_scalar(law, P, d, poly7(cw, w0, xc))
        xa, ga, xb, gb, side, done = illinois_update(xa, ga, xb, gb, side, xc, gc)
        if done:
            break
    return xc


# ---------------------------------------------------------------- any dimension
# The same DOP853 step for a state of any length, in three parts between which
# the caller evaluates its own vector field (stage ``j`` of the step is
# ``K[j] = f(t + C[j] h, y + h sum_i A[j, i] K[i])``). The chain engine uses them;
# the one-block engine uses the same tableau written out for ``(s, w)``.


@njit(cache=True, inline="always")
def _vec_combine(y, K, h, coef, m, n, out):  # type: ignore[no-untyped-def]
    """Fill ``out[:n]`` with ``y + h sum_{i < m} coef[i] K[i]``.

    The sum runs stage by stage over contiguous rows of ``K`` (so that the
    compiler vectorises it), in the same order for every component as a sum
    component by component: the same numbers, bit for bit.
    """
    for c in range(n):
        out[c] = 0.0
    for i in range(m):
        a = coef[i]
        if a != 0.0:
            for c in range(n):
                out[c] += a * K[i, c]
    for c in range(n):
        out[c] = y[c] + h * out[c]


@njit(cache=True)
def vec_stage(y, K, h, j, n, out):  # type: ignore[no-untyped-def]
    """Fill ``out[:n]`` with the state of stage ``j``: ``y + h sum_i A[j, i] K[i]``."""
    _vec_combine(y, K, h, A[j], j, n, out)


@njit(cache=True)
def vec_advance(y, K, h, n, out):  # type: ignore[no-untyped-def]
    """Fill ``out[:n]`` with the 8th-order solution at the end of the step."""
    _vec_combine(y, K, h, B, N_STAGES, n, out)


@njit(cache=True)
def vec_dense_coeffs(y_old, y_new, h, K, F, n):  # type: ignore[no-untyped-def]
    """Fill ``F[:, :n]`` with the interpolant's coefficients of the step (``K`` with all 16 stages).

    The numbers of ``_dop853_unrolled.dense_coeffs`` component by component, bit
    for bit, summed stage by stage as :func:`vec_stage`.
    """
    for i in range(n):
        dy = y_new[i] - y_old[i]
        F[0, i] = dy
        F[1, i] = h * K[0, i] - dy
        F[2, i] = 2.0 * dy - h * (K[12, i] + K[0, i])
    for r in range(4):
        for i in range(n):
            F[3 + r, i] = 0.0
        for j in range(N_STAGES_EXTENDED):
            c = D[r, j]
            if c != 0.0:
                for i in range(n):
                    F[3 + r, i] += c * K[j, i]
        for i in range(n):
            F[3 + r, i] = h * F[3 + r, i]


@njit(cache=True)
def vec_error(y, y_new, K, h, n, rtol, atol):  # type: ignore[no-untyped-def]
    """Return the DOP853 error norm of the step over ``y[:n]`` (``K[12]`` filled at the end).

    ``K`` has the rows of the interpolant's extra stages (``N_STAGES_EXTENDED``);
    two of them serve as work space here.

    As ``scipy.integrate.DOP853``: the 5th- and 3rd-order estimates combined, RMS
    over the components, scaled by ``atol + rtol max(|y|, |y_new|)``.
    """
    # the two estimates summed stage by stage into rows 13 and 14 of ``K`` (the
    # interpolant's extra stages, computed after this), as :func:`vec_stage`
    s5 = K[N_STAGES + 1]
    s3 = K[N_STAGES + 2]
    for c in range(n):
        s5[c] = 0.0
        s3[c] = 0.0
    for i in range(N_STAGES + 1):
        b5 = E5[i]
        b3 = E3[i]
        for c in range(n):
            s5[c] += b5 * K[i, c]
            s3[c] += b3 * K[i, c]
    e5 = 0.0
    e3 = 0.0
    for c in range(n):
        sc = atol + rtol * max(abs(y[c]), abs(y_new[c]))
        a5 = s5[c] / sc
        a3 = s3[c] / sc
        e5 += a5 * a5
        e3 += a3 * a3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True, inline="always")
def dense_slope(F, x, i):  # type: ignore[no-untyped-def]
    """Return d/dx of component ``i`` of the interpolant (see :func:`dense_eval`) at ``x``.

    Divide by the step to get the time derivative.
    """
    # y = y0 + x(F0 + x1(F1 + x(F2 + x1(F3 + x(F4 + x1(F5 + x F6))))))
    x1 = 1.0 - x
    p6 = F[6, i]
    q6 = 0.0
    p5 = F[5, i] + x * p6
    q5 = p6 + x * q6
    p4 = F[4, i] + x1 * p5
    q4 = -p5 + x1 * q5
    p3 = F[3, i] + x * p4
    q3 = p4 + x * q4
    p2 = F[2, i] + x1 * p3
    q2 = -p3 + x1 * q3
    p1 = F[1, i] + x * p2
    q1 = p2 + x * q2
    p0 = F[0, i] + x1 * p1
    q0 = -p1 + x1 * q1
    return p0 + x * q0
