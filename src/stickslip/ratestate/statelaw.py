"""A user's state evolution law from a formula: ``Phi' = F(v, phi, dc, vr, mu_rate)``.

The formula is read by :func:`stickslip.laws.formula.parse_formula` (never
evaluated as Python), then written as a postfix program of (opcode, value) pairs
that the compiled core evaluates (:func:`stickslip.core.ratestate.rpn_eval`), so a
new law needs no compilation. Variables: ``v`` the slip velocity (m/s), ``phi`` the
state (s), ``dc`` its ``D_c`` (m), ``vr`` the reference velocity (m/s) and
``mu_rate`` the rate of the spring's friction (1/s). The friction term is
``B ln(phi V_r / D_c)``, as for the aging law; steady sliding is where ``F = 0``.

Example: the aging law is ``"1 - v*phi/dc"``; the slip law ``"-(v*phi/dc)*log(v*phi/dc)"``.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import numpy.typing as npt
import sympy as sp

from ..core import ratestate_api as core
from ..laws.formula import parse_formula

__all__ = ["VARIABLES", "StateLawFormula", "state_law_formula"]

VARIABLES = ("v", "phi", "dc", "vr", "mu_rate")
_VAR_OPS = {
    "v": core.OP_V,
    "phi": core.OP_PHI,
    "dc": core.OP_DC,
    "vr": core.OP_VR,
    "mu_rate": core.OP_MU_RATE,
}
_UNARY = {
    sp.exp: core.OP_EXP,
    sp.log: core.OP_LOG,
    sp.Abs: core.OP_ABS,
    sp.tanh: core.OP_TANH,
    sp.sinh: core.OP_SINH,
    sp.cosh: core.OP_COSH,
    sp.asinh: core.OP_ASINH,
}


class StateLawFormula:
    """A parsed state law: its sympy expression, its program and its steady state."""

    def __init__(self, text: str) -> None:
        expr = parse_formula(text, "state_law", VARIABLES)
        extra = sorted(str(s) for s in expr.free_symbols if str(s) not in VARIABLES)
        if extra:
            raise ValueError(
                f"state_law={text!r}: unknown name {extra[0]!r}; a state law is aging, slip, prz, nagata "
                f"or a formula for dPhi/dt in {', '.join(VARIABLES)} (e.g. '1 - v*phi/dc')"
            )
        names = {str(x): x for x in expr.free_symbols}
        if "phi" not in names:
            raise ValueError(f"state_law={text!r}: dPhi/dt must depend on phi")
        self.text = text
        self.expr = expr
        ops: list[tuple[int, float]] = []
        _emit(expr, ops, text)
        self.program = np.array([x for pair in ops for x in pair], dtype=float)
        self._f = sp.lambdify([names.get(n, sp.Symbol(n)) for n in VARIABLES], expr, modules="math")

    def rate(self, v: float, phi: float, dc: float, vr: float, mu_rate: float = 0.0) -> float:
        """Return ``dPhi/dt`` (dimensionless: s/s)."""
        return float(self._f(v, phi, dc, vr, mu_rate))

    def steady_phi(self, v: float, dc: float, vr: float) -> float:
        """Return the steady state ``Phi`` (s) at slip velocity ``v`` (m/s): the root of ``F`` near ``dc/v``.

        Raises
        ------
        ValueError
            When ``F`` has no sign change within twelve decades of ``dc/v``.

        """
        from scipy import optimize  # here: 0.3 s to import, and most commands need none

        x0 = dc / v

        def g(lx: float) -> float:
            try:  # the formula in Python's math: exp(phi) overflows, log(-1) raises
                r = self.rate(v, x0 * math.exp(lx), dc, vr)
            except (ArithmeticError, ValueError):
                return math.nan
            return r if math.isfinite(r) else math.nan

        grid = np.linspace(-28.0, 28.0, 113)
        vals = np.array([g(x) for x in grid])
        for i in range(grid.size - 1):
            if np.isfinite(vals[i]) and np.isfinite(vals[i + 1]) and vals[i] > 0 >= vals[i + 1]:
                return x0 * math.exp(optimize.brentq(g, grid[i], grid[i + 1], xtol=1e-14))
        raise ValueError(
            f"state_law={self.text!r}: no stable steady state (dPhi/dt from + to -) within 1e12 of "
            f"dc/v at v = {v:g} m/s; steady sliding needs one"
        )


@lru_cache(maxsize=64)
def state_law_formula(text: str) -> StateLawFormula:
    """Return the parsed law of ``text`` (cached)."""
    return StateLawFormula(text)


def _emit(e: sp.Expr, ops: list[tuple[int, float]], text: str) -> None:
    if e.is_Number:
        ops.append((core.OP_CONST, float(e)))
        return
    if e.is_Symbol:
        ops.append((_VAR_OPS[str(e)], 0.0))
        return
    if e in (sp.pi, sp.E):
        ops.append((core.OP_CONST, float(e)))
        return
    if isinstance(e, sp.Add | sp.Mul):
        args = list(e.args)
        _emit(args[0], ops, text)
        for a in args[1:]:
            _emit(a, ops, text)
            ops.append((core.OP_ADD if isinstance(e, sp.Add) else core.OP_MUL, 0.0))
        return
    if isinstance(e, sp.Pow):
        base, exponent = e.args
        if exponent == sp.Rational(1, 2):
            _emit(base, ops, text)
            ops.append((core.OP_SQRT, 0.0))
            return
        if exponent == -1:
            ops.append((core.OP_CONST, 1.0))
            _emit(base, ops, text)
            ops.append((core.OP_DIV, 0.0))
            return
        _emit(base, ops, text)
        _emit(exponent, ops, text)
        ops.append((core.OP_POW, 0.0))
        return
    fn = type(e)
    if fn in _UNARY and len(e.args) == 1:
        _emit(e.args[0], ops, text)
        ops.append((_UNARY[fn], 0.0))
        return
    raise ValueError(
        f"state_law={text!r}: the function {fn.__name__} is not available in a state law "
        f"(use exp, log, sqrt, abs, tanh, sinh, cosh, asinh)"
    )


def program_table(programs: list[npt.NDArray[np.float64] | None]) -> npt.NDArray[np.float64]:
    """Return the columns ``(length, program...)`` of the state table, one row per state variable."""
    width = max([0] + [p.size for p in programs if p is not None])
    out = np.zeros((len(programs), 1 + width))
    for i, p in enumerate(programs):
        if p is not None:
            out[i, 0] = p.size // 2
            out[i, 1 : 1 + p.size] = p
    return out
