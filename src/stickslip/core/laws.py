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


# ---- each law's functions ---------------------------------------------------------
# Each takes the (unused) law id first, so that it can stand in for the dispatching
# function of the same role: a law's own engine (:mod:`stickslip.laws.compiler`)
# imports them under the names ``f_plus``, ``df_plus``, ``friction_scalar`` and
# ``slip_accel`` and is compiled with that one law only.


@njit(cache=True)
def _taylor_pole(x):  # type: ignore[no-untyped-def]
    """Return ``sum(x**k, k = 0..10)``: ``1/(1 - x)`` without its pole (Horner)."""
    acc = 1.0
    for _ in range(10):
        acc = 1.0 + x * acc
    return acc


@njit(cache=True)
def weakening_f(law, P, w):  # type: ignore[no-untyped-def]
    """``f_+(w) = 1/(1 + c w) + p w`` (``P = (c, p, ...)``)."""
    if w >= 0.0:
        return 1.0 / (1.0 + P[0] * w) + P[1] * w
    # Past a stop the slip integrator samples w < 0 before the stop is located.
    # There 1/(1 + c w) runs into its pole at w = -1/c and forces ever smaller
    # steps; its Taylor polynomial of degree 10 matches it far beyond the
    # method's order at w = 0 and has no pole.
    return _taylor_pole(-P[0] * w) + P[1] * w


@njit(cache=True)
def weakening_df(law, P, w):  # type: ignore[no-untyped-def]
    """``d f_+ / d w`` of the weakening law (for ``w >= 0``)."""
    q = 1.0 + P[0] * w
    return -P[0] / (q * q) + P[1]


@njit(cache=True)
def weakening_friction(law, P, d, w):  # type: ignore[no-untyped-def]
    """Friction of the weakening law in a slip phase in direction ``d`` at velocity ``w``."""
    if d * w >= 0.0:
        # Same value as d * f_plus(law, P, d * w), bit for bit (d = +-1 only flips
        # signs), but with one multiplication fewer before the division: this is
        # the latency-bound inner link of every Runge-Kutta stage.
        return d / (1.0 + (P[0] * d) * w) + P[1] * w
    return d * weakening_f(law, P, d * w)


@njit(cache=True)
def weakening_accel(law, P, d, s, w):  # type: ignore[no-untyped-def]
    """``dw/dtau = s - friction`` of the weakening law (see :func:`slip_accel`)."""
    if d * w >= 0.0:
        fr = d / (1.0 + (P[0] * d) * w)
        if P[1] != 0.0:
            fr += P[1] * w
        return s - fr
    return s - weakening_friction(law, P, d, w)


@njit(cache=True)
def cubic_f(law, P, w):  # type: ignore[no-untyped-def]
    """``f_+(w) = 1 - alpha w + gamma w**3`` (``P = (alpha, gamma, ...)``)."""
    return 1.0 - P[0] * w + P[1] * w * w * w


@njit(cache=True)
def cubic_df(law, P, w):  # type: ignore[no-untyped-def]
    """``d f_+ / d w`` of the cubic law."""
    return -P[0] + 3.0 * P[1] * w * w


@njit(cache=True)
def coulomb_f(law, P, w):  # type: ignore[no-untyped-def]
    """``f_+(w) = kinetic`` (``P = (kinetic, ...)``)."""
    return P[0]


@njit(cache=True)
def coulomb_df(law, P, w):  # type: ignore[no-untyped-def]
    """``d f_+ / d w = 0`` of the Coulomb law."""
    return 0.0


@njit(cache=True)
def carlson_langer_f(law, P, w):  # type: ignore[no-untyped-def]
    """``f_+(w) = (1 - sigma) / (1 + 2 alpha w / (1 - sigma))`` (``P = (alpha, sigma, ...)``)."""
    r = 1.0 - P[1]
    if w >= 0.0:
        return r / (1.0 + 2.0 * P[0] * w / r)
    # no pole past a stop: the Taylor polynomial of degree 10, as for the weakening law
    return r * _taylor_pole(-2.0 * P[0] * w / r)


@njit(cache=True)
def carlson_langer_df(law, P, w):  # type: ignore[no-untyped-def]
    """``d f_+ / d w`` of the Carlson-Langer law (for ``w >= 0``)."""
    q = 1.0 + 2.0 * P[0] * w / (1.0 - P[1])
    return -2.0 * P[0] / (q * q)


#: name of each built-in law's functions in this module (``<prefix>_f`` and ``<prefix>_df``;
#: the weakening law also has ``_friction`` and ``_accel``)
LAW_PREFIX = {
    LAW_WEAKENING: "weakening",
    LAW_CUBIC: "cubic",
    LAW_COULOMB: "coulomb",
    LAW_CARLSON_LANGER: "carlson_langer",
}


# ---- the built-in laws by id ------------------------------------------------------


@njit(cache=True)
def f_plus(law, P, w):  # type: ignore[no-untyped-def]
    """Return the forward-branch friction ``f_+(w)`` (units of static friction)."""
    if law == LAW_WEAKENING:
        return weakening_f(law, P, w)
    if law == LAW_CUBIC:
        return cubic_f(law, P, w)
    if law == LAW_CARLSON_LANGER:
        return carlson_langer_f(law, P, w)
    return coulomb_f(law, P, w)


@njit(cache=True)
def df_plus(law, P, w):  # type: ignore[no-untyped-def]
    """Return ``d f_+ / d w`` of the forward branch (for ``w >= 0``)."""
    if law == LAW_WEAKENING:
        return weakening_df(law, P, w)
    if law == LAW_CUBIC:
        return cubic_df(law, P, w)
    if law == LAW_CARLSON_LANGER:
        return carlson_langer_df(law, P, w)
    return coulomb_df(law, P, w)


@njit(cache=True)
def friction_scalar(law, P, d, w):  # type: ignore[no-untyped-def]
    """Return the friction of a slip phase in direction ``d`` (+1 or -1) at velocity ``w``."""
    if law == LAW_WEAKENING:
        return weakening_friction(law, P, d, w)
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
    if law == LAW_WEAKENING:
        return weakening_accel(law, P, d, s, w)
    return s - friction_scalar(law, P, d, w)
