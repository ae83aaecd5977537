"""Validators of plain numbers, one per kind of argument, shared by every public entry point.

Each raises :class:`TypeError` for a value of the wrong type and :class:`ValueError`
for a value out of range, with the argument's name, the value and what was
expected, before anything reaches the compiled kernels (where a NaN would loop
for ever and a huge number would end in a ``SystemError`` from numba).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from ..errors import ArgumentTypeError

__all__ = [
    "ATOL_MIN",
    "MAX_STATE",
    "NU_MAX",
    "NU_MIN",
    "bound_words",
    "driving_velocity",
    "finite",
    "finite_array",
    "integer",
    "nu_outside",
    "number_pair",
    "positive",
    "refusal",
    "state",
    "tolerances",
]

#: the largest spring force or velocity accepted as a state (units of the static threshold):
#: ten times the largest driving velocity a parameter set may have (1e12), well inside the
#: range where the kernels' arithmetic stays finite
MAX_STATE = 1e13
#: the smallest dimensionless driving velocity: below it the spring-force maximum (where the
#: slip velocity passes nu) is no longer located in double precision (at nu = 1e-20 an
#: amplitude comes out 3e-4 off with status ok; subnormal values stall the compiled loop)
NU_MIN = 1e-15
#: the largest dimensionless driving velocity a parameter set may have
NU_MAX = 1e12
#: the smallest absolute tolerance: a subnormal one (1e-320) ends in step-size-too-small, which
#: reads as the friction law's fault, and below about 1e-30 a cycle's steps run out (the
#: default is 1e-12)
ATOL_MIN = 1e-30


def _real(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(f"{name}={value!r} (type {type(value).__name__}): expected a real number")
    return float(value)


def finite(name: str, value: Any, *, what: str = "a finite number", text: bool = False) -> float:
    """Return ``value`` as a float after checking that it is a real number and finite (of any sign).

    With ``text``, a string of a number (``"0.1"``, as a grid's values come from a command
    line) is read too. A value that is not a number raises ``ArgumentTypeError`` ("expected a
    number"); NaN or an infinity raises ``ValueError`` ("expected ``what``").
    """
    if text and isinstance(value, str):
        try:
            x = float(value)
        except ValueError:
            raise ArgumentTypeError(f"{name}={value!r}: expected a number") from None
    else:
        x = _real(name, value)
    if not math.isfinite(x):
        raise ValueError(f"{name}={value!r}: expected {what}")
    return x


def number_pair(value: Any, expected: str) -> tuple[float, float]:
    """Return a pair of numbers as two floats (not yet checked finite).

    A str (which iterates as its characters: '59' as (5, 9)), a scalar, or entries that
    are not numbers are the wrong type (``ArgumentTypeError``); a sequence of another length
    than two is a wrong value (``ValueError``). ``expected`` is the whole message
    (``"guess=...: expected a pair (s0, period) of numbers"``).
    """
    if (
        isinstance(value, str | bytes)
        or not isinstance(value, Sequence | np.ndarray)
        or (isinstance(value, np.ndarray) and value.ndim == 0)
    ):
        raise ArgumentTypeError(expected)
    if len(value) != 2:
        raise ValueError(expected)
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError):  # entries that are not numbers
        raise ArgumentTypeError(expected) from None
    return a, b


def refusal(x: float, *, allow_zero: bool = False) -> str | None:
    """Say why ``x`` is not a finite positive (or, with ``allow_zero``, non-negative) number.

    The words every validator puts after ``name=value``: ``"is NaN"``, ``"is infinite"``,
    ``"must be positive"`` or ``"must be non-negative"``; ``None`` for a good value.
    """
    if math.isnan(x):
        return "is NaN"
    if math.isinf(x):
        return "is infinite"
    if x < 0.0 or (x == 0.0 and not allow_zero):
        return "must be non-negative" if allow_zero else "must be positive"
    return None


def positive(name: str, value: Any, *, upper: float | None = None, what: str = "a positive number") -> float:
    """Return ``value`` as a float after checking that it is finite, positive and at most ``upper``."""
    x = _real(name, value)
    why = refusal(x)
    if why is not None:
        raise ValueError(f"{name}={value!r} {why}: expected {what}")
    if upper is not None and x > upper:
        raise ValueError(f"{name}={value!r}: expected {what}{bound_words(what, f' of at most {upper:g}')}")
    return x


def driving_velocity(name: str, value: Any) -> float:
    """Return a dimensionless driving velocity ``nu = beta v0``, checked: ``NU_MIN <= nu <= NU_MAX``."""
    x = positive(name, value, what=f"a positive driving velocity (at most {NU_MAX:g})")
    if x < NU_MIN:
        raise ValueError(
            f"{name}={value!r}: expected a driving velocity of at least {NU_MIN:g} (below it the "
            "spring-force maximum, where the slip velocity passes nu, is not resolved in double "
            "precision)"
        )
    if x > NU_MAX:
        raise ValueError(f"{name}={value!r}: expected a driving velocity of at most {NU_MAX:g}")
    return x


def nu_outside(nu: npt.ArrayLike) -> npt.NDArray[np.bool_]:
    """Return where driving velocities lie outside ``[NU_MIN, NU_MAX]`` (NaN included), elementwise."""
    a = np.asarray(nu, dtype=np.float64)
    return ~((a >= NU_MIN) & (a <= NU_MAX))


def bound_words(what: str, words: str) -> str:
    """Return ``words`` naming a bound, or nothing where ``what`` says it already ('at most 1e12')."""
    return "" if "at most" in what or "below" in what else words


def tolerances(rtol: Any, atol: Any) -> tuple[float, float]:
    """Return integration tolerances, checked: ``1e-14 <= rtol <= 1e-3``, ``ATOL_MIN <= atol <= 1``."""
    r = positive("rtol", rtol, what="a relative tolerance between 1e-14 and 1e-3")
    if not 1e-14 <= r <= 1e-3:
        raise ValueError(f"rtol={rtol!r}: expected a relative tolerance between 1e-14 and 1e-3")
    a = positive("atol", atol, upper=1.0, what="a positive absolute tolerance")
    if a < ATOL_MIN:
        raise ValueError(f"atol={atol!r}: expected an absolute tolerance between {ATOL_MIN:g} and 1")
    return r, a


def integer(name: str, value: Any, *, lo: int = 1, hi: int | None = None) -> int:
    """Return ``value`` as an int after checking that it is an integer in ``[lo, hi]``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}={value!r} (type {type(value).__name__}): expected an integer")
    n = int(value)
    if n < lo or (hi is not None and n > hi):
        raise ValueError(f"{name}={value!r}: expected an integer from {lo}" + (f" to {hi}" if hi else " up"))
    return n


def state(name: str, value: Any, bound: float = MAX_STATE) -> float:
    """Return one component of a state (spring force or velocity) after checking it is finite and bounded."""
    x = _real(name, value)
    if not math.isfinite(x) or abs(x) > bound:
        raise ValueError(f"{name}={value!r}: expected a finite value of magnitude at most {bound:g}")
    return x


def finite_array(
    name: str, value: Any, *, bound: float = MAX_STATE, positive: bool = False
) -> npt.NDArray[np.float64]:
    """Return ``value`` as a float array after checking every entry is finite (and positive) and bounded."""
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected numbers, got {type(value).__name__}") from None
    # two reductions, no temporary array (a NaN fails both comparisons): a sweep's 10^7 values
    if a.size and float(a.max()) <= bound and float(a.min()) >= (0.0 if positive else -bound):
        if not positive or float(a.min()) > 0.0:
            return a
    bad = ~np.isfinite(a) | (np.abs(a) > bound)
    if positive:
        bad |= a <= 0.0
    if bad.any():
        i = tuple(int(k) for k in np.unravel_index(int(np.argmax(bad)), a.shape)) if a.ndim else ()
        where = "[" + ", ".join(map(str, i)) + "]" if i else ""
        kind = "a positive finite value" if positive else "a finite value"
        raise ValueError(f"{name}{where}={float(a[i])!r}: expected {kind} of magnitude at most {bound:g}")
    return a
