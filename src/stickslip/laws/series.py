"""Taylor coefficients of a formula by series arithmetic, not by repeated differentiation.

A formula's ``n``-th derivative built by sympy's ``diff`` grows with every order: a
nested ``exp(sin(exp(sin(w))))`` has 82 000 operations in its eighth derivative and
took minutes for the tenth. The truncated Taylor series of each node of the formula
follows from its arguments' series by the recurrences of automatic differentiation in
Taylor mode (Griewank & Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008, ch. 13):
``n`` coefficients cost ``O(n^2)`` operations a node, whatever the nesting.

Two kinds of coefficient are used:

* sympy expressions (:func:`taylor`): the coefficients at ``w = 0`` in the law's
  parameters, for the continuation of a formula to ``w < 0`` that is compiled into
  its kernel; a coefficient free of parameters is kept as a 30-digit float, so
  numbers never swell into nested exact expressions;
* numpy arrays (:func:`derivatives`): ``f^(k)(w)`` at given velocities and parameter
  values, for the analyses that need the second and third derivatives.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt
import sympy as sp

__all__ = ["Unsupported", "derivatives", "distinct_nodes", "node_count", "taylor"]

FloatArray = npt.NDArray[np.float64]
#: digits of a coefficient free of parameters (a double needs 17)
DIGITS = 30


class Unsupported(Exception):
    """A node the series arithmetic has no rule for (the caller differentiates instead)."""


def distinct_nodes(expr: sp.Basic) -> Iterator[sp.Basic]:
    """Yield each distinct node of ``expr`` once (shared subtrees once), without recursion.

    The tree of a derivative or a Taylor coefficient shares its subtrees; walked as a
    tree it can be exponentially larger than the code that evaluates it with common
    subexpressions.
    """
    seen: set[int] = set()
    stack = [expr]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        yield node
        stack.extend(node.args)


def node_count(expr: sp.Basic, limit: int | None = None) -> int:
    """Return the number of distinct nodes of ``expr`` (:func:`distinct_nodes`), up to ``limit``."""
    count = 0
    for _ in distinct_nodes(expr):
        count += 1
        if limit is not None and count > limit:
            break
    return count


def _sym(x: Any) -> sp.Expr:
    return x.e if isinstance(x, _Sym) else sp.sympify(x)


class _Sym:
    """A sympy coefficient whose sums and products skip sympy's automatic evaluation.

    sympy's ``Mul`` and ``Add`` ask the assumptions of their arguments (zero? finite?
    commutative?) at every product: 99 % of the time of the series of a formula nested
    25 deep in a parameter. Here zeros and ones are dropped, numbers combined, and the
    rest is kept as it stands.
    """

    __slots__ = ("e",)

    def __init__(self, e: Any) -> None:
        self.e: sp.Expr = _sym(e)

    @classmethod
    def number(cls, e: sp.Expr) -> _Sym:
        """``e`` free of symbols (``sin(1)``, ``sqrt(2)``, ``pi``) as a float of :data:`DIGITS` digits."""
        if not e.is_Number:
            value = e.evalf(DIGITS)
            e = value if value.is_Number else e
        return cls(e)

    def __add__(self, other: Any) -> _Sym:
        a, b = self.e, _sym(other)
        if a == 0:
            return _Sym(b)
        if b == 0:
            return self
        if a.is_Number and b.is_Number:
            return _Sym(a + b)
        return _Sym(sp.Add(a, b, evaluate=False))

    __radd__ = __add__

    def __neg__(self) -> _Sym:
        return _Sym(-self.e) if self.e.is_Number else _Sym(sp.Mul(sp.S.NegativeOne, self.e, evaluate=False))

    def __sub__(self, other: Any) -> _Sym:
        return self + (-_Sym(other))

    def __rsub__(self, other: Any) -> _Sym:
        return _Sym(other) + (-self)

    def __mul__(self, other: Any) -> _Sym:
        a, b = self.e, _sym(other)
        if a == 0 or b == 0:
            return _Sym(sp.S.Zero)
        if a == 1:
            return _Sym(b)
        if b == 1:
            return self
        if a.is_Number and b.is_Number:
            return _Sym(a * b)
        return _Sym(sp.Mul(a, b, evaluate=False))

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> _Sym:
        b = _sym(other)
        if b.is_Number:
            return self * (1 / b)
        return self * _Sym(sp.Pow(b, -1, evaluate=False))

    def __rtruediv__(self, other: Any) -> _Sym:
        return _Sym(other) / self

    def __pow__(self, p: Any) -> _Sym:
        a, q = self.e, _sym(p)
        if a.is_Number and q.is_Number:
            return _Sym.number(a**q)
        return _Sym(sp.Pow(a, q, evaluate=False))

    def __eq__(self, other: object) -> bool:
        return bool(self.e == _sym(other))

    def __hash__(self) -> int:
        return hash(self.e)


def _applied(f: Any, x: _Sym) -> _Sym:
    """``f(x)``, a number where ``x`` is one (``sin(1)`` as a float)."""
    return _Sym.number(f(x.e)) if x.e.is_Number else _Sym(f(x.e))


class _Algebra:
    """The operations a coefficient needs: sympy's (symbolic) or numpy's (numeric)."""

    def __init__(self, symbolic: bool) -> None:
        self.symbolic = symbolic
        if symbolic:
            self.fn: dict[Any, Callable[[Any], Any]] = {
                f: functools.partial(_applied, f)
                for f in (sp.exp, sp.log, sp.sin, sp.cos, sp.sinh, sp.cosh, sp.atan, sp.asinh, sp.erf)
            }
        else:
            from scipy.special import erf

            self.fn = {
                sp.exp: np.exp,
                sp.log: np.log,
                sp.sin: np.sin,
                sp.cos: np.cos,
                sp.sinh: np.sinh,
                sp.cosh: np.cosh,
                sp.atan: np.arctan,
                sp.asinh: np.arcsinh,
                sp.erf: erf,
            }

    def power(self, x: Any, p: Any) -> Any:
        return x**p

    def sign(self, x: Any) -> Any:
        return _Sym(sp.sign(x.e)) if self.symbolic else np.sign(x)

    def is_zero(self, x: Any) -> bool:
        return bool(self.symbolic and x == 0)


class _Series:
    """Taylor coefficients of the formula's nodes about one point, ``n`` of each."""

    def __init__(
        self, var: sp.Symbol, n: int, algebra: _Algebra, at: Any, values: Mapping[sp.Symbol, Any]
    ) -> None:
        self.var, self.n, self.a = var, n, algebra
        self.at, self.values = at, values
        self.memo: dict[sp.Basic, list[Any]] = {}
        self.zero: Any = _Sym(0) if algebra.symbolic else 0.0
        self.one: Any = _Sym(1) if algebra.symbolic else 1.0

    # ---- series of the nodes -------------------------------------------------
    def of(self, expr: sp.Basic) -> list[Any]:
        got = self.memo.get(expr)
        if got is None:
            got = self.memo[expr] = self._of(expr)
        return got

    def _const(self, c: Any) -> list[Any]:
        return [c] + [self.zero] * (self.n - 1)

    def _of(self, e: sp.Basic) -> list[Any]:
        if e == self.var:
            return [self.at, self.one] + [self.zero] * (self.n - 2)
        if not e.has(self.var):
            if self.a.symbolic:
                return self._const(_Sym.number(e) if not e.free_symbols else _Sym(e))
            if e.is_Symbol:
                return self._const(self.values[e])
            if e.is_Number or e.is_NumberSymbol:
                return self._const(float(e))
        if isinstance(e, sp.Add):
            out = self.of(e.args[0])
            for t in e.args[1:]:
                s = self.of(t)
                out = [x + y for x, y in zip(out, s, strict=True)]
            return out
        if isinstance(e, sp.Mul):
            out = self.of(e.args[0])
            for t in e.args[1:]:
                out = self._mul(out, self.of(t))
            return out
        if isinstance(e, sp.Pow):
            return self._pow(e)
        if isinstance(e, sp.Abs):
            return self._abs(self.of(e.args[0]))
        if len(e.args) == 1 and type(e) in (sp.tan, sp.tanh):
            a = self.of(e.args[0])
            even, odd = (sp.cos, sp.sin) if isinstance(e, sp.tan) else (sp.cosh, sp.sinh)
            s, c = self._pair(a, odd, even)
            return self._div(s, c)
        if len(e.args) == 1 and type(e) in self.a.fn:
            return self._function(type(e), self.of(e.args[0]))
        raise Unsupported(type(e).__name__)

    # ---- the recurrences ----------------------------------------------------
    def _mul(self, a: list[Any], b: list[Any]) -> list[Any]:
        return [sum((a[j] * b[k - j] for j in range(k + 1)), self.zero) for k in range(self.n)]

    def _div(self, a: list[Any], b: list[Any]) -> list[Any]:
        c: list[Any] = []
        for k in range(self.n):
            c.append((a[k] - sum((b[j] * c[k - j] for j in range(1, k + 1)), self.zero)) / b[0])
        return c

    def _pow(self, e: sp.Pow) -> list[Any]:
        base, exp = e.args
        if exp.has(self.var):  # a**b = exp(b log a)
            return self._function(sp.exp, self._mul(self.of(exp), self._function(sp.log, self.of(base))))
        a = self.of(base)
        if exp.is_Integer and int(exp) >= 0:  # a0 may be zero: products
            out = self._const(self.one)
            square, k = a, int(exp)
            while k:
                if k & 1:
                    out = self._mul(out, square)
                k >>= 1
                if k:
                    square = self._mul(square, square)
            return out
        p = _Sym(exp) if self.a.symbolic else self.of(exp)[0]
        if self.a.is_zero(a[0]):
            raise Unsupported("a fractional or negative power of a series that starts at zero")
        b = [self.a.power(a[0], p)]
        for k in range(1, self.n):
            b.append(
                sum(((p * j - (k - j)) * a[j] * b[k - j] for j in range(1, k + 1)), self.zero) / (k * a[0])
            )
        return b

    def _abs(self, a: list[Any]) -> list[Any]:
        lead = next((c for c in a if not self.a.is_zero(c)), None)
        if lead is None:
            return a
        s = self.a.sign(lead)
        return [s * c for c in a]

    def _pair(self, a: list[Any], odd: Any, even: Any) -> tuple[list[Any], list[Any]]:
        """Series of ``odd(a)`` and ``even(a)``: sin and cos (or sinh and cosh) together."""
        f = self.a.fn
        s, c = [f[odd](a[0])], [f[even](a[0])]
        sign = -1 if odd is sp.sin else 1
        for k in range(1, self.n):
            s.append(sum((j * a[j] * c[k - j] for j in range(1, k + 1)), self.zero) / k)
            c.append(sign * sum((j * a[j] * s[k - j] for j in range(1, k + 1)), self.zero) / k)
        return s, c

    def _function(self, kind: Any, a: list[Any]) -> list[Any]:
        f = self.a.fn
        if kind is sp.exp:
            b = [f[sp.exp](a[0])]
            for k in range(1, self.n):
                b.append(sum((j * a[j] * b[k - j] for j in range(1, k + 1)), self.zero) / k)
            return b
        if kind is sp.log:
            if self.a.is_zero(a[0]):
                raise Unsupported("log of a series that starts at zero")
            b = [f[sp.log](a[0])]
            for k in range(1, self.n):
                b.append((a[k] - sum((j * b[j] * a[k - j] for j in range(1, k)), self.zero) / k) / a[0])
            return b
        if kind in (sp.sin, sp.cos, sp.sinh, sp.cosh):
            odd, even = (sp.sin, sp.cos) if kind in (sp.sin, sp.cos) else (sp.sinh, sp.cosh)
            s, c = self._pair(a, odd, even)
            return s if kind is odd else c
        # atan, asinh, erf: b' = h(a) a', with h a series of its own
        one = self._const(self.one)
        square = self._mul(a, a)
        if kind is sp.atan:
            h = self._div(one, [x + y for x, y in zip(one, square, strict=True)])
        elif kind is sp.asinh:
            h = self._inverse_sqrt([x + y for x, y in zip(one, square, strict=True)])
        else:  # erf
            scale = _Sym.number(2 / sp.sqrt(sp.pi)) if self.a.symbolic else 2.0 / math.sqrt(math.pi)
            h = [scale * x for x in self._function(sp.exp, [-x for x in square])]
        b = [f[kind](a[0])]
        for k in range(1, self.n):
            b.append(sum((j * a[j] * h[k - j] for j in range(1, k + 1)), self.zero) / k)
        return b

    def _inverse_sqrt(self, a: list[Any]) -> list[Any]:
        p = _Sym(sp.Rational(-1, 2)) if self.a.symbolic else -0.5
        b = [self.a.power(a[0], p)]
        for k in range(1, self.n):
            b.append(
                sum(((p * j - (k - j)) * a[j] * b[k - j] for j in range(1, k + 1)), self.zero) / (k * a[0])
            )
        return b


def taylor(expr: sp.Expr, var: sp.Symbol, degree: int) -> list[sp.Expr]:
    """Return the Taylor coefficients ``c_0 .. c_degree`` of ``expr`` at ``var = 0``.

    The coefficients are sympy expressions in ``expr``'s other symbols (floats of
    :data:`DIGITS` digits where free of them); ``c_k = f^(k)(0) / k!``.

    Raises
    ------
    Unsupported
        For a node without a series rule (``sign``, a piecewise function) or a
        series that is not one at 0 (``sqrt(w)``, ``log(w)``): the caller takes
        derivatives and limits instead.

    """
    series = _Series(var, degree + 1, _Algebra(symbolic=True), _Sym(0), {})
    return [_sym(c) for c in series.of(expr)]


def derivatives(
    expr: sp.Expr,
    var: sp.Symbol,
    symbols: Sequence[sp.Symbol],
    w: npt.ArrayLike,
    values: Sequence[npt.ArrayLike],
    order: int,
) -> FloatArray:
    """Return ``d^order expr / d var^order`` at the velocities ``w`` for the parameter ``values``.

    ``w`` and the values broadcast together; the result has their broadcast shape.

    Raises
    ------
    Unsupported
        For a node without a series rule.

    """
    w = np.asarray(w, dtype=float)
    arrays = [np.asarray(v, dtype=float) for v in values]
    old = np.seterr(all="ignore")
    try:
        series = _Series(var, order + 1, _Algebra(symbolic=False), w, dict(zip(symbols, arrays, strict=True)))
        c = series.of(expr)[order]
    finally:
        np.seterr(**old)
    shape = np.broadcast_shapes(w.shape, *(a.shape for a in arrays))
    return np.asarray(np.broadcast_to(np.asarray(c, dtype=float) * math.factorial(order), shape), dtype=float)
