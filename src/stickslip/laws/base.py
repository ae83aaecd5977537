"""Friction laws as values: a declaration (:class:`~.spec.LawSpec`) and its parameters.

:class:`DimensionlessLaw` is a law in the model's units (friction in units of the
static friction force ``mu_s W`` against the slip velocity in units of
``mu_s W / sqrt(k m)``); :class:`PhysicalLaw` is the same law with units (the
friction coefficient against a velocity). Each law's module declares its spec
and two small classes bound to it (``WeakeningLaw``, ``PhysicalWeakeningLaw``);
every behaviour is here, derived from the spec. Both are immutable and
hashable, compare by value and pickle by value (for Dask workers).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt
import pint

from ..errors import ArgumentTypeError
from ..units import Q_, parse_quantity
from .spec import STATIC, LawSpec, Parameter

__all__ = [
    "DimensionlessLaw",
    "PhysicalLaw",
    "law_arrays",
    "require_dimensionless_law",
    "require_physical_law",
]

FloatArray = npt.NDArray[np.float64]
_ONE_S_PER_M = 1.0  # beta in s/m at which a physical law is evaluated (mu(v) does not depend on it)


def _bind(
    cls_name: str, params: tuple[Parameter, ...], args: tuple[Any, ...], kwargs: dict[str, Any]
) -> dict[str, Any]:
    names = [p.name for p in params]
    if len(args) > len(names):
        raise TypeError(f"{cls_name} takes {len(names)} parameters ({', '.join(names)}), got {len(args)}")
    given = dict(zip(names, args, strict=False))
    for k, v in kwargs.items():
        if k not in names:
            raise TypeError(f"{cls_name}: unknown parameter {k!r}; expected {', '.join(names)}")
        if k in given:
            raise TypeError(f"{cls_name}: {k!r} given twice")
        given[k] = v
    return given


class DimensionlessLaw:
    """A friction law in dimensionless form: ``f(w)``, friction in units of static friction.

    Construct a law through its class (``WeakeningLaw(c=3.8)``), by name
    (``stickslip.laws.get("weakening").dimensionless(c=3.8)``) or from a formula
    (:class:`~stickslip.laws.expression.ExpressionLaw`). The parameters are
    attributes (``law.c``); :attr:`params` has them all.

    Friction is odd in ``w`` and set-valued at rest: the static threshold is 1.
    """

    __slots__ = ("_values", "spec")
    _spec: ClassVar[LawSpec | None] = None
    static_threshold: ClassVar[float] = 1.0
    spec: LawSpec
    _values: tuple[float, ...]

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        spec = type(self)._spec
        if spec is None:
            raise TypeError(
                "DimensionlessLaw is the base class: use a law's class (WeakeningLaw(c=3.8)), "
                "stickslip.laws.get(name).dimensionless(...), or ExpressionLaw('...')"
            )
        self._set(spec, args, kwargs)

    def _set(self, spec: LawSpec, args: tuple[Any, ...], kwargs: dict[str, Any]) -> None:
        given = _bind(type(self).__name__, spec.parameters, args, kwargs)
        values = []
        for p in spec.parameters:
            if p.name in given:
                values.append(p.check(given[p.name]))
            elif p.default is not None:
                values.append(float(p.default))
            else:
                raise TypeError(f"{type(self).__name__}: missing parameter {p.name!r} ({p.help})")
        spec.validate(dict(zip([p.name for p in spec.parameters], values, strict=True)))
        object.__setattr__(self, "spec", spec)
        object.__setattr__(self, "_values", tuple(values))

    @classmethod
    def _from_values(cls, spec: LawSpec, values: Mapping[str, float]) -> DimensionlessLaw:
        """Return a law of ``spec`` with the given values (checked)."""
        law = object.__new__(cls)
        law._set(spec, (), dict(values))
        return law

    # ------------------------------------------------------------------ value semantics

    def __getattr__(self, name: str) -> float:
        try:
            spec = object.__getattribute__(self, "spec")
            values = object.__getattribute__(self, "_values")
        except AttributeError:
            raise AttributeError(name) from None
        for p, v in zip(spec.parameters, values, strict=True):
            if p.name == name:
                return v
        raise AttributeError(f"{type(self).__name__} has no attribute or parameter {name!r}")

    def __setattr__(self, name: str, value: Any) -> None:
        raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}: laws are immutable")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, DimensionlessLaw):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def _key(self) -> tuple[Any, ...]:
        return (self.spec.name, self.spec.f, self._values)

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({args})"

    def __reduce__(self) -> tuple[Any, ...]:
        from .registry import rebuild_dimensionless

        return rebuild_dimensionless, (self.spec.name, self.params)

    # ------------------------------------------------------------------ parameters

    @property
    def name(self) -> str:
        """The law's registry name (``weakening``)."""
        return self.spec.name

    @property
    def params(self) -> dict[str, float]:
        """The parameters, by name."""
        return {p.name: v for p, v in zip(self.spec.parameters, self._values, strict=True)}

    def replace(self, **changes: float) -> DimensionlessLaw:
        """Return a copy with some parameters changed (checked)."""
        return type(self)._from_values(self.spec, {**self.params, **changes})

    def core_params(self) -> FloatArray:
        """Return the parameter vector of the compiled kernel."""
        return np.array(self._values, dtype=np.float64)

    @property
    def kernel(self) -> Any:
        """The compiled kernel (:class:`~stickslip.core.api.Kernel`) of the law."""
        return self.spec.kernel()

    def arrays(self) -> tuple[Any, FloatArray]:
        """Return the compiled kernel and the parameter vector, padded to the kernels' width.

        What the core's functions take (:func:`~stickslip.core.api.run_attractors`):
        ``kernel, lp = law.arrays()``.
        """
        from ..core.laws import N_LAW_PARAMS

        lp = np.zeros(N_LAW_PARAMS)
        cp = np.asarray(self.core_params(), dtype=np.float64)
        lp[: cp.size] = cp
        return self.kernel, lp

    # ------------------------------------------------------------------ values

    def forward(self, w: npt.ArrayLike, order: int = 0) -> FloatArray:
        """Return the ``order``-th derivative of the forward branch ``f_+(w)`` (for ``w > 0``)."""
        return self.spec.evaluate(w, self._values, order)

    def at(self, w: float, order: int = 0) -> float:
        """Return ``f_+^(n)(w)`` at one velocity, as a float (faster than :meth:`forward` for one point)."""
        return self.spec.evaluate_scalar(w, self._values, order)

    def value(self, w: npt.ArrayLike) -> FloatArray:
        """Return the friction force ``f(w)`` (units of static friction), odd in ``w``.

        Parameters
        ----------
        w : array_like
            Slip velocity (units of ``mu_s W / sqrt(k m)``).

        Returns
        -------
        numpy.ndarray
            ``sign(w) f_+(|w|)``; 0 at ``w = 0``, where the law is set-valued.

        """
        w = np.asarray(w, dtype=float)
        return np.where(w == 0.0, 0.0, np.sign(w) * self.forward(np.abs(w)))

    def derivative(self, w: npt.ArrayLike, order: int = 1) -> FloatArray:
        """Return the ``order``-th derivative of :meth:`value` for ``w != 0``.

        The odd extension gives ``f^(n)(-w) = (-1)^(n+1) f^(n)(w)``.
        """
        if not isinstance(order, int) or isinstance(order, bool):
            raise ArgumentTypeError(f"order={order!r}: expected an integer >= 1")
        if order < 1:
            raise ValueError(f"order={order!r}: expected an integer >= 1")
        w = np.asarray(w, dtype=float)
        sign = np.where(w < 0, (-1.0) ** (order + 1), 1.0)
        return np.asarray(sign * self.forward(np.abs(w), order), dtype=float)

    @property
    def kinetic_limit(self) -> float:
        """Friction just after breakaway, ``f(0+)`` (units of static friction)."""
        return float(self.forward(np.zeros(1))[0])

    def range_warning(self, w_max: float) -> str | None:
        """Say so when a motion reaching velocity ``w_max`` leaves where the law is known (tables).

        ``w_max`` NaN means the motion could not be followed (a table names the
        likeliest cause: its extrapolation reaching zero friction).
        """
        return None

    def motion_warning(self, w_max: npt.ArrayLike, failed: bool) -> str | None:
        """Return :meth:`range_warning` for a set of motions.

        Where a motion could not be followed (``failed``) the law's reason for that
        comes first; else the largest finite ``w_max`` reached is judged.
        """
        reached = np.asarray(w_max, dtype=float)
        reached = reached[np.isfinite(reached)]
        return (self.range_warning(math.nan) if failed else None) or (
            self.range_warning(float(reached.max())) if reached.size else None
        )

    def breakpoints(self) -> FloatArray:
        """Return the velocities ``w > 0`` where ``f''`` may jump (a table's rows); none for a formula."""
        return np.empty(0)

    def hopf_note(self, nu: float, criticality: str) -> str | None:
        """Say what a Hopf point at a breakpoint ``nu`` owes to the law's construction (tables)."""
        return None

    # ------------------------------------------------------------------ physical form

    def to_physical(self, beta: Any, mu_s: float) -> PhysicalLaw:
        """Return the physical law for the scale ``beta = sqrt(k m)/(mu_s W)`` and ``mu_s``."""
        from .registry import physical_class

        b = float(parse_quantity(beta, "beta", "[time] / [length]", "42 s/m").to("s/m").magnitude)
        si = self.spec.physical_values(self.params, b, float(mu_s))
        cls = physical_class(self.spec)
        return cls._from_values(self.spec, float(mu_s), si)

    def describe(self) -> str:
        """One line: the law, its formula and its parameters."""
        pars = ", ".join(f"{k} = {v:.6g}" for k, v in self.params.items())
        return f"{self.name}: f(w) = {self.spec.f}" + (f" with {pars}" if pars else "")


class PhysicalLaw:
    """A friction law with units: the friction coefficient against the slip velocity.

    ``mu(v) = mu_s f(beta v)``, with the dimensionless law's parameters from the
    physical ones (:attr:`LawSpec.to_dimensionless`). ``mu_s`` is the static
    friction coefficient of every law (the paper's ``mu0`` for its law).
    """

    __slots__ = ("_values", "mu_s", "spec")
    _spec: ClassVar[LawSpec | None] = None
    spec: LawSpec
    mu_s: float
    _values: tuple[float, ...]

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        spec = type(self)._spec
        if spec is None:
            raise TypeError(
                "PhysicalLaw is the base class: use a law's class (PhysicalWeakeningLaw(mu_s=0.46, "
                "a='160 s/m')) or stickslip.laws.get(name).physical(...)"
            )
        self._set(spec, args, kwargs)

    def _set(self, spec: LawSpec, args: tuple[Any, ...], kwargs: dict[str, Any]) -> None:
        kwargs = dict(kwargs)
        static = STATIC
        for alias in spec.static_aliases:
            if alias in kwargs:
                if "mu_s" in kwargs:
                    raise TypeError(f"{type(self).__name__}: give mu_s or {alias}, not both")
                kwargs["mu_s"] = kwargs.pop(alias)
                static = dataclasses.replace(STATIC, name=alias)
        given = _bind(type(self).__name__, (STATIC, *spec.physical), args, kwargs)
        if "mu_s" not in given:
            raise TypeError(f"{type(self).__name__}: missing the static friction coefficient mu_s")
        mu_s = static.check(given["mu_s"])
        si = {}
        for p in spec.physical:
            if p.name in given:
                si[p.name] = p.check(given[p.name])
            elif p.default is not None:
                si[p.name] = float(p.default)
            else:
                raise TypeError(f"{type(self).__name__}: missing parameter {p.name!r} ({p.help})")
        self._validate(spec, mu_s, si)
        object.__setattr__(self, "spec", spec)
        object.__setattr__(self, "mu_s", mu_s)
        object.__setattr__(self, "_values", tuple(si[p.name] for p in spec.physical))

    @staticmethod
    def _validate(spec: LawSpec, mu_s: Any, si: Mapping[str, Any], where: str = "") -> None:
        """Check what the physical values map to (at beta = 1 s/m: bounds do not depend on it)."""
        nd = spec.dimensionless_values(si, _ONE_S_PER_M, mu_s)
        try:
            spec.validate(nd, where=where)
        except ValueError as exc:
            bad = str(exc).split("=", 1)[0]
            if bad not in spec.to_dimensionless:
                raise
            formula = spec.to_dimensionless[bad]
            used = [p for p in spec.physical if p.name in formula] + ([STATIC] if "mu_s" in formula else [])
            names = ", ".join(
                f"{p.name}={p.quantity(float(np.ravel(mu_s if p is STATIC else si[p.name])[0]))!r}"
                for p in used
            )
            raise ValueError(f"{names}: {bad} = {formula}: {exc}") from None

    @classmethod
    def _from_values(cls, spec: LawSpec, mu_s: float, si: Mapping[str, float]) -> PhysicalLaw:
        law = object.__new__(cls)
        law._set(spec, (), {"mu_s": mu_s, **{k: spec.parameter(k).quantity(v) for k, v in si.items()}})
        return law

    # ------------------------------------------------------------------ value semantics

    def __getattr__(self, name: str) -> Any:
        try:
            spec = object.__getattribute__(self, "spec")
            values = object.__getattribute__(self, "_values")
        except AttributeError:
            raise AttributeError(name) from None
        if name in spec.static_aliases:
            return object.__getattribute__(self, "mu_s")
        for p, v in zip(spec.physical, values, strict=True):
            if p.name == name:
                return p.quantity(v)
        raise AttributeError(f"{type(self).__name__} has no attribute or parameter {name!r}")

    def __setattr__(self, name: str, value: Any) -> None:
        raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}: laws are immutable")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PhysicalLaw):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def _key(self) -> tuple[Any, ...]:
        return (self.spec.name, self.spec.f, self.mu_s, self._values)

    def __repr__(self) -> str:
        args = ", ".join([f"mu_s={self.mu_s!r}", *(f"{k}={v!r}" for k, v in self.params.items())])
        return f"{type(self).__name__}({args})"

    def __reduce__(self) -> tuple[Any, ...]:
        from .registry import rebuild_physical

        return rebuild_physical, (self.spec.name, self.mu_s, self.si_parameters())

    @property
    def name(self) -> str:
        """The law's registry name."""
        return self.spec.name

    @property
    def params(self) -> dict[str, Any]:
        """The physical parameters besides ``mu_s`` (quantities, numbers where dimensionless)."""
        return {p.name: p.quantity(v) for p, v in zip(self.spec.physical, self._values, strict=True)}

    def si_parameters(self) -> dict[str, float]:
        """Return the physical parameters besides ``mu_s`` as SI numbers."""
        return {p.name: v for p, v in zip(self.spec.physical, self._values, strict=True)}

    def replace(self, **changes: Any) -> PhysicalLaw:
        """Return a copy with some parameters changed (``mu_s`` included; checked)."""
        mu_s = changes.pop("mu_s", self.mu_s)
        values = {**self.params, **changes}
        law = object.__new__(type(self))
        law._set(self.spec, (), {"mu_s": mu_s, **values})
        return law

    # ------------------------------------------------------------------ values

    def nondimensionalize(self, beta: Any) -> DimensionlessLaw:
        """Return the dimensionless law for ``beta = sqrt(k m)/(mu_s W)`` (time/length)."""
        from .registry import dimensionless_class

        b = float(parse_quantity(beta, "beta", "[time] / [length]", "42 s/m").to("s/m").magnitude)
        nd = self.spec.dimensionless_values(self.si_parameters(), b, self.mu_s)
        return dimensionless_class(self.spec)._from_values(self.spec, {k: float(v) for k, v in nd.items()})

    def coefficient(self, v: Any) -> FloatArray:
        """Return the friction coefficient ``mu(v)`` at slip velocity ``v`` (0 at ``v = 0``), odd in ``v``."""
        x = _velocity(v)
        return self.mu_s * self.nondimensionalize(Q_(_ONE_S_PER_M, "s/m")).value(x)

    def value(self, v: Any) -> FloatArray:
        """Return the friction coefficient at slip velocity ``v`` (as :meth:`coefficient`)."""
        return self.coefficient(v)

    def derivative(self, v: Any, order: int = 1) -> pint.Quantity:
        """Return ``d^n mu / dv^n`` at ``v != 0``, in units of ``(s/m)**order``."""
        x = _velocity(v)
        d = self.nondimensionalize(Q_(_ONE_S_PER_M, "s/m")).derivative(x, order)
        return Q_(self.mu_s * d, f"(s/m)**{order}")

    @property
    def static_threshold(self) -> float:
        """Static friction coefficient: the threshold of ``|mu|`` at rest (``mu_s``)."""
        return self.mu_s

    def describe(self) -> str:
        """One line: the law and its parameters."""
        pars = ", ".join(
            [
                f"mu_s = {self.mu_s:.6g}",
                *(
                    f"{k} = {v:~P}" if isinstance(v, pint.Quantity) else f"{k} = {v:.6g}"
                    for k, v in self.params.items()
                ),
            ]
        )
        return f"{self.name}: mu(v) = mu_s f(beta v), f(w) = {self.spec.f}; {pars}"


def _velocity(v: Any) -> FloatArray:
    if isinstance(v, str):
        v = parse_quantity(v, "v", "[length] / [time]", "5 um/s", allow_zero=True)
    if not isinstance(v, pint.Quantity):
        raise ArgumentTypeError(f"v={v!r}: expected a velocity with units, such as '5 um/s'")
    if not v.check("[length] / [time]"):
        raise ValueError(f"v={v!r}: expected a velocity with units, such as '5 um/s'")
    return np.asarray(v.to("m/s").magnitude, dtype=float)


def require_dimensionless_law(law: Any, name: str = "law") -> DimensionlessLaw:
    """Return ``law`` after checking that it is a dimensionless friction law.

    Raises
    ------
    TypeError
        Naming the argument and what it is instead.

    """
    if not isinstance(law, DimensionlessLaw):
        raise TypeError(
            f"{name}={law!r} (type {type(law).__name__}): expected a dimensionless friction law such as "
            "WeakeningLaw(c=3.8), CubicLaw(alpha=0.5, gamma=0.17), CoulombLaw(kinetic=0.5) or "
            "ExpressionLaw('1/(1 + 3.8*w)'); PhysicalParameters(...).dimensionless().law converts "
            "a physical set-up"
        )
    return law


def require_physical_law(law: Any, name: str = "law") -> PhysicalLaw:
    """Return ``law`` after checking that it is a physical friction law (an ArgumentTypeError otherwise)."""
    if not isinstance(law, PhysicalLaw):
        raise ArgumentTypeError(
            f"{name}={law!r}: expected a physical law (PhysicalWeakeningLaw, PhysicalCubicLaw, "
            "PhysicalCoulombLaw, ExpressionLaw(mu=...), TabulatedLaw)"
        )
    return law


def law_arrays(law: DimensionlessLaw) -> tuple[Any, np.ndarray]:
    """Return the compiled kernel and the parameter vector of ``law`` (:meth:`DimensionlessLaw.arrays`)."""
    return law.arrays()
