"""Numba code printed from a law's formulas: the module of ``f_plus`` and ``df_plus``.

The code is Python for numba: floats printed exactly, ``math`` functions qualified, a
long formula printed one line per distinct part. Kept apart from :mod:`~.compiler`,
which builds and loads the engines, so that a command with a built-in law does not
import sympy (0.3 s of its start).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from .compiler import _COMMON, _HEADER
from .series import node_count

__all__ = ["INLINE_CHARS", "law_module_source"]


class _Printer(PythonCodePrinter):
    """Python code for numba: floats printed exactly, math functions qualified."""

    def _print_Float(self, expr: sp.Float) -> str:
        return repr(float(expr))

    def _print_Rational(self, expr: sp.Rational) -> str:
        return repr(float(expr))

    def _print_Integer(self, expr: sp.Integer) -> str:
        return f"{int(expr)}.0"

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        b, e = expr.as_base_exp()
        if e.is_Integer and 2 <= int(e) <= 4:
            base = self.parenthesize(b, 1000)
            return "(" + "*".join([base] * int(e)) + ")"
        if e == -1:
            return f"(1.0/{self.parenthesize(b, 1000)})"
        if e.is_Integer:
            return f"{self.parenthesize(b, 1000)}**{int(e)}"
        return super()._print_Pow(expr, rational=rational)


def _code(expr: sp.Expr, symbols: Sequence[sp.Symbol]) -> str:
    """Python code of ``expr`` with the parameters renamed ``P[i]`` and ``w``."""
    sub = {s: sp.Symbol(f"_p{i}", real=True) for i, s in enumerate(symbols)}
    text = _Printer({"fully_qualified_modules": True, "standard": "python3"}).doprint(expr.subs(sub))
    for i in range(len(symbols)):
        text = text.replace(f"_p{i}", f"P[{i}]")
    return text


#: a formula printed longer than this is printed as one line per distinct part (:func:`_lines`)
INLINE_CHARS = 20_000


def _lines(
    exprs: Sequence[sp.Expr], symbols: Sequence[sp.Symbol], indent: str
) -> tuple[list[str], list[str]]:
    """Lines of temporaries, one per distinct part of ``exprs``, and the code of each after them.

    A derivative repeats its formula's parts (the chain rule) and a Taylor coefficient
    its arguments' coefficients: printed as trees, they grow exponentially with the
    nesting, while their distinct parts (shared subtrees, once each) grow as the formula
    does. The parts are walked without recursion, so a formula as deep as the parser
    allows prints.
    """
    names = {s: f"P[{i}]" for i, s in enumerate(symbols)}
    names[sp.Symbol("w", real=True)] = "w"
    printer = _Printer({"fully_qualified_modules": True, "standard": "python3"})
    code: dict[int, str] = {}
    lines: list[str] = []
    stack: list[tuple[sp.Basic, bool]] = [(e, False) for e in exprs]
    while stack:
        node, ready = stack.pop()
        if id(node) in code:
            continue
        if node.is_Symbol:
            code[id(node)] = names[node]
            continue
        if node.is_Number or node.is_NumberSymbol:
            text = printer.doprint(sp.Float(node, 17) if node.is_NumberSymbol else node)
            code[id(node)] = f"({text})" if text.startswith("-") else text
            continue
        if not ready:
            stack.append((node, True))
            stack.extend((a, False) for a in node.args if id(a) not in code)
            continue
        args = [code[id(a)] for a in node.args]
        if isinstance(node, sp.Add):
            text = " + ".join(args)
        elif isinstance(node, sp.Mul):
            text = "*".join(args)
        elif isinstance(node, sp.Pow):
            e = node.args[1]
            if e.is_Integer and 2 <= int(e) <= 4:
                text = "*".join([args[0]] * int(e))
            elif e == -1:
                text = f"1.0/{args[0]}"
            else:
                text = f"{args[0]}**{args[1]}"
        else:  # a function: printed with its arguments as the temporaries' names
            dummies = [sp.Symbol(a, real=True) for a in args]
            text = printer.doprint(node.func(*dummies))
        name = f"_t{len(lines)}"
        lines.append(f"{indent}{name} = {text}")
        code[id(node)] = name
    return lines, [code[id(e)] for e in exprs]


def _printed(expr: sp.Expr, symbols: Sequence[sp.Symbol], indent: str) -> tuple[list[str], str]:
    """Return the code of ``expr``: one expression, or lines of its parts where that is long."""
    # distinct parts counted once (count_ops walks the tree, exponential in a derivative's nesting)
    text = _code(expr, symbols) if node_count(expr, INLINE_CHARS // 10) <= INLINE_CHARS // 10 else ""
    if text and len(text) <= INLINE_CHARS:
        return [], text
    lines, (value,) = _lines([expr], symbols, indent)
    return lines, value


def _function(name: str, expr: sp.Expr, negative: Sequence[sp.Expr], symbols: Sequence[sp.Symbol]) -> str:
    """Return a kernel function: ``expr`` for ``w >= 0``, the polynomial ``negative`` below."""
    lines, value = _printed(expr, symbols, " " * 8)
    body = "\n".join([*lines, f"        return {value}"])
    cont, coefficients = _lines(negative, symbols, " " * 4)
    horner = coefficients[-1]
    for c in reversed(coefficients[:-1]):
        horner = f"({horner})*w + {c}"
    tail = "\n".join([*cont, f"    return {horner}"])
    return f"""

@njit(cache=True)
def {name}(law, P, w):
    if w >= 0.0:
{body}
{tail}
"""


def law_module_source(
    expr: sp.Expr,
    dexpr: sp.Expr,
    continuation: Sequence[sp.Expr],
    symbols: Sequence[sp.Symbol],
    name: str,
) -> str:
    """Return the numba module of a law given by formulas (for ``w >= 0``) and its continuation.

    ``continuation`` holds the coefficients of the Taylor polynomial at 0 that
    continues the law to ``w < 0``, lowest degree first.
    """
    slope = [sp.Mul(k, c, evaluate=False) for k, c in enumerate(continuation)][1:] or [sp.Integer(0)]
    body = _function("f_plus", expr, list(continuation), symbols) + _function(
        "df_plus", dexpr, slope, symbols
    )
    return _HEADER.format(name=name, formula=sp.sstr(expr)) + _COMMON + body
