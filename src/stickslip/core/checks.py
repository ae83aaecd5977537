"""Validators of plain numbers, one per kind of argument, shared by every public entry point.

Each raises :class:`TypeError` for a value of the wrong type and :class:`ValueError`
for a value out of range, with the argument's name, the value and what was
expected, before anything reaches the compiled kernels (where a NaN would loop
for ever and a huge number would end in a ``SystemError`` from numba).
"""

from __future__ import annotations

import math
import numbers
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
    "finite_array",
    "integer",
    "positive",
    "state",
    "tolerances",
]

#: the largest spring force or velocity accepted as a state (units of the static threshold):
#: ten times the largest driving velocity a parameter set may have (1e12), well inside the
#: range where the kernels' arithmetic stays finite
MAX_STATE = 1e13
#: the smallest dimensionless driving velocity: below it the spring-force maximum (where the
#: slip velocity passes nu) is no longer located in double precision (at nu = 1e-20 an
#: amplitude came out 3e-4 off with status ok; subnormal values hung the compiled loop)
NU_MIN = 1e-15
#: the largest dimensionless driving velocity a parameter set may have
NU_MAX = 1e12
#: the smallest absolute tolerance: a subnormal one (1e-320) ended in step-size-too-small, blaming
#: the friction law, and below about 1e-30 a cycle's steps run out (the default is 1e-12)
ATOL_MIN = 1e-30


def _real(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(f"{name}={value!r} (type {type(value).__name__}): expected a real number")
    return float(value)


def positive(name: str, value: Any, *, upper: float | None = None, what: str = "a positive number") -> float:
    """Return ``value`` as a float after checking that it is finite, positive and at most ``upper``."""
    x = _real(name, value)
    if math.isnan(x):
        raise ValueError(f"{name}={value!r} is NaN: expected {what}")
    if not math.isfinite(x) or x <= 0.0:
        raise ValueError(f"{name}={value!r}: expected {what}")
    if upper is not None and x > upper:
        raise ValueError(f"{name}={value!r}: expected {what}{bound_words(what, f' of at most {upper:g}')}")
    return x


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
