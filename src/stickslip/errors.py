"""The exception of an argument of the wrong type: :class:`ArgumentTypeError`.

The rule of the whole API: an argument of the wrong type (a string where only numbers are
accepted, ``None``, a list where one value is expected, an object of the wrong class)
raises :class:`ArgumentTypeError`; an argument of the right type with a wrong value (NaN,
negative, out of bounds, a quantity of the wrong dimension, a text that is not a quantity,
an unknown name) raises :class:`ValueError`. A string is the right type wherever a quantity
may be given as text (``"5 um/s"``).

Imports nothing, so every layer (the numeric core too) may raise it.
"""

from __future__ import annotations

__all__ = ["ArgumentTypeError"]


class ArgumentTypeError(TypeError, ValueError):
    """An argument of the wrong type; the message names the argument, its type and what was expected.

    A :class:`TypeError`, so ``except TypeError`` catches every wrong type; and a
    :class:`ValueError`, so code that catches bad arguments with ``except ValueError`` (the
    command line, a script) catches it as well. NumPy's ``AxisError(ValueError, IndexError)``
    is built the same way.

    >>> import stickslip
    >>> try:
    ...     stickslip.WeakeningLaw(c="3")
    ... except TypeError as exc:
    ...     print(isinstance(exc, ValueError), exc)
    True c='3': expected a positive number
    """
