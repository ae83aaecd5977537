"""Formulas typed by users, read into sympy without ``eval``.

:func:`parse_formula` walks Python's syntax tree of the text and builds the sympy
expression node by node. Only numbers, names, ``+ - * / **`` (and ``^`` for the
power), parentheses and a fixed list of functions are accepted: anything else
(attribute access, indexing, lambdas, keyword arguments, strings, comparisons)
is refused in one line that says what is allowed. Nothing the user typed is
ever executed.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Iterable

import sympy as sp

from ..errors import ArgumentTypeError

__all__ = ["FUNCTIONS", "FormulaError", "parse_formula"]

#: the functions a formula may call, by the name the user types
FUNCTIONS: dict[str, sp.Function] = {
    "exp": sp.exp,
    "log": sp.log,
    "ln": sp.log,
    "log10": lambda x: sp.log(x, 10),
    "sqrt": sp.sqrt,
    "abs": sp.Abs,
    "sin": sp.sin,
    "cos": sp.cos,
    "tan": sp.tan,
    "sinh": sp.sinh,
    "cosh": sp.cosh,
    "tanh": sp.tanh,
    "atan": sp.atan,
    "arctan": sp.atan,
    "asinh": sp.asinh,
    "arcsinh": sp.asinh,
    "erf": sp.erf,
}
#: named constants
CONSTANTS = {"pi": sp.pi, "e": sp.E}

#: the deepest nesting of functions and operations a formula may have (sums and products
#: count once however many terms): its derivatives, code and checks recurse through it,
#: about ten Python frames a level; a friction law of the literature nests fewer than ten
MAX_DEPTH = 60

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}


class FormulaError(ValueError):
    """A formula that is not one: the message names the argument and what is allowed."""


def _allowed(variables: Iterable[str]) -> str:
    v = ", ".join(variables)
    return (
        f"numbers, the variable{'s' if ',' in v else ''} {v}, parameter names, the constants "
        f"{' and '.join(CONSTANTS)}, + - * / ** ( ) and the functions {', '.join(sorted(FUNCTIONS))}"
    )


def parse_formula(text: str, name: str, variables: Iterable[str]) -> sp.Expr:
    """Return the sympy expression of ``text``.

    Parameters
    ----------
    text : str
        The formula, e.g. ``"1/(1 + 3.8*w) + 0.5*w"``.
    name : str
        The argument it came from (``f``, ``mu``), for messages.
    variables : iterable of str
        Names with a fixed meaning (``w``, ``v``); every other name is a parameter.

    Raises
    ------
    FormulaError
        For text that is not a formula of this kind (a :class:`ValueError`).

    """
    variables = tuple(variables)
    if not isinstance(text, str):
        raise ArgumentTypeError(f"{name}={text!r}: expected a formula as text, such as '1/(1 + 3.8*w)'")
    if not text.strip():
        raise FormulaError(f"{name}: the formula is empty")
    if len(text) > 2000:
        raise FormulaError(f"{name}: a formula of {len(text)} characters is too long (at most 2000)")
    try:
        # '^' is the power as written on paper, with the power's precedence: parsed as Python's
        # XOR it bound looser than + and *, and '1 + w^2' was (1 + w)**2
        tree = ast.parse(text.strip().replace("^", "**"), mode="eval")
    except SyntaxError as exc:
        raise FormulaError(
            f"{name}={text!r} is not a formula ({exc.msg} at column {exc.offset}); "
            f"allowed: {_allowed(variables)}"
        ) from None

    def build(node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Expression):
            return build(node.body)
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, int | float):
                raise FormulaError(
                    f"{name}={text!r}: {node.value!r} is not a number; allowed: {_allowed(variables)}"
                )
            if isinstance(node.value, float) and not math.isfinite(node.value):
                raise FormulaError(f"{name}={text!r}: {node.value!r} is not a finite number")
            return sp.Integer(node.value) if isinstance(node.value, int) else sp.Float(node.value)
        if isinstance(node, ast.Name):
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            if node.id in FUNCTIONS:
                raise FormulaError(f"{name}={text!r}: {node.id} is a function: call it, as in {node.id}(w)")
            if node.id.startswith("_"):
                raise FormulaError(
                    f"{name}={text!r}: the name {node.id!r} is not allowed (leading underscore)"
                )
            return sp.Symbol(node.id, real=True)
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            left, right = build(node.left), build(node.right)
            if isinstance(node.op, ast.Pow):
                _check_power(left, right, name, text)
            return _BINARY[type(node.op)](left, right)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
            x = build(node.operand)
            return -x if isinstance(node.op, ast.USub) else x
        if isinstance(node, ast.Call):
            fn = node.func
            if not isinstance(fn, ast.Name) or fn.id not in FUNCTIONS:
                what = ast.unparse(fn)
                raise FormulaError(
                    f"{name}={text!r}: {what}(...) is not an allowed function; allowed: {_allowed(variables)}"
                )
            if node.keywords or len(node.args) != 1:
                raise FormulaError(f"{name}={text!r}: {fn.id} takes exactly one argument")
            return FUNCTIONS[fn.id](build(node.args[0]))
        what = type(node).__name__
        snippet = ast.unparse(node) if hasattr(ast, "unparse") else what
        raise FormulaError(
            f"{name}={text!r}: {snippet!r} ({what}) is not allowed in a formula; "
            f"allowed: {_allowed(variables)}"
        )

    try:
        expr = build(tree)
    except RecursionError:  # '------...w' or 'w**w**...**w', hundreds deep
        raise FormulaError(f"{name}: the formula is nested too deeply to be read") from None
    if not isinstance(expr, sp.Expr):
        raise FormulaError(f"{name}={text!r}: not a formula")
    deep = _too_deep(expr)
    if deep is not None:
        depth, part = deep
        raise FormulaError(
            f"{name}: the formula nests {depth} levels deep, at most {MAX_DEPTH}, in its part "
            f"{_shown(part)}: write it with fewer nested functions"
        )
    big = next((x for x in expr.atoms(sp.Number) if not math.isfinite(_float(x))), None)
    if big is not None:  # 1e200*1e200: a bare inf in the compiled law
        raise FormulaError(
            f"{name}={text!r}: the number {sp.sstr(sp.Float(big, 3))} is beyond double precision (1.8e308)"
        )
    if expr.has(sp.I, sp.zoo, sp.nan):  # sqrt(-1), (-1)**0.5, 1/0: a traceback deep in the engine
        raise FormulaError(
            f"{name}={text!r}: the formula is not a real number ({sp.sstr(expr)}): "
            "expected a real function (no square root or fractional power of a negative constant, no 1/0)"
        )
    return expr


def _float(x: sp.Number) -> float:
    """Return a sympy number in double precision (inf where beyond it)."""
    try:
        return float(x)
    except (OverflowError, TypeError):
        return math.inf


def _check_power(base: sp.Expr, exponent: sp.Expr, name: str, text: str) -> None:
    """Refuse a constant power beyond double precision before sympy works it out exactly.

    ``10**10**10`` is an integer of ten billion digits: sympy computed it, and hung.
    """
    if not (isinstance(base, sp.Number) and isinstance(exponent, sp.Number)):
        return
    b, e = abs(_float(base)), _float(exponent)
    if math.isfinite(b) and math.isfinite(e) and (b in (0.0, 1.0) or abs(e * math.log10(b)) <= 400):
        return  # within 1e-400 .. 1e400: sympy's exact value is small, a later check says the rest
    raise FormulaError(
        f"{name}={text!r}: the power {sp.sstr(base)}**{sp.sstr(exponent)} is beyond double precision "
        "(magnitudes from 1e-308 to 1.8e308)"
    )


def _too_deep(expr: sp.Expr) -> tuple[int, sp.Basic] | None:
    """Return the depth of ``expr`` and its deepest part when deeper than :data:`MAX_DEPTH`, else None."""
    height: dict[int, int] = {}
    stack: list[tuple[sp.Basic, bool]] = [(expr, False)]
    while stack:  # heights after the arguments' (no recursion: the formula may be deep)
        node, done = stack.pop()
        if id(node) in height:
            continue
        if done:
            height[id(node)] = 1 + max((height[id(a)] for a in node.args), default=0)
        else:
            stack.append((node, True))
            stack.extend((a, False) for a in node.args if id(a) not in height)
    if height[id(expr)] <= MAX_DEPTH:
        return None
    part: sp.Basic = expr
    while isinstance(part, sp.Add | sp.Mul):  # down the deepest path to its outermost function
        part = max(part.args, key=lambda a: height[id(a)])
    return height[id(expr)], part


def _shown(part: sp.Basic, width: int = 60) -> str:
    """``part`` as text, cut to ``width`` characters."""
    text = sp.sstr(part, order="none")
    return repr(text if len(text) <= width else text[: width - 3] + "...")
