"""Rate-and-state spring-slider: compiled right-hand sides and Jacobians (numbers only).

Quasi-static model (the paper's appendix, PHYSICS.md §5), SI units:

    mu = (k/W) (x_lp - x) = mu0 + A ln(v/V_r) + B ln(Phi V_r / D0)

with state ``theta = ln(Phi V_r / D0)`` (so ``Phi`` stays positive over any
number of decades) and friction ``mu`` as variables:

    v      = V_r exp((mu - mu0 - B theta)/A)
    mu'    = kw (v_lp - v)                       (kw = k/W, 1/m)
    theta' = (V_r/D0) exp(-theta) - v/D0          aging (Dieterich) law
    theta' = -(v/D0) (ln(v/V_r) + theta)          slip (Ruina) law

Inertial model (``m x'' = k (x_lp - x) - W mu``), variables ``(mu_s, v, theta)``
with the spring's friction-equivalent ``mu_s = (k/W)(x_lp - x)`` and the
regularised friction ``mu = A asinh(v/(2 V_r) exp((mu0 + B theta)/A))``, equal to
the logarithmic law for ``v >> V_r exp(-(mu0 + B theta)/A)`` and defined at
``v <= 0`` (Rice and Ben-Zion 1996).

Parameter vector ``p = (A, B, D0, V_r, mu0, kw, W/m)``; law 0 = aging, 1 = slip.
"""

from __future__ import annotations

import math

from numba import njit

AGING = 0
SLIP = 1


@njit(cache=True)
def qs_rhs(y, p, law, v_lp, out):  # type: ignore[no-untyped-def]
    """Quasi-static right-hand side for ``y = (mu, theta)`` at load-point velocity ``v_lp``."""
    a, b, dc, vr, mu0, kw = p[0], p[1], p[2], p[3], p[4], p[5]
    mu, th = y[0], y[1]
    lnv = (mu - mu0 - b * th) / a  # ln(v / V_r)
    v = vr * math.exp(lnv)
    out[0] = kw * (v_lp - v)
    if law == AGING:
        out[1] = (vr / dc) * math.exp(-th) - v / dc
    else:
        out[1] = -(v / dc) * (lnv + th)


@njit(cache=True)
def qs_jac(y, p, law, out):  # type: ignore[no-untyped-def]
    """Jacobian of :func:`qs_rhs` with respect to ``(mu, theta)``."""
    a, b, dc, vr, mu0, kw = p[0], p[1], p[2], p[3], p[4], p[5]
    mu, th = y[0], y[1]
    lnv = (mu - mu0 - b * th) / a
    v = vr * math.exp(lnv)
    out[0, 0] = -kw * v / a
    out[0, 1] = kw * b * v / a
    if law == AGING:
        out[1, 0] = -v / (a * dc)
        out[1, 1] = -(vr / dc) * math.exp(-th) + b * v / (a * dc)
    else:
        ln_l = lnv + th
        out[1, 0] = -(v / (a * dc)) * (ln_l + 1.0)
        out[1, 1] = (v / dc) * ((b / a) * ln_l + b / a - 1.0)


@njit(cache=True)
def qs_velocity(mu, th, p):  # type: ignore[no-untyped-def]
    """Slip velocity (m/s) of the quasi-static model."""
    return p[3] * math.exp((mu - p[4] - p[1] * th) / p[0])


@njit(cache=True)
def inertial_friction(v, th, p):  # type: ignore[no-untyped-def]
    """Regularised rate-and-state friction ``A asinh(v/(2 V_r) exp((mu0 + B theta)/A))``."""
    a, b, vr, mu0 = p[0], p[1], p[3], p[4]
    return a * math.asinh(v / (2.0 * vr) * math.exp((mu0 + b * th) / a))


@njit(cache=True)
def in_rhs(y, p, law, v_lp, out):  # type: ignore[no-untyped-def]
    """Inertial right-hand side for ``y = (mu_s, v, theta)``."""
    dc, vr, kw, wm = p[2], p[3], p[5], p[6]
    mus, v, th = y[0], y[1], y[2]
    out[0] = kw * (v_lp - v)
    out[1] = wm * (mus - inertial_friction(v, th, p))
    av = abs(v)
    if law == AGING:
        out[2] = (vr / dc) * math.exp(-th) - av / dc
    else:
        av = max(av, 1e-300)
        out[2] = -(av / dc) * (math.log(av / vr) + th)


@njit(cache=True)
def in_jac(y, p, law, out):  # type: ignore[no-untyped-def]
    """Jacobian of :func:`in_rhs` with respect to ``(mu_s, v, theta)``."""
    a, b, dc, vr, mu0, kw, wm = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    v, th = y[1], y[2]
    e = math.exp((mu0 + b * th) / a) / (2.0 * vr)
    z = v * e
    s = 1.0 / math.sqrt(1.0 + z * z)
    dmu_dv = a * e * s
    dmu_dth = a * s * z * (b / a)
    out[0, 0] = 0.0
    out[0, 1] = -kw
    out[0, 2] = 0.0
    out[1, 0] = wm
    out[1, 1] = -wm * dmu_dv
    out[1, 2] = -wm * dmu_dth
    av = abs(v)
    sg = 1.0 if v >= 0 else -1.0
    out[2, 0] = 0.0
    if law == AGING:
        out[2, 1] = -sg / dc
        out[2, 2] = -(vr / dc) * math.exp(-th)
    else:
        av = max(av, 1e-300)
        out[2, 1] = -sg * (math.log(av / vr) + th + 1.0) / dc
        out[2, 2] = -av / dc
