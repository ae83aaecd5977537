"""The plane of a two-parameter diagram: two axes and the model at each point of it.

A :class:`Plane` maps a point ``(x, y)`` of its two axes to the one-block model there:
the driving velocity ``nu`` and the dimensionless law's parameter values. Its axes are

- in dimensionless form (:meth:`Plane.dimensionless`): ``nu`` and a parameter of the
  law, or two parameters of the law at a fixed ``nu``;
- in physical units (:meth:`Plane.physical`): any two of the driving velocity ``v0``,
  the ``stiffness``, ``mass`` and ``load``, and the law's physical parameters, the other
  values those of a :class:`~stickslip.models.parameters.PhysicalParameters` set-up.

The continuation works in the unit square: ``u = (log p - log lo) / (log hi - log lo)``
on a logarithmic axis, ``(p - lo) / (hi - lo)`` on a linear one, so a step is the same
fraction of each axis. The law is evaluated from its specification and a value vector
(no law object per point: building and checking one costs 11 ms for an expression law,
the formula 2 us).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw, require_dimensionless_law
from ..models.parameters import PhysicalParameters

__all__ = ["Axes", "Axis", "LawPoint", "Plane"]

#: the physical quantities a plane's axis may be, besides the law's parameters, and their SI units
PHYSICAL_AXES = {"v0": "m/s", "stiffness": "N/m", "mass": "kg", "load": "N"}
#: the unit an axis of a physical plane is shown in (SI values are divided by the factor)
SHOWN = {"v0": ("um/s", 1e-6), "stiffness": ("N/m", 1.0), "mass": ("kg", 1.0), "load": ("N", 1.0)}


@dataclass(frozen=True)
class Axis:
    """One axis of a plane: its name, range, scale and unit.

    ``lo`` and ``hi`` are in the axis' own unit (``unit``: ``1`` for a dimensionless
    one); ``log`` makes the axis logarithmic (both ends positive).
    """

    name: str
    lo: float
    hi: float
    log: bool
    unit: str = "1"
    factor: float = 1.0  # SI value = shown value * factor

    def to_unit(self, u: float) -> float:
        """Return the value at the fraction ``u`` of the axis (axis unit)."""
        if self.log:
            return float(self.lo * (self.hi / self.lo) ** u)
        return float(self.lo + u * (self.hi - self.lo))

    def from_value(self, p: Any) -> Any:
        """Return the fraction of the axis at the value(s) ``p`` (axis unit)."""
        p = np.asarray(p, dtype=float)
        if self.log:
            return np.log(p / self.lo) / math.log(self.hi / self.lo)
        return (p - self.lo) / (self.hi - self.lo)

    def label(self) -> str:
        """Return ``name [unit]`` (just the name when dimensionless)."""
        return self.name if self.unit == "1" else f"{self.name} [{self.unit}]"


@dataclass(frozen=True)
class LawPoint:
    """The model at one point of a plane: ``nu``, and the law as its specification and values."""

    nu: float
    spec: Any
    values: tuple[float, ...]

    def f(self, w: float, order: int = 0) -> float:
        """Return ``f_+^(order)(w)``."""
        return float(self.spec.evaluate_scalar(w, self.values, order))

    def lp(self) -> np.ndarray:
        """Return the kernel's parameter vector (padded)."""
        from ..core.laws import N_LAW_PARAMS

        lp = np.zeros(N_LAW_PARAMS)
        lp[: len(self.values)] = self.values
        return lp


def _axis(name: Any, rng: Any, log: Any, unit: str = "1", factor: float = 1.0) -> Axis:
    if not isinstance(name, str):
        raise ArgumentTypeError(f"axis {name!r}: expected a parameter name")
    try:
        lo, hi = (float(v) for v in rng)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}={rng!r}: expected a range (lo, hi) of two numbers") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        raise ValueError(f"{name}={rng!r}: expected a range lo < hi of finite numbers")
    if log is None:
        log = lo > 0 and hi / lo >= 20.0
    if log and lo <= 0:
        raise ValueError(f"{name}={rng!r}: a logarithmic axis needs lo > 0")
    return Axis(name, lo, hi, bool(log), unit, factor)


class Axes:
    """Two axes of a plane and the plane in words: what a diagram's figure and files need.

    :class:`Plane` adds the one-block model at each point; another model (the inertial
    rate-and-state slider) draws its diagram on bare axes.
    """

    def __init__(self, x: Axis, y: Axis, describe: str) -> None:
        self.x, self.y, self.describe = x, y, describe

    def values(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return the axis values (axis units) at unit-square points ``u`` (shape (..., 2))."""
        u = np.asarray(u, dtype=float)
        return (
            np.vectorize(self.x.to_unit)(u[..., 0]) if u.size else u[..., 0],
            np.vectorize(self.y.to_unit)(u[..., 1]) if u.size else u[..., 1],
        )


class Plane(Axes):
    """Two axes and the one-block model at each point of the plane (build with a classmethod)."""

    def __init__(
        self,
        x: Axis,
        y: Axis,
        law: DimensionlessLaw,
        point: Callable[[float, float], tuple[float, dict[str, float]]],
        describe: str,
        physical: PhysicalParameters | None = None,
    ) -> None:
        super().__init__(x, y, describe)
        self.law = law
        self.spec = law.spec
        self._point = point
        self.setup = physical
        self._names = tuple(p.name for p in self.spec.parameters)

    @classmethod
    def dimensionless(
        cls,
        law: DimensionlessLaw,
        x: tuple[str, tuple[float, float]],
        y: tuple[str, tuple[float, float]],
        *,
        nu: float | None = None,
        log: tuple[bool | None, bool | None] = (None, None),
    ) -> Plane:
        """Return the plane of ``nu`` and a law parameter, or of two law parameters at ``nu``.

        Parameters
        ----------
        law : DimensionlessLaw
            The law; the parameters not on an axis keep its values.
        x, y : (name, (lo, hi))
            The axes: ``"nu"`` or a parameter of the law (:attr:`LawSpec.mappable`).
        nu : float, optional
            The driving velocity where neither axis is ``nu``.
        log : (bool or None, bool or None)
            Logarithmic axes; by default where the range spans a factor 20 or more.

        Raises
        ------
        ValueError
            For an unknown or repeated name, a bad range, or a missing ``nu``.

        """
        law = require_dimensionless_law(law)
        allowed = ("nu", *law.spec.mappable)
        axes = []
        for (name, rng), lg in zip((x, y), log, strict=True):
            if name not in allowed:
                raise ValueError(f"axis {name!r}: a plane of the {law.name} law runs over {allowed}")
            axes.append(_axis(name, rng, lg))
        ax, ay = axes
        if ax.name == ay.name:
            raise ValueError(f"axes x={ax.name!r} and y={ay.name!r}: expected two different parameters")
        if "nu" not in (ax.name, ay.name) and nu is None:
            raise ValueError(f"neither axis is nu: give nu= (the driving velocity of the {law.name} plane)")
        base = dict(law.params)
        nu0 = float(nu) if nu is not None else math.nan

        def point(px: float, py: float) -> tuple[float, dict[str, float]]:
            vals = dict(base)
            v = nu0
            for a, p in ((ax, px), (ay, py)):
                if a.name == "nu":
                    v = p
                else:
                    vals[a.name] = p
            return v, vals

        for px in (ax.lo, ax.hi):  # the law must be valid at the corners (its own checks and message)
            for py in (ay.lo, ay.hi):
                _, vals = point(px, py)
                law.replace(**{k: vals[k] for k in (ax.name, ay.name) if k != "nu"})
        fixed = ", ".join(f"{k} = {v:.6g}" for k, v in law.params.items() if k not in (ax.name, ay.name))
        fixed += (", " if fixed else "") + (f"nu = {nu0:.6g}" if "nu" not in (ax.name, ay.name) else "")
        words = f"{law.name}: f(w) = {law.spec.f}" + (
            f" with {fixed.strip(', ')}" if fixed.strip(", ") else ""
        )
        return cls(ax, ay, law, point, f"{words} over ({ax.name}, {ay.name})")

    @classmethod
    def physical(
        cls,
        params: PhysicalParameters,
        x: tuple[str, tuple[Any, Any]],
        y: tuple[str, tuple[Any, Any]],
        *,
        log: tuple[bool | None, bool | None] = (True, True),
    ) -> Plane:
        """Return the plane of two physical quantities of the set-up ``params``.

        Parameters
        ----------
        params : PhysicalParameters
            The set-up; the quantities not on an axis keep its values.
        x, y : (name, (lo, hi))
            ``v0`` (um/s), ``stiffness`` (N/m), ``mass`` (kg), ``load`` (N), or a physical
            parameter of the law (SI), with its range in that unit.
        log : (bool or None, bool or None)
            Logarithmic axes (default both).

        """
        if not isinstance(params, PhysicalParameters):
            raise ArgumentTypeError(f"params={params!r}: expected PhysicalParameters")
        law_si = params.law.si_parameters()
        allowed = (*PHYSICAL_AXES, *law_si)
        axes = []
        for (name, rng), lg in zip((x, y), log, strict=True):
            if name not in allowed:
                raise ValueError(f"axis {name!r}: a physical plane runs over {allowed}")
            unit, factor = SHOWN.get(name, (_si_unit(params, name), 1.0))
            axes.append(_axis(name, rng, lg, unit, factor))
        ax, ay = axes
        if ax.name == ay.name:
            raise ValueError(f"axes x={ax.name!r} and y={ay.name!r}: expected two different quantities")
        dimless = params.dimensionless()
        names = tuple(p.name for p in dimless.law.spec.parameters)

        def point(px: float, py: float) -> tuple[float, dict[str, float]]:
            values = {ax.name: np.array([px * ax.factor]), ay.name: np.array([py * ay.factor])}
            nu, nd, _ = params.dimensionless_at(values, 1)
            return float(np.asarray(nu)[0]), {k: float(np.asarray(nd[k])[0]) for k in names}

        for px in (ax.lo, ax.hi):
            for py in (ay.lo, ay.hi):
                _, vals = point(px, py)
                dimless.law.replace(**vals)
        return cls(
            ax,
            ay,
            dimless.law,
            point,
            f"{params.law.describe()} over ({ax.name}, {ay.name})",
            physical=params,
        )

    # ---------------------------------------------------------------------------------------

    def at(self, u: np.ndarray | tuple[float, float]) -> LawPoint:
        """Return the model at the unit-square point ``u``."""
        nu, vals = self._point(self.x.to_unit(float(u[0])), self.y.to_unit(float(u[1])))
        return LawPoint(nu, self.spec, tuple(vals[k] for k in self._names))

    def law_at(self, u: np.ndarray | tuple[float, float]) -> tuple[float, DimensionlessLaw]:
        """Return ``nu`` and the (checked) law at the unit-square point ``u``."""
        p = self.at(u)
        return p.nu, self.law.replace(**dict(zip(self._names, p.values, strict=True)))


def _si_unit(params: PhysicalParameters, name: str) -> str:
    q = params.law.parameters[name] if hasattr(params.law, "parameters") else None
    try:
        return f"{q.to_base_units().units:~P}" if q is not None else "SI"
    except (AttributeError, TypeError):
        return "SI"


def check_positive_int(value: Any, name: str, lo: int, hi: int) -> int:
    """Return ``value`` as an int in ``[lo, hi]``, or a one-line error naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ArgumentTypeError(f"{name}={value!r}: expected an integer from {lo} to {hi}")
    if not lo <= int(value) <= hi:
        raise ValueError(f"{name}={value!r}: expected an integer from {lo} to {hi}")
    return int(value)
