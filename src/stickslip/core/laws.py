"""Compiled friction laws in dimensionless form: the built-in laws' kernels.

A law is an integer id and a parameter vector ``lp`` of length
:data:`N_LAW_PARAMS`; the hot loops pass the vector as a tuple ``P``
(:func:`params`), so no array crosses a call and the signature of every kernel
is the same for a law of one parameter or of eight. Friction is measured in
units of the static friction force, so the static threshold is 1 for every law.
The functions here give the *forward branch* ``f_+(w)``: the expression valid
for ``w > 0``, continued to ``w <= 0`` without a pole (the integrator samples
slightly negative ``w`` before it locates a stop). A slip phase in direction
``d = +1`` integrates with ``f_+(w)`` and one in direction ``d = -1`` with the
odd extension ``-f_+(-w)``; the set-valued law at ``w = 0`` is handled by the
engine, never by these functions.

Laws declared in :mod:`stickslip.laws` without an id here (a user's expression
or table, a law registered by a test) get a module of the same functions,
generated from their declaration, and a copy of the engine compiled with it
(:mod:`stickslip.laws.compiler`): every function below keeps its signature in
that module, with the ``law`` argument unused.

Laws (see :mod:`stickslip.laws` for sources):

``LAW_WEAKENING`` (``P = (c, p, ...)``)
    ``f_+(w) = 1/(1 + c w) + p w`` (the paper's F1 for ``p = 0``, F2 otherwise).
``LAW_CUBIC`` (``P = (alpha, gamma, ...)``)
    ``f_+(w) = 1 - alpha w + gamma w**3`` (Thomsen and Fidlin).
``LAW_COULOMB`` (``P = (kinetic, ...)``)
    ``f_+(w) = kinetic``, with ``0 <= kinetic < 1``.
``LAW_CARLSON_LANGER`` (``P = (alpha, sigma, ...)``)
    ``f_+(w) = (1 - sigma) / (1 + 2 alpha w / (1 - sigma))`` (Carlson and Langer):
    a drop ``sigma`` at the onset of slip, then weakening.
"""

from __future__ import annotations

from numba import njit

LAW_WEAKENING = 0
LAW_CUBIC = 1
LAW_COULOMB = 2
LAW_CARLSON_LANGER = 3
#: ids of the laws compiled into this module
BUILTIN_LAWS = (LAW_WEAKENING, LAW_CUBIC, LAW_COULOMB, LAW_CARLSON_LANGER)
#: length of a law's parameter vector (unused entries are 0)
N_LAW_PARAMS = 8
STATIC_THRESHOLD = 1.0


@njit(cache=True, inline="always")
def params(lp):  # type: ignore[no-untyped-def]
    """Return the parameter vector ``lp`` (an array of :data:`N_LAW_PARAMS`) as a tuple."""
    return (lp[0], lp[1], lp[2], lp[3], lp[4], lp[5], lp[6], lp[7])


@njit(cache=True)
def f_plus(law, P, w):  # type: ignore[no-untyped-def]
    """Return the forward-branch friction ``f_+(w)`` (units of static friction)."""
    if law == LAW_WEAKENING:
        if w >= 0.0:
            return 1.0 / (1.0 + P[0] * w) + P[1] * w
        # Past a stop the slip integrator samples w < 0 before the stop is located.
        # There 1/(1 + c w) runs into its pole at w = -1/c and forces ever smaller
        # steps; its Taylor polynomial of degree 10 matches it far beyond the
        # method's order at w = 0 and has no pole.
        x = -P[0] * w
        acc = 1.0
        for _ in range(10):
            acc = 1.0 + x * acc
        return acc + P[1] * w
    if law == LAW_CUBIC:
        return 1.0 - P[0] * w + P[1] * w * w * w
    if law == LAW_CARLSON_LANGER:
        r = 1.0 - P[1]
        if w >= 0.0:
            return r / (1.0 + 2.0 * P[0] * w / r)
        # no pole past a stop: the Taylor polynomial of degree 10, as for the weakening law
        x = -2.0 * P[0] * w / r
        acc = 1.0
        for _ in range(10):
            acc = 1.0 + x * acc
        return r * acc
    return P[0]


@njit(cache=True)
def df_plus(law, P, w):  # type: ignore[no-untyped-def]
    """Return ``d f_+ / d w`` of the forward branch (for ``w >= 0``)."""
    if law == LAW_WEAKENING:
        q = 1.0 + P[0] * w
        return -P[0] / (q * q) + P[1]
    if law == LAW_CUBIC:
        return -P[0] + 3.0 * P[1] * w * w
    if law == LAW_CARLSON_LANGER:
        q = 1.0 + 2.0 * P[0] * w / (1.0 - P[1])
        return -2.0 * P[0] / (q * q)
    return 0.0


@njit(cache=True)
def friction_scalar(law, P, d, w):  # type: ignore[no-untyped-def]
    """Return the friction of a slip phase in direction ``d`` (+1 or -1) at velocity ``w``."""
    if law == LAW_WEAKENING and d * w >= 0.0:
        # Same value as d * f_plus(law, P, d * w), bit for bit (d = +-1 only flips
        # signs), but with one multiplication fewer before the division: this is
        # the latency-bound inner link of every Runge-Kutta stage.
        return d / (1.0 + (P[0] * d) * w) + P[1] * w
    return d * f_plus(law, P, d * w)


@njit(cache=True)
def slip_accel(law, P, d, s, w):  # type: ignore[no-untyped-def]
    """Return ``dw/dtau = s - friction`` of a slip phase in direction ``d``.

    The same value as ``s - friction_scalar(...)`` (so that, e.g., steady sliding
    stays an exact fixed point), but for the weakening law with ``P[1] = 0`` the
    addition of ``P[1] * w = 0`` is skipped: the division is the slowest link of
    the chain of dependent operations from one Runge-Kutta stage to the next, and
    every operation after it lengthens that chain.
    """
    if law == LAW_WEAKENING and d * w >= 0.0:
        fr = d / (1.0 + (P[0] * d) * w)
        if P[1] != 0.0:
            fr += P[1] * w
        return s - fr
    return s - friction_scalar(law, P, d, w)
