"""A user's friction law from a formula: ``ExpressionLaw("1/(1 + 3.8*w) + 0.5*w")``.

Two forms:

* dimensionless, ``f(w)``: friction in units of the static friction force, ``w``
  the slip velocity in the model's units (``mu_s W / sqrt(k m)``), so
  ``f(0+) = 1`` for a law that is continuous at the onset of slip. For a law
  that drops at the onset, give the static threshold ``static`` in the units of
  ``f``: with ``static=1``, ``f(0+) < 1`` is the drop; any other value is taken
  as the unit of ``f``, and the formula is rescaled to units of the static
  friction, ``f(w) -> f(static w) / static`` (so ``nu`` is then in those units);
* physical, ``mu(v)``: the friction coefficient against the slip velocity ``v``
  in m/s (``ExpressionLaw(mu="0.46/(1 + 160*v)")``), with the set-up's mass,
  stiffness and load; ``static`` is the static coefficient ``mu_s`` where it
  differs from ``mu(0+)``.

Other names in the formula are parameters, given as keywords (numbers, or
quantities with units in the physical form: ``a="160 s/m"``); they can be swept.
The formula is read by :func:`~.formula.parse_formula` (never ``eval``'d), its
derivatives come from sympy, and the engine is compiled for it once
(:mod:`~.compiler`): the same exact stick and events as a built-in law.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt
import pint
import sympy as sp

from ..core.checks import finite
from ..errors import ArgumentTypeError
from ..units import Q_, check_number, parse_quantity, ureg
from ..userwarnings import warn
from .base import DimensionlessLaw, PhysicalLaw
from .formula import CONSTANTS, FormulaError, parse_formula
from .spec import LawSpec, Parameter, W

__all__ = ["ExpressionLaw", "PhysicalExpressionLaw"]

FloatArray = npt.NDArray[np.float64]
V = sp.Symbol("v", real=True)
#: friction at the onset of slip within this of 1 counts as continuous (no --static needed)
ONSET_TOL = 1e-9
#: velocities at which a formula must be finite (model units; physical: these times 1 m/s)
_PROBE = np.concatenate([[0.0], np.geomspace(1e-9, 1e2, 45)])
#: where a formula's denominators (and tan's, log's arguments) are looked at for a zero: steps of 6.5 %
#: to two past w = 100 (a minimum of a denominator's magnitude just below 100 has both neighbours)
_STEPS = np.geomspace(1e-9, _PROBE[-1], 401)
_POLE_GRID = np.concatenate([[0.0], _STEPS, _STEPS[-1] * (_STEPS[-1] / _STEPS[-2]) ** np.arange(1, 3)])
#: a denominator is zero where its value is below this of the magnitude of its terms (rounding)
_TOUCH = 1e-12
#: a sign change is a zero where the value found is below this of its neighbours'; else it is a
#: jump through infinity (tan's at pi/2, where 1/tan(w) is 0)
_CROSS = 1e-6
#: local minima of |denominator| below this of its largest on the grid are searched (a double root's
#: grid value is at most (step/2)^2 = 1e-3 of it); a denominator bounded away from zero has none
_NEAR = 1e-2
#: parameter points of a sweep looked at together (memory: grid size times this)
_POLE_CHUNK = 2048

_SPECS: dict[tuple[Any, ...], LawSpec] = {}


def _onset(expr: sp.Expr, var: sp.Symbol, values: Mapping[str, float]) -> float:
    """``expr`` at ``var = 0+`` for these parameter values."""
    e = expr.subs({sp.Symbol(k, real=True): v for k, v in values.items()})
    x = e.subs(var, 0)
    if x.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        x = sp.limit(e, var, 0, "+")
    try:
        return float(x)
    except TypeError:
        return math.nan


def _parameters(expr: sp.Expr, variable: str, given: Mapping[str, Any], what: str, text: str) -> list[str]:
    names = sorted(s.name for s in expr.free_symbols if s.name != variable)
    for n in names:
        if n == "v" and variable == "w":  # the slip velocity in m/s is the physical form's
            raise FormulaError(
                f"{what}={text!r}: the dimensionless formula's velocity is w (model units); for the "
                "friction coefficient against v in m/s give mu=... (ExpressionLaw(mu=...), --mu)"
            )
        if n == "w" and variable == "v":
            raise FormulaError(
                f"{what}={text!r}: the physical formula's velocity is v (m/s); for a dimensionless "
                "f(w) give f=... (ExpressionLaw(f), --f)"
            )
        if n in ("w", "v", "beta", "mu_s", "nu") or n.startswith("_"):
            raise FormulaError(f"{what}={text!r}: {n!r} is reserved; give the parameter another name")
    missing = [n for n in names if n not in given]
    if missing:
        raise FormulaError(
            f"{what}={text!r}: give the value of {', '.join(missing)} "
            f"({', '.join(f'{n}=...' for n in missing)}; on the command line --param {missing[0]}=...)"
        )
    extra = [n for n in given if n not in names]
    constant = [n for n in extra if n in CONSTANTS]
    if constant:  # 'e' in a formula is Euler's number: a parameter of that name is refused, said
        n = constant[0]
        raise FormulaError(
            f"{what}={text!r}: {n!r} in a formula is the constant {n} = {float(CONSTANTS[n]):.6g}, "
            f"not a parameter; give the parameter another name ({n}0, say)"
        )
    if extra:
        raise FormulaError(f"{what}={text!r} has no parameter {', '.join(map(repr, extra))}")
    return names


def _check_values(spec: LawSpec, values: Mapping[str, npt.ArrayLike], text: str) -> None:
    """Friction finite for ``w >= 0``, at most the static threshold at the onset; warn where negative."""
    arrays = [np.asarray(values[p.name], dtype=float) for p in spec.parameters]
    shape = np.broadcast_shapes(*(a.shape for a in arrays)) if arrays else ()
    w = _PROBE.reshape((-1,) + (1,) * len(shape))
    f = spec.evaluate(w, arrays)
    f = np.broadcast_to(f, (w.shape[0], *shape)).reshape(w.shape[0], -1)
    bad = ~np.isfinite(f)
    if not bad.any():
        pole = _pole(spec, arrays, shape)
    else:
        i, j = np.argwhere(bad)[0]
        # a pole that a probe velocity hits exactly (numpy 2.4's geomspace gives 1e-5 itself) is
        # named as a pole, as one between the probes is
        pole = _pole(spec, arrays, shape) if _PROBE[i] > 0.0 else None
    if pole is None and bad.any():
        at = f" at point {j}" if f.shape[1] > 1 else ""
        if _PROBE[i] == 0.0:  # 0/0 with a finite limit (sin(w)/w): say why that is refused
            point = {
                p.name: float(np.ravel(np.broadcast_to(a, shape))[j])
                for p, a in zip(spec.parameters, arrays, strict=True)
            }
            lim = _onset(spec.expression, W, point)
            if math.isfinite(lim):
                raise ValueError(
                    f"f(w) = {text} is 0/0 at w = 0{at} (its limit there is {lim:.6g}); the engine evaluates "
                    "friction at w = 0 itself, so a removable singularity is not supported: write a formula "
                    "that is finite at w = 0"
                )
        raise ValueError(
            f"f(w) = {text} is not finite at w = {_PROBE[i]:.3g}{at}: friction must be finite for every "
            "velocity the block can reach"
        )
    if pole is not None:
        at_w, part, j, of = pole
        at = f" at point {j}" if f.shape[1] > 1 else ""
        names = [p.name for p in spec.parameters]
        law, x, zero = f"f(w) = {text}", f"w = {at_w:.6g}", sp.sstr(part)
        if "beta" in names:  # the physical form, mu(w/beta)/mu_s: say it in m/s
            beta = float(np.ravel(np.broadcast_to(arrays[names.index("beta")], shape))[j])
            law, x = text.split("mu_s, ", 1)[-1], f"v = {at_w / beta:.6g} m/s"
            zero = sp.sstr(part.subs(W, sp.Symbol("beta", real=True) * V))
        whose = law if of == "f" else f"the slope of {law}"
        raise ValueError(
            f"{whose} has a pole at {x}{at}, where {zero} is zero: friction and its slope must be finite "
            "for every velocity the block can reach"
        )
    onset = f[0]
    if np.any(onset > 1.0 + ONSET_TOL):
        j = int(np.argmax(onset > 1.0 + ONSET_TOL))
        raise ValueError(
            f"f(0+) = {onset[j]:.6g} for f(w) = {text}: friction just after breakaway exceeds the static "
            "threshold 1, so the block could never slip"
        )
    low = _lowest(spec, arrays, shape)
    if low is not None:
        f_min, w_min, j, count = low
        names = [p.name for p in spec.parameters]
        law, x = f"f(w) = {text}", f"w = {w_min:.3g}"
        if "beta" in names:  # the physical form: say it in m/s, as a pole is
            beta = float(np.ravel(np.broadcast_to(arrays[names.index("beta")], shape))[j])
            law, x = text.split("mu_s, ", 1)[-1], f"v = {w_min / beta:.3g} m/s"
            f_min *= float(np.ravel(np.broadcast_to(arrays[names.index("mu_s")], shape))[j])  # mu's minimum
        where = ""
        if f.shape[1] > 1:
            first = ", ".join(
                f"{name}={float(np.ravel(np.broadcast_to(a, shape))[j]):g}"
                for name, a in zip(names, arrays, strict=True)
                if np.size(a) > 1
            )
            where = f" (at {count} of {f.shape[1]} points, the first shown: {first})"
        warn(f"{law} turns negative (minimum {f_min:.3g} at {x}): the friction drives the block there{where}")


def _lowest(
    spec: LawSpec, arrays: list[FloatArray], shape: tuple[int, ...]
) -> tuple[float, float, int, int] | None:
    """Where friction is negative for ``0 <= w <= 100``: (minimum, its w, first point, points), or None.

    The grid is :data:`_POLE_GRID`'s (steps of 6.5 %); every local minimum on it is
    refined by golden-section search within its two neighbours, so a negative dip
    narrower than a step is found (1 - 2.9 w + 2 w**2, negative on 0.565..0.885 only,
    passed the 45 probe points).
    """
    grid = _POLE_GRID[_POLE_GRID <= _PROBE[-1]]
    f = spec.evaluate(grid.reshape((-1,) + (1,) * len(shape)), arrays)
    f = np.broadcast_to(f, (grid.size, *shape)).reshape(grid.size, -1)
    f = np.where(np.isfinite(f), f, np.inf)
    best = f.min(axis=0)
    at = grid[f.argmin(axis=0)]
    i, j = np.nonzero((f[1:-1] < f[:-2]) & (f[1:-1] <= f[2:]))
    if i.size:
        values = [np.ravel(np.broadcast_to(np.asarray(a, dtype=float), shape))[j] for a in arrays]
        a, b = grid[i], grid[i + 2]
        golden = (math.sqrt(5.0) - 1.0) / 2.0
        for _ in range(60):  # 0.618**60: the bracket to 3e-13 of itself
            c, d = b - golden * (b - a), a + golden * (b - a)
            fc, fd = spec.evaluate(c, values), spec.evaluate(d, values)
            left = ~(fc > fd)  # the minimum is in [a, d]; NaN leaves it there too
            a, b = np.where(left, a, c), np.where(left, d, b)
        w = 0.5 * (a + b)
        fw = spec.evaluate(w, values)
        fw = np.where(np.isfinite(fw), fw, np.inf)
        for k in np.flatnonzero(fw < best[j]):
            if fw[k] < best[j[k]]:
                best[j[k]], at[j[k]] = fw[k], w[k]
    negative = np.flatnonzero(best < 0.0)
    if not negative.size:
        return None
    first = int(negative[0])
    return float(best[first]), float(at[first]), first, int(negative.size)


def _singular_parts(expr: sp.Expr) -> tuple[sp.Expr, ...]:
    """Sub-expressions of ``expr`` whose zero makes it infinite: denominators, tan's cos, log's argument."""
    parts = []
    for node in sp.preorder_traversal(expr):
        if isinstance(node, sp.Pow) and node.exp.is_number and node.exp.is_negative:
            parts.append(node.base)
        elif isinstance(node, sp.tan):
            parts.append(sp.cos(node.args[0]))
        elif isinstance(node, sp.log):
            parts.append(node.args[0])
    return tuple(dict.fromkeys(p for p in parts if p.has(W)))


def _pole(
    spec: LawSpec, arrays: list[FloatArray], shape: tuple[int, ...]
) -> tuple[float, sp.Expr, int, str] | None:
    """Return ``(w, part, point, of)`` of the first zero of a singular part for ``0 < w <= 100``, or None.

    The 46 probes of :func:`_check_values` step over a pole between them
    (``1/(w - 0.5)``); here each denominator is evaluated on a grid of 6.5 % steps:
    a change of sign between two points is a zero, and so is a local minimum of
    its magnitude that falls to zero between them (``1/(w - 0.5)**2`` written
    out as ``1/(w**2 - w + 0.25)``), found by golden-section search. ``of`` says
    whose pole it is: ``f``'s, or only its slope's (``sqrt(abs(w - 0.5))``), which
    the engine evaluates as well.
    """
    own = _singular_parts(spec.expr)
    parts = [(p, "f") for p in own] + [
        (p, "slope") for p in _singular_parts(spec.derivative(1)) if p not in own
    ]
    if not parts:
        return None
    flat = [np.broadcast_to(a, shape).ravel() for a in arrays]
    w = _POLE_GRID[:, None]
    old = np.seterr(all="ignore")
    try:
        for part, of in parts:
            # only the parameters in this part matter: a sweep's distinct values of those
            used = [i for i, s in enumerate(spec.symbols) if s in part.free_symbols]
            args = (W, *(spec.symbols[i] for i in used))
            fn = sp.lambdify(args, part, modules=["scipy", "numpy"])
            terms = _magnitude(part)
            size = None if terms is None else sp.lambdify(args, terms, modules=["scipy", "numpy"])
            table = np.stack([flat[i] for i in used], axis=1) if used else np.zeros((1, 0))
            points, first = np.unique(table, axis=0, return_index=True)
            for lo in range(0, len(points), _POLE_CHUNK):
                chunk = points[lo : lo + _POLE_CHUNK]
                cols = [chunk[:, i] for i in range(chunk.shape[1])]
                g = np.broadcast_to(np.asarray(fn(w, *cols), dtype=float), (w.size, len(chunk)))
                found = _zero_on_grid(fn, size, g, cols)
                if found is not None:
                    at, k = found
                    return at, part, int(first[lo + k]), of
    finally:
        np.seterr(**old)
    return None


def _magnitude(part: sp.Expr) -> sp.Expr | None:
    """Return the size of a sum's terms, ``|a| + |b| + ...`` for ``a + b + ...`` (None for no sum).

    A zero of a sum cancels its terms: its value falls to rounding against their size.
    """
    if isinstance(part, sp.Abs):
        return _magnitude(part.args[0])
    if isinstance(part, sp.Add):
        return sp.Add(*(sp.Abs(t) for t in part.args))
    return None


def _zero_on_grid(fn: Any, size: Any, g: FloatArray, cols: list[FloatArray]) -> tuple[float, int] | None:
    """First ``(w, column)`` where ``g`` (grid by points) is zero, changes sign, or touches zero.

    A sign change is a zero where the value found is small against the neighbours' (not a
    jump through infinity: tan's at pi/2, where ``1/tan(w)`` is 0). A minimum of a sum is a
    zero where its terms cancel, its value at rounding against ``size``, their magnitude
    (``w**2 - w + 0.25`` at 0.5: 0 against 1; a steep but finite ``1 + 1e16 (w - 0.5)**2``
    was taken for one against its neighbours, and an expanded quartic's root missed); of
    another expression, where it is small against its neighbours.
    """
    from scipy.optimize import brentq

    finite = np.isfinite(g)
    neg = g < 0
    hit = ((neg[1:] != neg[:-1]) & finite[1:] & finite[:-1]) | (g[1:] == 0)
    for i, k in np.argwhere(hit):
        a, b = _POLE_GRID[i], _POLE_GRID[i + 1]
        args = [float(c[k]) for c in cols]
        if b > _PROBE[-1]:  # past w = 100: only there for a minimum's neighbour
            continue
        if g[i + 1, k] == 0:
            return float(b), int(k)
        x = float(brentq(lambda x, p=args: float(fn(x, *p)), a, b, xtol=1e-15, rtol=1e-14))
        if abs(float(fn(x, *args))) <= _CROSS * max(abs(g[i, k]), abs(g[i + 1, k])):
            return x, int(k)
    m = np.where(finite, np.abs(g), np.inf)
    top = np.max(np.where(finite, m, 0.0), axis=0)
    inner = (m[1:-1] <= m[:-2]) & (m[1:-1] <= m[2:]) & (m[1:-1] <= _NEAR * top)
    i, k = np.nonzero(inner)
    if i.size == 0:
        return None
    a, b = _POLE_GRID[i].copy(), _POLE_GRID[i + 2].copy()
    at = [c[k] for c in cols]
    ratio = (np.sqrt(5.0) - 1.0) / 2.0
    for _ in range(100):  # golden section on |g| in [a, b], every candidate at once
        x1, x2 = b - ratio * (b - a), a + ratio * (b - a)
        left = np.abs(fn(x1, *at)) <= np.abs(fn(x2, *at))
        b = np.where(left, x2, b)
        a = np.where(left, a, x1)
    x = (a + b) / 2
    low = np.abs(np.asarray(fn(x, *at), dtype=float))
    scale = np.minimum(m[i, k], m[i + 2, k]) if size is None else np.asarray(size(x, *at), dtype=float)
    touch = np.flatnonzero((low <= _TOUCH * scale) & (x <= _PROBE[-1]))
    if touch.size == 0:
        return None
    c = touch[np.argmin(k[touch] * g.shape[0] + i[touch])]  # the first point, its lowest zero
    return float(x[c]), int(k[c])


def _continuous_onset(spec: LawSpec, text: str) -> Any:
    def check(values: Mapping[str, FloatArray]) -> None:
        _check_values(spec, values, text)
        arrays = [np.asarray(values[p.name], dtype=float) for p in spec.parameters]
        f0 = np.ravel(spec.evaluate(np.zeros(1), arrays))
        if np.any(np.abs(f0 - 1.0) > ONSET_TOL):
            j = int(np.argmax(np.abs(f0 - 1.0) > ONSET_TOL))
            at = f" (point {j})" if f0.size > 1 else ""
            raise ValueError(
                f"f(0+) = {f0[j]:.10g}{at} for f(w) = {text}: the dimensionless form measures friction in "
                "units of the static friction, so a law continuous at the onset of slip has f(0+) = 1. "
                "For a law that drops at the onset give the static threshold in the units of f "
                "(static=1 / --static 1 if f is already in units of static friction)"
            )

    return check


def _spec_for(expr: sp.Expr, names: list[str], text: str, continuous: bool) -> LawSpec:
    key = (sp.srepr(expr), tuple(names), continuous)
    spec = _SPECS.get(key)
    if spec is None:
        params = tuple(Parameter(n, f"parameter {n} of the formula", lower=-math.inf) for n in names)
        spec = LawSpec(
            name="expr",
            title=f"f(w) = {text}",
            f=sp.sstr(expr),
            parameters=params,
            expression=expr.subs({sp.Symbol(n, real=True): sp.Symbol(n, real=True) for n in names}),
            source="a formula typed by the user",
        )
        checker = _continuous_onset(spec, text) if continuous else (lambda v: _check_values(spec, v, text))
        object.__setattr__(spec, "check", checker)
        _SPECS[key] = spec
    return spec


class ExpressionLaw(DimensionlessLaw):
    """A dimensionless friction law from a formula in ``w`` (or, with ``mu=``, a physical one).

    Parameters
    ----------
    f : str
        ``f_+(w)`` for ``w > 0``, friction in units of the static friction force, e.g.
        ``"1/(1 + 3.8*w) + 0.5*w"`` or ``"1/(1 + c*w)"`` with ``c=3.8``.
    static : float, optional
        Static threshold in the units of ``f`` where it differs from ``f(0+) = 1``
        (a drop at the onset of slip): 1 keeps ``f``'s units; another value
        rescales the formula to units of the static friction.
    mu : str, optional
        Instead of ``f``: the friction coefficient ``mu(v)``, ``v`` in m/s; returns a
        :class:`PhysicalExpressionLaw`.
    **params
        Values of the formula's other names. In the physical form (``mu=``) a plain
        number is read in SI units (``a=160`` in ``1 + a*v`` is 160 s/m); give a quantity
        (``a="160 s/m"``) to have its units checked.

    Raises
    ------
    ValueError
        For a formula that is not one (code, unknown functions), missing or extra
        parameters, friction not finite, or ``f(0+) != 1`` without ``static``.

    Examples
    --------
    >>> from stickslip import ExpressionLaw
    >>> law = ExpressionLaw("1/(1 + c*w) + p*w", c=3.8, p=0.5)
    >>> float(law.forward(0.0))
    1.0

    """

    __slots__ = ("static", "text")
    static: float | None
    text: str

    def __new__(cls, f: str | None = None, *, mu: str | None = None, **kwargs: Any) -> Any:  # noqa: D102
        if mu is not None:
            if f is not None:
                raise TypeError("ExpressionLaw: give f (dimensionless) or mu (physical), not both")
            return PhysicalExpressionLaw(mu, **kwargs)
        return object.__new__(cls)

    def __init__(self, f: str | None = None, *, static: float | None = None, **params: Any) -> None:
        if f is None:
            raise TypeError("ExpressionLaw: give the formula f, e.g. ExpressionLaw('1/(1 + 3.8*w)')")
        expr = parse_formula(f, "f", ("w",))
        names = _parameters(expr, "w", params, "f", f)
        values = {n: _number(n, params[n]) for n in names}
        continuous = static is None
        if static is not None:
            s = check_number(
                static, "static", upper=1e12, upper_inclusive=True, what="a positive static threshold"
            )
            if s < 1e-12:  # 1e308 (or 1e-320) rescaled w past double precision: 'numba cannot compile'
                raise ValueError(f"static={static!r}: expected a static threshold between 1e-12 and 1e12")
            if s != 1.0:  # f in other units than the static friction: rescale to them
                expr = expr.subs(W, s * W) / s
        shown = f if static in (None, 1.0) else f"({f}) rescaled by static={static}"
        spec = _spec_for(expr, names, shown, continuous)
        self._set(spec, (), values)
        object.__setattr__(self, "static", None if static is None else float(static))
        object.__setattr__(self, "text", f)

    @classmethod
    def _from_spec(cls, spec: LawSpec, values: Mapping[str, float], text: str) -> ExpressionLaw:
        law = object.__new__(cls)
        law._set(spec, (), dict(values))
        object.__setattr__(law, "static", 1.0)
        object.__setattr__(law, "text", text)
        return law

    def _from_values_like(self, values: Mapping[str, float]) -> ExpressionLaw:
        law = object.__new__(type(self))
        law._set(self.spec, (), dict(values))
        object.__setattr__(law, "static", self.static)
        object.__setattr__(law, "text", self.text)
        return law

    def replace(self, **changes: float) -> ExpressionLaw:
        """Return a copy with some parameters changed (checked)."""
        return self._from_values_like({**self.params, **changes})

    def __repr__(self) -> str:
        args = [repr(self.text), *(f"{k}={v!r}" for k, v in self.params.items())]
        if self.static is not None:
            args.append(f"static={self.static!r}")
        return f"ExpressionLaw({', '.join(args)})"

    def __reduce__(self) -> tuple[Any, ...]:
        names = [p.name for p in self.spec.parameters]
        title = self.spec.title.removeprefix("f(w) = ")
        return _rebuild, (self.spec.expr, names, title, self.params, self.static, self.text)

    def to_physical(self, beta: Any, mu_s: float) -> PhysicalLaw:
        """Return ``mu(v) = mu_s f(beta v)`` as a :class:`PhysicalExpressionLaw`."""
        b = parse_quantity(beta, "beta", "[time] / [length]", "42 s/m").to("s/m").magnitude
        mu = check_number(mu_s, "mu_s")
        expr = mu * self.spec.expr.subs(W, float(b) * V)
        expr = expr.subs({s: v for s, v in zip(self.spec.symbols, self._values, strict=True)})
        static = mu if self.kinetic_limit < 1.0 - ONSET_TOL else None
        return PhysicalExpressionLaw._from_expr(expr, {}, static, f"{mu:g}*f({float(b):g}*v)")

    def describe(self) -> str:
        """One line: the formula and its parameters."""
        pars = ", ".join(f"{k} = {v:.6g}" for k, v in self.params.items())
        return f"expr: f(w) = {self.spec.f}" + (f" with {pars}" if pars else "")


def _rebuild(
    expr: sp.Expr, names: list[str], title: str, params: dict[str, float], static: float | None, text: str
) -> ExpressionLaw:
    spec = _spec_for(expr, names, title, static is None)
    law = object.__new__(ExpressionLaw)
    law._set(spec, (), params)
    object.__setattr__(law, "static", static)
    object.__setattr__(law, "text", text)
    return law


class PhysicalExpressionLaw(PhysicalLaw):
    """A friction law from a formula for the coefficient ``mu(v)``, ``v`` the slip velocity in m/s.

    Parameters
    ----------
    mu : str
        ``mu(v)`` for ``v > 0``, e.g. ``"0.46/(1 + 160*v)"`` or ``"m0/(1 + a*v)"``.
    static : float, optional
        Static coefficient ``mu_s`` where it differs from ``mu(0+)`` (a drop at the onset).
    **params
        Values of the formula's other names: numbers, or quantities (``a="160 s/m"``)
        so that the formula is dimensionally consistent with ``v`` in m/s.

    """

    __slots__ = ("_mu_expr", "static", "text")
    static: float | None
    text: str
    _mu_expr: sp.Expr

    def __init__(self, mu: str, *, static: float | None = None, **params: Any) -> None:
        expr = parse_formula(mu, "mu", ("v",))
        names = _parameters(expr, "v", params, "mu", mu)
        self._init(expr, {n: params[n] for n in names}, static, mu)

    @classmethod
    def _from_expr(
        cls, expr: sp.Expr, params: Mapping[str, Any], static: float | None, text: str
    ) -> PhysicalExpressionLaw:
        law = object.__new__(cls)
        law._init(expr, params, static, text)
        return law

    def _init(self, expr: sp.Expr, params: Mapping[str, Any], static: float | None, text: str) -> None:
        names = sorted(params)
        quantities: dict[str, Any] = {}
        si: dict[str, float] = {}
        units: dict[str, str] = {}
        for n in names:
            x = params[n]
            if isinstance(x, str | pint.Quantity):
                q = _quantity(n, x)
                base = q.to_base_units()
                quantities[n] = q
                si[n] = float(base.magnitude)
                units[n] = "" if base.dimensionless else f"{base.units:~}"
            else:
                si[n] = _number(n, x)
                quantities[n] = si[n]
                units[n] = ""
        _dimension_check(expr, quantities, text)
        onset = _onset(expr, V, si)
        if not (math.isfinite(onset) and onset > 0):
            raise ValueError(
                f"mu(0+) = {onset!r} for mu(v) = {text}: the friction coefficient at the onset of slip "
                "must be positive and finite"
            )
        if static is None:
            mu_s = onset
        else:
            mu_s = check_number(static, "static", what="a positive static coefficient")
            if onset > mu_s * (1 + ONSET_TOL):
                raise ValueError(f"mu(0+) = {onset:.6g} exceeds static={mu_s!r}: the block could never slip")
        # the dimensionless form: f(w) = mu(w / beta) / mu_s, beta and mu_s parameters of its own
        beta_s, mu_s_s = sp.Symbol("beta", real=True), sp.Symbol("mu_s", real=True)
        f_expr = expr.subs(V, W / beta_s) / mu_s_s
        nd_names = ["beta", "mu_s", *names]
        # the parameters' units in the key too: a law of the same formula with other units must not
        # show the first one's (a = 160 s/m as '160 kilogram')
        key = ("physical", sp.srepr(f_expr), tuple(nd_names), tuple(units[n] for n in names))
        spec = _SPECS.get(key)
        if spec is None:
            spec = LawSpec(
                name="expr",
                title=f"mu(v) = {text}",
                f=sp.sstr(f_expr),
                parameters=(
                    Parameter("beta", "beta = sqrt(k m)/(mu_s W) in s/m"),
                    Parameter("mu_s", "static friction coefficient"),
                    *(Parameter(n, f"parameter {n} of the formula (SI)", lower=-math.inf) for n in names),
                ),
                physical=tuple(
                    Parameter(
                        n,
                        f"parameter {n} of the formula",
                        unit=units[n],
                        example=f"1 {units[n]}" if units[n] else "",
                        lower=-math.inf,
                    )
                    for n in names
                ),
                to_dimensionless={"beta": "beta", "mu_s": "mu_s", **{n: n for n in names}},
                expression=f_expr,
                source="a formula typed by the user",
            )
            shown = f"mu(w/beta)/mu_s, mu(v) = {text}"
            object.__setattr__(spec, "check", lambda v, s=spec, t=shown: _check_values(s, v, t))
            if static is None:
                object.__setattr__(spec, "static_from", _static_from(expr, names))
            _SPECS[key] = spec
        object.__setattr__(self, "spec", spec)
        object.__setattr__(self, "mu_s", float(mu_s))
        object.__setattr__(self, "_values", tuple(si[n] for n in names))
        object.__setattr__(self, "static", None if static is None else float(mu_s))
        object.__setattr__(self, "text", text)
        object.__setattr__(self, "_mu_expr", expr)
        self._validate(spec, mu_s, dict(zip(names, [si[n] for n in names], strict=True)))

    def replace(self, **changes: Any) -> PhysicalExpressionLaw:
        """Return a copy with some parameters (or ``static``) changed."""
        static = changes.pop("static", changes.pop("mu_s", self.static))
        return PhysicalExpressionLaw._from_expr(self._mu_expr, {**self.params, **changes}, static, self.text)

    def __repr__(self) -> str:
        args = [f"mu={self.text!r}", *(f"{k}={v!r}" for k, v in self.params.items())]
        if self.static is not None:
            args.append(f"static={self.static!r}")
        return f"ExpressionLaw({', '.join(args)})"

    def __reduce__(self) -> tuple[Any, ...]:
        return PhysicalExpressionLaw._from_expr, (self._mu_expr, self.params, self.static, self.text)

    def nondimensionalize(self, beta: Any) -> DimensionlessLaw:
        """Return ``f(w) = mu(w/beta)/mu_s`` as an :class:`ExpressionLaw` (parameters ``beta``, ``mu_s``)."""
        b = float(parse_quantity(beta, "beta", "[time] / [length]", "42 s/m").to("s/m").magnitude)
        values = {"beta": b, "mu_s": self.mu_s, **self.si_parameters()}
        return ExpressionLaw._from_spec(self.spec, values, f"mu(w/beta)/mu_s, mu(v) = {self.text}")

    def describe(self) -> str:
        """One line: the formula, ``mu_s`` and the parameters."""
        pars = ", ".join([f"mu_s = {self.mu_s:.6g}", *(f"{k} = {v}" for k, v in self.params.items())])
        return f"expr: mu(v) = {self.text}; {pars}"


def _quantity(name: str, x: Any) -> pint.Quantity:
    if isinstance(x, pint.Quantity):
        q = ureg.Quantity(x.magnitude, str(x.units))
    else:
        try:
            q = ureg.Quantity(x)
        except Exception as exc:  # pint raises several unrelated types
            raise ValueError(f"{name}={x!r}: not a quantity ({exc}); expected e.g. '160 s/m'") from None
    if not isinstance(q, pint.Quantity) or not math.isfinite(float(q.magnitude)):
        raise ValueError(f"{name}={x!r}: expected a finite quantity such as '160 s/m'")
    return q


def _dimension_check(expr: sp.Expr, quantities: Mapping[str, Any], text: str) -> None:
    """Check the units: ``mu`` must be a pure number, with ``v`` a velocity or a number of m/s.

    ``v`` is the slip velocity in m/s, so a formula of numbers (``0.46/(1 + 160*v)``) is
    read in SI; parameters given with units must then combine into a pure number, with
    ``v`` either as a velocity (``a = 160 s/m`` in ``1 + a*v``) or as a number of m/s.
    """
    names = sorted(quantities)
    # erf is SciPy's, which pint does not wrap, so the check could not tell a = "160 kg" from
    # 160 s/m; tanh asks the same of its argument (a pure number), and pint has it
    checked = expr.replace(sp.erf, sp.tanh)
    fn = sp.lambdify([V, *[sp.Symbol(n, real=True) for n in names]], checked, modules=["numpy"])
    reasons = []
    for v in (Q_(1e-3, "m/s"), 1e-3):
        try:
            out = fn(v, *[quantities[n] for n in names])
        except pint.DimensionalityError as exc:
            reasons.append(str(exc))
            continue
        except Exception:  # a numpy function pint does not wrap: the values check will tell
            return
        if isinstance(out, pint.Quantity) and not out.dimensionless:
            reasons.append(f"the result has dimension {out.dimensionality}")
            continue
        return
    raise ValueError(
        f"mu(v) = {text} is not dimensionally consistent with v in m/s and these parameters "
        f"({reasons[0]}): a friction coefficient is a pure number; give parameters with units, "
        "e.g. a='160 s/m' in 0.46/(1 + a*v)"
    )


def _number(name: str, x: Any) -> float:
    if isinstance(x, bool) or not isinstance(x, int | float | np.floating | np.integer):
        raise ArgumentTypeError(
            f"{name}={x!r}: expected a finite number (or, in the physical form, a quantity)"
        )
    return finite(name, x)


def _static_from(expr: sp.Expr, names: list[str]) -> Any:
    at_zero = expr.subs(V, 0)
    if not at_zero.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        fn = sp.lambdify([sp.Symbol(n, real=True) for n in names], at_zero, modules=["scipy", "numpy"])

        def direct(values: Mapping[str, FloatArray]) -> FloatArray:
            arrays = [np.asarray(values[n], dtype=float) for n in names]
            shape = np.broadcast_shapes(*(a.shape for a in arrays)) if arrays else ()
            return np.asarray(np.broadcast_to(fn(*arrays), shape), dtype=float)

        return direct

    def static(values: Mapping[str, FloatArray]) -> FloatArray:
        arrays = [np.asarray(values[n], dtype=float) for n in names]
        shape = np.broadcast_shapes(*(a.shape for a in arrays)) if arrays else ()
        out = np.empty(shape)
        flat = [np.broadcast_to(a, shape).ravel() for a in arrays]
        o = out.ravel()
        for i in range(o.size):
            o[i] = _onset(expr, V, {n: float(f[i]) for n, f in zip(names, flat, strict=True)})
        return out

    return static
