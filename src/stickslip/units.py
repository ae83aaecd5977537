"""Units: one pint registry for the package and validation of physical inputs.

Every physical argument may be a :class:`pint.Quantity` or a string such as
``"196 mN"`` or ``"5 um/s"``. Plain numbers are refused for physical
arguments: a bare ``5`` could be metres or micrometres, and guessing is how
silently wrong answers are made.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np
import pint

from .core.checks import bound_words, refusal
from .errors import ArgumentTypeError

ureg: pint.UnitRegistry = pint.UnitRegistry()
Q_ = ureg.Quantity

QuantityLike = pint.Quantity | str

__all__ = [
    "FORCE_UNITS",
    "Q_",
    "VELOCITY_UNITS",
    "QuantityLike",
    "check_count",
    "check_number",
    "check_seed",
    "format_speed",
    "parse_quantity",
    "readable_unit",
    "ureg",
]


#: units values are shown in, smallest first, with their size in SI
VELOCITY_UNITS = (("um/s", 1e-6), ("mm/s", 1e-3), ("m/s", 1.0))
FORCE_UNITS = (("mN", 1e-3), ("N", 1.0))


def readable_unit(values: Any, units: Sequence[tuple[str, float]]) -> tuple[str, float]:
    """Return the unit (and its size in SI) that shows typical ``values`` (SI) best.

    The largest of ``units`` not larger than the median magnitude of the finite, nonzero
    values: 100 um/s, not 0.0001 m/s; the smallest where there are none.

    >>> readable_unit([2e-5, 5e-4], VELOCITY_UNITS)
    ('um/s', 1e-06)
    """
    v = np.abs(np.asarray(values, dtype=float).ravel())
    v = v[np.isfinite(v) & (v > 0)]
    typical = float(np.median(v)) if v.size else 0.0
    fitting = [u for u in units if typical >= u[1]]
    return fitting[-1] if fitting else units[0]


def format_speed(v: float, digits: int = 4) -> str:
    """Write a speed given in m/s in the unit that reads best: ``300 um/s``, ``7.143 mm/s``, ``2 m/s``.

    >>> format_speed(3e-4)
    '300 um/s'
    """
    unit, size = readable_unit([v], VELOCITY_UNITS) if math.isfinite(v) and v != 0 else ("m/s", 1.0)
    return f"{v / size:.{digits}g} {unit}"


def parse_quantity(
    value: Any,
    name: str,
    dimension: str,
    example: str,
    *,
    allow_zero: bool = False,
    allow_negative: bool = False,
) -> pint.Quantity:
    """Return ``value`` as a validated pint quantity of the given dimension.

    Parameters
    ----------
    value : pint.Quantity or str
        The user's input, for instance ``"62 N/m"``.
    name : str
        The argument's name, used in error messages.
    dimension : str
        A pint dimensionality such as ``"[mass]"`` or ``"[length] / [time]"``.
    example : str
        An example of a valid value, used in error messages (``"1 kg"``).
    allow_zero : bool, optional
        Accept zero (default: only strictly positive values).
    allow_negative : bool, optional
        Accept any finite value (the caller checks the bounds).

    Returns
    -------
    pint.Quantity
        The quantity, in the registry of this package.

    Raises
    ------
    ArgumentTypeError
        If the value is neither a quantity nor a string (a plain number, ``None``, a
        list) or is a quantity of more than one number.
    ValueError
        If a string is not a quantity, or the value has no unit, has the wrong
        dimension, or is NaN, infinite, negative or (unless ``allow_zero``) zero.

    """
    if isinstance(value, bool) or value is None:
        raise ArgumentTypeError(f"{name}={value!r}: expected a quantity with units such as {example!r}")
    if isinstance(value, int | float):
        raise ArgumentTypeError(
            f"{name}={value!r} has no unit: expected a quantity such as {example!r} (dimension {dimension})"
        )
    if isinstance(value, str):
        q: Any = _parse_string(value, name, example)
    elif isinstance(value, pint.Quantity):
        try:
            q = ureg.Quantity(value.magnitude, str(value.units))
        except Exception as exc:
            raise ValueError(f"{name}={value!r}: unusable unit ({exc})") from None
    else:
        raise ArgumentTypeError(
            f"{name}={value!r} (type {type(value).__name__}): expected a pint Quantity "
            f"or a string such as {example!r}"
        )
    if not isinstance(q, pint.Quantity) or (q.dimensionless and dimension != "[]"):
        raise ValueError(
            f"{name}={value!r} has no unit: expected a quantity such as {example!r} (dimension {dimension})"
        )
    if not q.check(dimension):
        raise ValueError(
            f"{name}={value!r} has dimension {q.dimensionality}, expected {dimension} "
            f"(for example {example!r})"
        )
    mag = q.magnitude
    try:
        x = float(mag)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}={value!r}: expected a single number with a unit") from None
    if allow_negative and math.isfinite(x):
        return q
    _check_finite_sign(name, value, x, allow_zero, f"a quantity such as {example!r}")
    return q


_NUMBER = re.compile(
    r"^\s*([+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|nan|inf|infinity))(?:\s+|(?=[^\d.,\s])|$)(.*?)\s*$",
    re.IGNORECASE,
)


def _parse_string(value: str, name: str, example: str) -> Any:
    """Parse exactly one number followed by a unit (no expressions, no lists).

    pint alone would evaluate ``"5,5 um/s"`` as 55 um/s and ``"5 6 um/s"`` as
    30 um/s; a decimal comma or a second number must be an error instead.
    """
    text = value.strip()
    m = _NUMBER.match(text)
    bad = (
        m is None
        or "," in text
        or (re.match(r"^[\d.(\[]", m.group(2)) is not None and not m.group(2).startswith("1/"))
    )
    if bad or m is None:
        if re.fullmatch(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?", text):
            raise ValueError(f"{name}={value!r} has no unit: expected a quantity such as {example!r}")
        raise ValueError(
            f"{name}={value!r} is not a quantity: expected one number (with a decimal point, not "
            f"a comma) followed by a unit, such as {example!r}"
        )
    number, unit = m.group(1), m.group(2)
    if re.match(r"[eE](\s|$)", text[len(number) :]):  # '5e um/s': not 5 elementary charges um/s
        raise ValueError(
            f"{name}={value!r}: {number}{text[len(number)]!s} is a number's exponent without its digits; "
            f"write the exponent (5e-6 m/s) or the unit's prefix (5 um/s), such as {example!r}"
        )
    if unit.lstrip().startswith("/"):  # '1/mm': the number, then a reciprocal unit
        unit = "1" + unit.lstrip()
    try:
        u = ureg.Unit(unit) if unit else ureg.dimensionless
    except Exception as exc:  # pint raises several unrelated exception types
        raise ValueError(
            f"{name}={value!r} is not a quantity pint understands "
            f"({type(exc).__name__}: {exc}); expected something like {example!r}"
        ) from None
    return ureg.Quantity(float(number), u)


def check_number(
    value: Any,
    name: str,
    *,
    allow_zero: bool = False,
    upper: float | None = None,
    upper_inclusive: bool = False,
    what: str = "a positive number",
) -> float:
    """Return ``value`` as a float after checking that it is finite and positive.

    Parameters
    ----------
    value : float
        The user's input (dimensionless).
    name : str
        The argument's name, used in error messages.
    allow_zero : bool, optional
        Accept zero.
    upper : float, optional
        An upper bound.
    upper_inclusive : bool, optional
        Whether ``upper`` itself is allowed.
    what : str, optional
        Description of what is expected, for the error message.

    Raises
    ------
    ArgumentTypeError
        If the value is not a real number (a string, ``None``, a list).
    ValueError
        If the value is NaN or infinite, out of range, or a quantity with units.

    """
    if isinstance(value, pint.Quantity):
        if not value.dimensionless:
            raise ValueError(f"{name}={value!r}: expected a dimensionless number, got units {value.units}")
        value = value.to("").magnitude
    if isinstance(value, bool) or not isinstance(value, int | float):
        try:
            import numpy as np

            if isinstance(value, np.floating | np.integer):
                value = float(value)
            else:
                raise TypeError
        except TypeError:
            raise ArgumentTypeError(f"{name}={value!r}: expected {what}") from None
    x = float(value)
    _check_finite_sign(name, value, x, allow_zero, what)
    if upper is not None and (x > upper or (x == upper and not upper_inclusive)):
        rel = "<=" if upper_inclusive else "<"
        raise ValueError(f"{name}={value!r}: expected {what}{bound_words(what, f' {rel} {upper:g}')}")
    return x


def check_count(value: Any, name: str, *, minimum: int = 1, what: str = "") -> int:
    """Return ``value`` as an int after checking that it is a whole number >= ``minimum``.

    A float, even a whole one, is refused: ``events=2.7`` once ran 2 events.

    Raises
    ------
    ArgumentTypeError
        If the value is not an integer (a float, a string, ``None``), naming ``name``.
    ValueError
        If it is below ``minimum``, naming ``name``, the value and what was expected.

    """
    import numpy as np

    expected = f"{what or 'a whole number'} >= {minimum}"
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ArgumentTypeError(f"{name}={value!r}: expected {expected}")
    if value < minimum:
        raise ValueError(f"{name}={value!r}: expected {expected}")
    return int(value)


def check_seed(seed: Any, name: str = "seed") -> int | None:
    """Return a random seed (None or a whole number >= 0); an error naming ``name`` otherwise."""
    if seed is None:
        return None
    return check_count(seed, name, minimum=0, what="None or a whole-number seed")


def _check_finite_sign(name: str, shown: Any, x: float, allow_zero: bool, what: str) -> None:
    why = refusal(x, allow_zero=allow_zero)
    if why is not None:
        raise ValueError(f"{name}={shown!r} {why}: expected {what}")
