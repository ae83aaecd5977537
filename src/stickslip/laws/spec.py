"""A friction law declared once: :class:`LawSpec` and its :class:`Parameter` s.

A law is declared by its dimensionless forward branch ``f_+(w)`` as a formula
(friction in units of the static friction force, ``w`` the slip velocity in units
of ``mu_s W / sqrt(k m)``), its parameters with bounds and help, its physical
parameters with units and the map from physical to dimensionless values. Every
thing else is derived here from that declaration, with sympy:

* the derivatives ``f^(n)`` the analyses need (stability, Hopf criticality),
  as vectorised numpy functions;
* the compiled kernel: the built-in laws have hand-tuned kernels in
  :mod:`stickslip.core.laws` (the declaration names their id, and the
  conformance tests check them against the formula); any other law gets numba
  code generated from its formula (:meth:`LawSpec.kernel_source`), with a
  continuation to ``w < 0`` by its Taylor polynomial at 0 (the integrator
  samples slightly negative velocities before it locates a stop);
* the physical law ``mu(v) = mu_s f(beta v)`` and the inverse map;
* validation of scalars and, vectorised, of whole sweep grids;
* the command-line options, the sweep tables and the docs table.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
import pint

from ..core.checks import refusal
from ..errors import ArgumentTypeError
from ..units import Q_, check_number, parse_quantity, ureg

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["STATIC", "LawSpec", "Parameter"]

FloatArray = npt.NDArray[np.float64]

#: the sympy symbols of the formulas, by name: the velocity of the dimensionless formulas
#: (``W``) and the scales of the physical-to-dimensionless map (``BETA``, ``MU_S``); made on
#: first use, so that declaring the built-in laws does not import sympy (0.3 s of a command's
#: start)
_SYMBOLS = {
    "W": ("w", {"real": True}),
    "BETA": ("beta", {"positive": True}),
    "MU_S": ("mu_s", {"positive": True}),
}


def _symbol(name: str) -> sp.Symbol:
    """Return the symbol ``W``, ``BETA`` or ``MU_S`` (sympy caches it: the same object each time)."""
    import sympy as sp

    text, assumptions = _SYMBOLS[name]
    return sp.Symbol(text, **assumptions)


def __getattr__(name: str) -> Any:
    """Return ``W``, ``BETA`` or ``MU_S``, made on first use (PEP 562)."""
    if name in _SYMBOLS:
        return _symbol(name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: degree of the Taylor polynomial that continues f_+ to w < 0
CONTINUATION_DEGREE = 10
#: the most nodes of that polynomial's coefficients in the parameters (shared subtrees once)
CONTINUATION_NODES = 20_000
#: derivatives up to this order are sympy's formulas; higher ones Taylor coefficients
SYMBOLIC_ORDER = 1


#: the largest magnitude of a dimensionless law parameter (the core's bound on its inputs)
KERNEL_BOUND = 1e15


@dataclass(frozen=True)
class Parameter:
    """One parameter of a friction law, with its bounds, unit and help.

    Parameters
    ----------
    name : str
        Name in Python, in the formula and (with ``-`` for ``_``) on the command line.
    help : str
        One line for the command line and the docs.
    unit : str, optional
        SI unit of a physical parameter (``"s/m"``); empty for a number.
    example : str, optional
        A valid value as a user would type it (``"160 s/m"``).
    lower, upper : float, optional
        Bounds (default: positive, no upper bound).
    lower_inclusive, upper_inclusive : bool, optional
        Whether the bounds themselves are allowed.
    default : float, optional
        Value when not given (SI for a physical parameter); None: required.
    aliases : tuple of str, optional
        Other names accepted on input (the paper's ``mu0`` for ``mu_s``).

    """

    name: str
    help: str
    unit: str = ""
    example: str = ""
    lower: float = 0.0
    upper: float = math.inf
    lower_inclusive: bool = False
    upper_inclusive: bool = False
    default: float | None = None
    aliases: tuple[str, ...] = ()

    @property
    def dimension(self) -> str:
        """Pint dimensionality of a physical parameter ("" for a number)."""
        if not self.unit:
            return ""
        return str(ureg.Unit(self.unit).dimensionality)

    @property
    def what(self) -> str:
        """What a valid value is, in words, for messages."""
        lo = (
            ""
            if self.lower == -math.inf
            else ("non-negative" if self.lower == 0 and self.lower_inclusive else "")
        )
        if self.lower == 0 and not self.lower_inclusive and self.upper == math.inf:
            kind = "a positive number"
        elif lo and self.upper == math.inf:
            kind = f"a {lo} number"
        elif self.upper == math.inf and self.lower == -math.inf:
            kind = "a finite number"
        else:
            a = "[" if self.lower_inclusive else "("
            b = "]" if self.upper_inclusive else ")"
            kind = f"a number in {a}{self.lower:g}, {self.upper:g}{b}"
        if self.unit:
            kind = kind.replace("number", f"quantity such as {self.example!r}")
        return kind

    def check(self, value: Any) -> float:
        """Return ``value`` in SI (a float) after checking its unit and bounds.

        Raises
        ------
        ArgumentTypeError
            For a value of the wrong type (a string for a number, ``None``, a plain number
            for a physical parameter), naming the parameter.
        ValueError
            For a value out of bounds, NaN, or of the wrong unit, naming the parameter,
            the value and what was expected.

        """
        if self.unit:
            q = parse_quantity(
                value,
                self.name,
                self.dimension,
                self.example or f"1 {self.unit}",
                allow_zero=True,
                allow_negative=True,
            )
            x = float(q.to(self.unit).magnitude)
        else:
            if isinstance(value, pint.Quantity):
                x = check_number(value, self.name, allow_zero=True, what=self.what)
            elif isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
                raise ArgumentTypeError(f"{self.name}={value!r}: expected {self.what}")
            else:
                x = float(value)
        self.check_array(np.array([x]), shown=value)
        return x

    def check_array(self, values: npt.ArrayLike, *, shown: Any = None, where: str = "") -> None:
        """Check SI values (any shape) against the bounds, in one vectorised pass.

        ``shown`` is the value as the user gave it, for the message: one for a
        scalar, or one per point (the same size as ``values``) for an array.

        Raises
        ------
        ValueError
            At the first bad value, naming it (and its point, for arrays).

        """
        x = np.asarray(values, dtype=float)
        ok = np.isfinite(x)
        ok &= (x >= self.lower) if self.lower_inclusive else (x > self.lower)
        if self.upper < math.inf:
            ok &= (x <= self.upper) if self.upper_inclusive else (x < self.upper)
        if not self.unit:  # a dimensionless value goes to the compiled kernels, which take |x| <= 1e15
            ok &= np.abs(x) <= KERNEL_BOUND
        if ok.all():
            return
        i = int(np.flatnonzero(~ok.ravel())[0])
        bad = float(x.ravel()[i])
        if shown is not None and np.ndim(shown) > 0:  # each point as the user gave it
            shown = np.ravel(np.asarray(shown, dtype=object))[i]
        v = shown if shown is not None else (Q_(bad, self.unit) if self.unit else bad)
        at = f" (point {i}{where})" if x.size > 1 else where
        why = refusal(bad, allow_zero=self.lower_inclusive)  # NaN, infinite, or below a lower bound of 0
        if why is not None and (self.lower == 0 or not math.isfinite(bad)):
            reason = why
        elif bad < self.lower or (bad == self.lower and not self.lower_inclusive):
            reason = "is too small"
        elif abs(bad) > KERNEL_BOUND and not self.unit:
            reason = f"is beyond {KERNEL_BOUND:g} in magnitude, the compiled kernels' range"
        else:
            reason = "is too large"
        raise ValueError(f"{self.name}={v!r} {reason}{at}: expected {self.what}")

    def quantity(self, si: float) -> Any:
        """Return an SI value as the user sees it (a pint quantity for a physical parameter)."""
        return Q_(si, self.unit) if self.unit else float(si)


def check_distinct(name: str, si: npt.ArrayLike, as_given: Sequence[str]) -> None:
    """Refuse a value given twice: a grid axis's coordinates must be distinct to be selected by.

    Parameters
    ----------
    name : str
        The parameter, for the message.
    si : array_like
        Its values in one unit (SI); equal within 1e-12 relative counts as the same.
    as_given : sequence of str
        Each value as the user gave it ('5 um/s'), for the message.

    Raises
    ------
    ValueError
        Naming the first value given twice and its two points.

    """
    si = np.asarray(si, dtype=float)
    order = np.argsort(si, kind="stable")
    ordered = si[order]
    same = np.flatnonzero(np.diff(ordered) <= 1e-12 * np.abs(ordered[1:]))  # 5 um/s and 0.005 mm/s too
    if same.size:
        i, j = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        twice = (
            f"{as_given[i]} is given twice (points {i} and {j})"
            if as_given[i] == as_given[j]
            else f"{as_given[i]} (point {i}) and {as_given[j]} (point {j}) are the same value"
        )
        raise ValueError(f"{name}: {twice}: expected distinct values")


#: the static friction coefficient of every physical law
STATIC = Parameter(
    "mu_s",
    "static friction coefficient mu_s: the friction force at rest is at most mu_s W",
    lower=0.0,
)


@dataclass(frozen=True, eq=False)
class LawSpec:
    """The declaration of a friction law; everything else is derived from it.

    Parameters
    ----------
    name : str
        Registry name and ``--law`` choice (``weakening``).
    title : str
        One line: what the law is.
    f : str
        Dimensionless forward branch ``f_+(w)`` (``w > 0``) as a formula in ``w``
        and the parameters, friction in units of the static friction force, e.g.
        ``"1/(1 + c*w) + p*w"``. Friction is odd in ``w`` and set-valued at rest.
    parameters : tuple of Parameter
        Dimensionless parameters, in the order of the compiled parameter vector.
    physical : tuple of Parameter, optional
        Physical parameters besides ``mu_s``, with units.
    to_dimensionless : mapping, optional
        For each dimensionless parameter, a formula in the physical parameters
        (SI), ``beta = sqrt(k m)/(mu_s W)`` (s/m) and ``mu_s``: ``{"c": "a/beta"}``.
    source : str, optional
        Citation.
    core_id : int, optional
        Id of a hand-tuned kernel in :mod:`stickslip.core.laws` (built-in laws);
        otherwise a kernel is generated from ``f``.
    map_parameters : tuple of str, optional
        The parameters a regime map may run over (default: all).
    check : callable, optional
        Extra vectorised validation of dimensionless values
        (``check(values: dict of arrays)``), e.g. a warning where friction turns negative.
    static_aliases : tuple of str, optional
        Other names of ``mu_s`` on input (``mu0``, the paper's name).
    notes : str, optional
        A paragraph for the docs.
    example : mapping, optional
        Typical dimensionless values (docs, ``--help`` examples, the conformance tests).
    expression : sympy.Expr, optional
        ``f`` already parsed (laws built from a user's formula), used instead of parsing ``f``.
    static_from : callable, optional
        ``mu_s`` from the physical values (SI arrays) where the law fixes it (a
        formula's ``mu(0+)``); None: ``mu_s`` is a parameter of its own.

    """

    name: str
    title: str
    f: str
    parameters: tuple[Parameter, ...]
    physical: tuple[Parameter, ...] = ()
    to_dimensionless: Mapping[str, str] = field(default_factory=dict)
    source: str = ""
    core_id: int | None = None
    map_parameters: tuple[str, ...] | None = None
    check: Callable[[Mapping[str, FloatArray]], None] | None = None
    static_aliases: tuple[str, ...] = ()
    notes: str = ""
    example: Mapping[str, float] = field(default_factory=dict)
    expression: sp.Expr | None = field(default=None, compare=False, repr=False)
    static_from: Callable[[Mapping[str, FloatArray]], FloatArray] | None = field(
        default=None, compare=False, repr=False
    )

    def __post_init__(self) -> None:
        names = [p.name for p in self.parameters]
        if len(set(names)) != len(names):
            raise ValueError(f"law {self.name!r}: parameter names repeat: {names}")
        from ..core.laws import N_LAW_PARAMS

        if len(names) > N_LAW_PARAMS:
            raise ValueError(f"law {self.name!r}: {len(names)} parameters, at most {N_LAW_PARAMS}")
        for reserved in ("w",):
            if reserved in names:
                raise ValueError(f"law {self.name!r}: the parameter name {reserved!r} is reserved")
        if self.core_id is None:
            # a built-in law's formulas are checked by the tests (``check_formulas``), not at
            # every import: sympy's solve for the inverse map took half a second
            self.check_formulas()

    def check_formulas(self) -> None:
        """Check the formulas: ``f`` uses only the parameters; the physical map can be inverted.

        Raises
        ------
        ValueError
            Naming the law and what is wrong.

        """
        names = [p.name for p in self.parameters]
        free = {s.name for s in self.expr.free_symbols} - {"w"}
        if free - set(names):
            raise ValueError(f"law {self.name!r}: f uses {sorted(free - set(names))}, not parameters")
        if self.physical:
            if set(self.to_dimensionless) != set(names):
                raise ValueError(f"law {self.name!r}: to_dimensionless must give each of {names}")
            self._inverse  # noqa: B018  (checks that the map can be inverted)

    # ------------------------------------------------------------------ symbols

    @functools.cached_property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        """Symbols of the dimensionless parameters, in order."""
        import sympy as sp

        return tuple(sp.Symbol(p.name, real=True) for p in self.parameters)

    @functools.cached_property
    def expr(self) -> sp.Expr:
        """``f_+(w)`` as a sympy expression."""
        import sympy as sp

        from .formula import parse_formula

        e = (
            self.expression
            if self.expression is not None
            else parse_formula(self.f, f"law {self.name!r}: f", ("w",))
        )
        return e.subs(
            {sp.Symbol(p.name, real=True): s for p, s in zip(self.parameters, self.symbols, strict=True)}
        )

    @functools.cache  # noqa: B019  (specs live for the whole run)
    def derivative(self, order: int) -> sp.Expr:
        """``d^n f_+ / d w^n`` as a sympy expression."""
        import sympy as sp

        W = _symbol("W")
        return sp.diff(self.expr, W, order) if order else self.expr

    @functools.cache  # noqa: B019
    def numpy_function(self, order: int) -> Callable[..., Any]:
        """``f_+^(n)(w, *params)`` as a vectorised numpy function.

        Orders above :data:`SYMBOLIC_ORDER` are Taylor coefficients of the formula's nodes
        (:func:`~.series.derivatives`): sympy's third derivative of a formula nested 40
        deep took minutes; where a node has no series rule, sympy differentiates.
        """
        import sympy as sp

        from .series import Unsupported, derivatives

        W = _symbol("W")
        if order > SYMBOLIC_ORDER:
            try:
                derivatives(self.expr, W, self.symbols, np.zeros(1), [0.0] * len(self.symbols), order)
            except Unsupported:
                pass
            else:
                return functools.partial(_jet, self.expr, self.symbols, order)
        return sp.lambdify((W, *self.symbols), self.derivative(order), modules=["scipy", "numpy"])

    @functools.cache  # noqa: B019
    def scalar_function(self, order: int) -> Callable[..., float]:
        """``f_+^(n)(w, *params)`` for Python floats (``math``; no array overhead)."""
        import sympy as sp

        W = _symbol("W")
        return sp.lambdify((W, *self.symbols), self.derivative(order), modules="math")

    def evaluate_scalar(self, w: float, values: Sequence[float], order: int = 0) -> float:
        """Return ``f_+^(n)(w)`` at one velocity (NaN where the formula is not defined).

        A built-in law's friction and slope at ``w > 0`` are its hand-written kernel's
        (:mod:`stickslip.core.laws`, the same formula, checked against it by the
        conformance tests): a one-block command then needs no sympy (0.3 s of its start).
        """
        if order > SYMBOLIC_ORDER:
            return float(self.evaluate(np.array([w]), values, order)[0])
        if self.core_id is not None and w > 0.0:
            return float(_core_function(self.core_id, order)(self.core_id, _kernel_params(values), float(w)))
        try:
            return float(self.scalar_function(order)(float(w), *values))
        except (ValueError, ZeroDivisionError, OverflowError, TypeError):
            return float(self.evaluate(np.array([w]), values, order)[0])

    def evaluate(self, w: npt.ArrayLike, values: Sequence[Any], order: int = 0) -> FloatArray:
        """Return ``f_+^(n)(w)`` for parameter values (scalars or arrays that broadcast with ``w``)."""
        w = np.asarray(w, dtype=float)
        old = np.seterr(all="ignore")  # a formula may overflow where the caller does not look
        try:
            out = np.asarray(self.numpy_function(order)(w, *values), dtype=float)
        finally:
            np.seterr(**old)
        if all(isinstance(v, float | int) for v in values):
            shape = w.shape
        else:
            shape = np.broadcast_shapes(w.shape, *(np.shape(v) for v in values))
        return out if out.shape == shape else np.broadcast_to(out, shape).copy()

    @functools.cached_property
    def continuation(self) -> sp.Expr:
        """Taylor polynomial of ``f_+`` at ``w = 0`` for ``w < 0`` (:attr:`continuation_coefficients`)."""
        import sympy as sp

        W = _symbol("W")
        return sp.Add(*(c * W**k for k, c in enumerate(self.continuation_coefficients)))

    @functools.cached_property
    def continuation_coefficients(self) -> tuple[sp.Expr, ...]:
        """Coefficients of ``f_+``'s Taylor polynomial at 0 (:data:`CONTINUATION_DEGREE`), lowest first.

        Where ``f_+`` is not smooth at 0 (``sqrt(w)``), the polynomial stops at the
        last finite derivative (a constant at least); where its coefficients in the
        parameters grow past :data:`CONTINUATION_NODES` nodes, at the last degree
        within them (the continuation serves the few steps past a stop, which the
        integrator's error control checks).
        """
        from .series import Unsupported, node_count, taylor

        W = _symbol("W")
        try:
            coefficients = taylor(self.expr, W, CONTINUATION_DEGREE)
        except Unsupported:  # a node without a series rule, or not smooth at 0: derivatives
            coefficients = self._derived_coefficients()
        terms: list[sp.Expr] = []
        size = 0
        for c in coefficients:
            # infinite, a limit sympy cannot take (sign(w - 0.5) inside), or beyond double
            # precision (1/(1 + 1e200*w): 1e400 w**2)
            if not _finite(c):
                break
            size += node_count(c, CONTINUATION_NODES)
            if terms and size > CONTINUATION_NODES:
                break
            terms.append(c)
        if not terms:
            raise ValueError(
                f"law {self.name!r}: f_+(0+) is not finite; friction at the onset of slip must be"
            )
        return tuple(terms)

    def _derived_coefficients(self) -> list[sp.Expr]:
        """Taylor coefficients at 0 by successive derivatives and limits, while they stay small."""
        import sympy as sp

        from .series import node_count

        W = _symbol("W")
        out: list[sp.Expr] = []
        d = self.expr
        bad = (sp.zoo, sp.oo, -sp.oo, sp.nan)
        for k in range(CONTINUATION_DEGREE + 1):
            if k:
                d = sp.diff(d, W)
                if node_count(d, CONTINUATION_NODES) > CONTINUATION_NODES:
                    break
            c = d.subs(W, 0)
            if c.has(*bad):
                c = sp.limit(d, W, 0, "+")
            out.append(c / sp.factorial(k))
            if c.has(*bad, sp.Limit):
                break
        return out

    # ------------------------------------------------------------------ kernel

    def kernel_source(self) -> str:
        """Return the numba module of this law's kernel (the functions of :mod:`stickslip.core.laws`)."""
        from .codegen import law_module_source

        return law_module_source(
            self.expr, self.derivative(1), self.continuation_coefficients, self.symbols, self.name
        )

    def kernel(self) -> Any:
        """Return the compiled kernel (:class:`~stickslip.core.api.Kernel`) of this law."""
        from .compiler import builtin_kernel, compile_kernel, slow_notice

        if self.core_id is not None:
            # the engine compiled with this law alone: the same code as the built-in
            # engine's for it, compiled in less time (no switch over the four laws)
            return builtin_kernel(self.core_id, self.name)
        with slow_notice(f"preparing the kernel of {self.title} (its slope and continuation below w = 0)"):
            source = self.kernel_source()
        return compile_kernel(source, self.name)

    # ------------------------------------------------------------------ physical form

    @functools.cached_property
    def _mapping(self) -> dict[str, sp.Expr]:
        import sympy as sp

        from .formula import parse_formula

        BETA, MU_S = _symbol("BETA"), _symbol("MU_S")
        phys = {p.name: sp.Symbol(p.name, real=True) for p in self.physical}
        local = ("beta", "mu_s")
        out = {}
        for k, text in self.to_dimensionless.items():
            e = parse_formula(text, f"law {self.name!r}: to_dimensionless[{k!r}]", local)
            e = e.subs({sp.Symbol("beta", real=True): BETA, sp.Symbol("mu_s", real=True): MU_S})
            e = e.subs({sp.Symbol(n, real=True): s for n, s in phys.items()})
            unknown = {s.name for s in e.free_symbols} - set(phys) - {"beta", "mu_s"}
            if unknown:
                raise ValueError(
                    f"law {self.name!r}: to_dimensionless[{k!r}] uses unknown names {sorted(unknown)}"
                )
            out[k] = e
        return out

    @functools.cached_property
    def _inverse(self) -> dict[str, sp.Expr]:
        """Each physical parameter from the dimensionless ones (the map solved by sympy)."""
        import sympy as sp

        out = {}
        for p in self.physical:
            sym = sp.Symbol(p.name, real=True)
            using = [k for k, e in self._mapping.items() if e.has(sym)]
            if len(using) != 1:
                raise ValueError(
                    f"law {self.name!r}: the physical parameter {p.name!r} must enter exactly one "
                    f"dimensionless parameter (it enters {using})"
                )
            k = using[0]
            nd = sp.Symbol(f"nd_{k}", real=True)  # the dimensionless value (its name may be p.name)
            sol = sp.solve(sp.Eq(nd, self._mapping[k]), sym, dict=True)
            if len(sol) != 1:
                raise ValueError(f"law {self.name!r}: cannot solve {k} = {self._mapping[k]} for {p.name}")
            out[p.name] = sol[0][sym].subs(nd, sp.Symbol(k, real=True))
        return out

    @functools.cached_property
    def _to_dimensionless_fn(self) -> Callable[..., Any]:
        import sympy as sp

        BETA, MU_S = _symbol("BETA"), _symbol("MU_S")
        args = (*[sp.Symbol(p.name, real=True) for p in self.physical], BETA, MU_S)
        out = [self._mapping[p.name] for p in self.parameters]
        return sp.lambdify(args, out, modules=["scipy", "numpy"], dummify=True)

    @functools.cached_property
    def _to_physical_fn(self) -> Callable[..., Any]:
        import sympy as sp

        BETA, MU_S = _symbol("BETA"), _symbol("MU_S")
        args = (*[sp.Symbol(p.name, real=True) for p in self.parameters], BETA, MU_S)
        out = [self._inverse[p.name] for p in self.physical]
        return sp.lambdify(args, out, modules=["scipy", "numpy"], dummify=True)

    def dimensionless_values(
        self, physical_si: Mapping[str, npt.ArrayLike], beta: npt.ArrayLike, mu_s: npt.ArrayLike
    ) -> dict[str, FloatArray]:
        """Map physical values (SI, scalars or arrays) to the dimensionless parameters, vectorised."""
        args = [np.asarray(physical_si[p.name], dtype=float) for p in self.physical]
        vals = self._to_dimensionless_fn(*args, np.asarray(beta, dtype=float), np.asarray(mu_s, dtype=float))
        shape = np.broadcast_shapes(np.shape(beta), np.shape(mu_s), *(np.shape(a) for a in args))
        return {
            p.name: np.asarray(np.broadcast_to(v, shape), dtype=float)
            for p, v in zip(self.parameters, vals, strict=True)
        }

    def physical_values(self, values: Mapping[str, float], beta: float, mu_s: float) -> dict[str, float]:
        """Map dimensionless values to the physical parameters (SI) for ``beta`` (s/m) and ``mu_s``."""
        out = self._to_physical_fn(*[values[p.name] for p in self.parameters], beta, mu_s)
        return {p.name: float(v) for p, v in zip(self.physical, out, strict=True)}

    @functools.cached_property
    def physical_expr(self) -> sp.Expr:
        """``mu(v) = mu_s f(beta v)`` in the physical parameters (``v`` in m/s)."""
        import sympy as sp

        W, BETA, MU_S = _symbol("W"), _symbol("BETA"), _symbol("MU_S")
        v = sp.Symbol("v", positive=True)
        e = self.expr.subs(W, BETA * v).subs(
            {s: self._mapping[p.name] for p, s in zip(self.parameters, self.symbols, strict=True)}
        )
        return sp.simplify(MU_S * e)

    # ------------------------------------------------------------------ validation

    def validate(self, values: Mapping[str, npt.ArrayLike], *, where: str = "") -> None:
        """Check dimensionless values (scalars or whole grids) against the bounds and the law's check."""
        arrays = {p.name: np.asarray(values[p.name], dtype=float) for p in self.parameters}
        for p in self.parameters:
            p.check_array(arrays[p.name], where=where)
        if self.check is not None:
            self.check(arrays)

    def parameter(self, name: str) -> Parameter:
        """Return the dimensionless or physical parameter ``name`` (or an alias of ``mu_s``)."""
        for p in (*self.parameters, *self.physical):
            if p.name == name:
                return p
        if name == "mu_s" or name in self.static_aliases:
            return STATIC
        raise KeyError(name)

    @property
    def mappable(self) -> tuple[str, ...]:
        """Parameters a regime map may run over."""
        return (
            self.map_parameters if self.map_parameters is not None else tuple(p.name for p in self.parameters)
        )

    def latex(self) -> str:
        """``f_+(w)`` in LaTeX."""
        import sympy as sp

        return sp.latex(self.expr)


def _jet(expr: sp.Expr, symbols: Sequence[sp.Symbol], order: int, w: Any, *values: Any) -> FloatArray:
    """``d^order expr / dw^order`` at ``w`` by series arithmetic (:func:`~.series.derivatives`)."""
    from .series import derivatives

    W = _symbol("W")
    return derivatives(expr, W, symbols, w, values, order)


def _finite(expr: sp.Expr) -> bool:
    """Whether every number in ``expr`` is finite in double precision and no limit is left in it.

    Walks the distinct parts once (a Taylor coefficient shares its subtrees: as a tree it
    is exponentially larger).
    """
    import sympy as sp

    from .formula import _float
    from .series import distinct_nodes

    for node in distinct_nodes(expr):
        if node.is_Number:
            if not math.isfinite(_float(node)):
                return False
        elif node in (sp.zoo, sp.nan) or isinstance(node, sp.Limit):
            return False
    return True


@functools.cache
def _core_function(core_id: int, order: int) -> Callable[..., float]:
    """Return a built-in law's compiled ``f_+`` (order 0) or ``f_+'`` (order 1)."""
    from ..core import laws

    return getattr(laws, f"{laws.LAW_PREFIX[core_id]}_{'f' if order == 0 else 'df'}")


def _kernel_params(values: Sequence[float]) -> tuple[float, ...]:
    """Return the kernel's parameter tuple: the law's values, then zeros to its eight places."""
    from ..core.laws import N_LAW_PARAMS

    return tuple(float(v) for v in values) + (0.0,) * (N_LAW_PARAMS - len(values))
