"""Compiled friction laws in dimensionless form.

A law is an integer id and a parameter vector ``lp`` of length
:data:`N_LAW_PARAMS`. Friction is measured in units of the static friction
force, so the static threshold is 1 for every law. The functions here give the
*forward branch* ``f_+(w)``: the analytic expression valid for ``w > 0``,
continued analytically to ``w <= 0``. A slip phase in direction ``d = +1``
integrates with ``f_+(w)`` and one in direction ``d = -1`` with the odd
extension ``-f_+(-w)``; the set-valued law at ``w = 0`` is handled by the
engine, never by these functions.

Laws (see :mod:`stickslip.models.friction` for sources):

``LAW_WEAKENING`` (``lp = (c, p)``)
    ``f_+(w) = 1/(1 + c w) + p w`` (the paper's F1 for ``p = 0``, F2 otherwise).
``LAW_CUBIC`` (``lp = (alpha, gamma)``)
    ``f_+(w) = 1 - alpha w + gamma w**3`` (Thomsen and Fidlin).
``LAW_COULOMB`` (``lp = (kinetic,)``)
    ``f_+(w) = kinetic``, with ``0 <= kinetic < 1``.
"""

from __future__ import annotations

from numba import njit

LAW_WEAKENING = 0
LAW_CUBIC = 1
LAW_COULOMB = 2
N_LAW_PARAMS = 3
STATIC_THRESHOLD = 1.0


@njit(cache=True)
def f_scalar(law, p0, p1, w):  # type: ignore[no-untyped-def]
    """Return the forward-branch friction ``f_+(w)`` from scalar law parameters."""
    if law == LAW_WEAKENING:
        if w >= 0.0:
            return 1.0 / (1.0 + p0 * w) + p1 * w
        # Past a stop the slip integrator samples w < 0 before the stop is located.
        # There 1/(1 + c w) runs into its pole at w = -1/c and forces ever smaller
        # steps; its Taylor polynomial of degree 10 matches it far beyond the
        # method's order at w = 0 and has no pole.
        x = -p0 * w
        acc = 1.0
        for _ in range(10):
            acc = 1.0 + x * acc
        return acc + p1 * w
    if law == LAW_CUBIC:
        return 1.0 - p0 * w + p1 * w * w * w
    return p0


@njit(cache=True)
def friction_scalar(law, p0, p1, d, w):  # type: ignore[no-untyped-def]
    """Return the friction of a slip phase in direction ``d`` from scalar parameters."""
    if law == LAW_WEAKENING and d * w >= 0.0:
        # Same value as d * f_scalar(law, p0, p1, d * w), bit for bit (d = +-1 only
        # flips signs), but with one multiplication fewer before the division: this
        # is the latency-bound inner link of every Runge-Kutta stage.
        return d / (1.0 + (p0 * d) * w) + p1 * w
    return d * f_scalar(law, p0, p1, d * w)


@njit(cache=True)
def slip_accel(law, p0, p1, d, s, w):  # type: ignore[no-untyped-def]
    """Return ``dw/dtau = s - friction`` of a slip phase in direction ``d``.

    The same value as ``s - friction_scalar(...)`` (so that, e.g., steady sliding
    stays an exact fixed point), but for the weakening law with ``p1 = 0`` the
    addition of ``p1 * w = 0`` is skipped: the division is the slowest link of
    the chain of dependent operations from one Runge-Kutta stage to the next, and
    every operation after it lengthens that chain.
    """
    if law == LAW_WEAKENING and d * w >= 0.0:
        fr = d / (1.0 + (p0 * d) * w)
        if p1 != 0.0:
            fr += p1 * w
        return s - fr
    return s - friction_scalar(law, p0, p1, d, w)


@njit(cache=True, inline="always")
def f_branch(law, lp, w):  # type: ignore[no-untyped-def]
    """Return the forward-branch friction ``f_+(w)`` (units of static friction)."""
    return f_scalar(law, lp[0], lp[1], w)


@njit(cache=True, inline="always")
def df_branch(law, lp, w):  # type: ignore[no-untyped-def]
    """Return ``d f_+ / d w`` of the forward branch (for ``w >= 0``)."""
    if law == LAW_WEAKENING:
        q = 1.0 + lp[0] * w
        return -lp[0] / (q * q) + lp[1]
    if law == LAW_CUBIC:
        return -lp[0] + 3.0 * lp[1] * w * w
    return 0.0


@njit(cache=True, inline="always")
def friction(law, lp, d, w):  # type: ignore[no-untyped-def]
    """Return the friction of a slip phase in direction ``d`` (+1 or -1) at velocity ``w``."""
    return friction_scalar(law, lp[0], lp[1], d, w)
