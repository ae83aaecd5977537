"""Friction laws, in dimensionless and in physical form.

Dimensionless laws give the friction force in units of the static friction
force ``mu_s W`` as a function of the dimensionless slip velocity ``w`` (units
of ``mu_s W / sqrt(k m)``), so their static threshold is 1. Physical laws give
the friction *coefficient* as a function of a velocity with units; with a
normal load ``W`` and the scale ``beta = sqrt(k m) / (mu_s W)`` they convert
to the dimensionless form (:meth:`nondimensionalize`) and back
(:meth:`to_physical`).

Every law is odd in the velocity (friction opposes motion) and set-valued at
``w = 0``: at rest the friction force takes any value in
``[-static_threshold, static_threshold]``. :meth:`value` returns 0 at exactly
``w = 0``; the engine never uses that value.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
import numpy.typing as npt
import pint

from ..core.laws import LAW_COULOMB, LAW_CUBIC, LAW_WEAKENING
from .units import Q_, check_number, parse_quantity

_ONE_S_PER_M = Q_(1.0, "s/m")

__all__ = [
    "CoulombLaw",
    "CubicLaw",
    "DimensionlessLaw",
    "PhysicalCoulombLaw",
    "PhysicalCubicLaw",
    "PhysicalLaw",
    "PhysicalWeakeningLaw",
    "WeakeningLaw",
    "f1",
    "f2",
    "require_dimensionless_law",
]

ArrayLike = npt.ArrayLike


@runtime_checkable
class DimensionlessLaw(Protocol):
    """Interface of a dimensionless friction law (force in units of static friction)."""

    name: ClassVar[str]
    core_id: ClassVar[int]
    static_threshold: ClassVar[float]

    def forward(self, w: npt.NDArray[np.float64], order: int = 0) -> npt.NDArray[np.float64]:
        """Return the ``order``-th derivative of the forward branch ``f_+(w)`` for ``w > 0``."""
        ...

    def core_params(self) -> npt.NDArray[np.float64]:
        """Return the parameter vector of the compiled core."""
        ...

    def to_physical(self, beta: pint.Quantity, static_coefficient: float) -> PhysicalLaw:
        """Return the physical law for the scale ``beta`` (time/length)."""
        ...


class _LawMixin:
    """Shared evaluation of the odd extension from the forward branch."""

    static_threshold: ClassVar[float] = 1.0

    def forward(self, w: npt.NDArray[np.float64], order: int = 0) -> npt.NDArray[np.float64]:
        raise NotImplementedError

    def value(self, w: ArrayLike) -> npt.NDArray[np.float64]:
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

    def derivative(self, w: ArrayLike, order: int = 1) -> npt.NDArray[np.float64]:
        """Return the ``order``-th derivative of :meth:`value` for ``w != 0``.

        The odd extension gives ``f^(n)(-w) = (-1)^(n+1) f^(n)(w)``.
        """
        if not isinstance(order, int) or order < 1:
            raise ValueError(f"order={order!r}: expected an integer >= 1")
        w = np.asarray(w, dtype=float)
        sign = np.where(w < 0, (-1.0) ** (order + 1), 1.0)
        return sign * self.forward(np.abs(w), order)

    @property
    def kinetic_limit(self) -> float:
        """Friction just after breakaway, ``f(0+)`` (units of static friction)."""
        return float(self.forward(np.zeros(1))[0])


@dataclass(frozen=True)
class WeakeningLaw(_LawMixin):
    r"""Velocity-weakening law of the paper, dimensionless.

    .. math:: f(w) = \frac{1}{1 + c w} + p w, \qquad w > 0,

    with ``c = a / beta`` and ``p = b / beta``. ``p = 0`` is the paper's F1,
    ``p > 0`` its F2 (normalised as in PHYSICS.md §1: the linear term is in units
    of ``mu0 W``).

    Source: J. Szkutnik and K. Kułakowski, "How to distinguish between
    stick-slip and pure slip oscillations", arXiv cond-mat/0506435, eq. (2);
    the ``1/(1 + a v)`` form after M. de Sousa Vieira.

    Parameters
    ----------
    c : float
        Weakening rate (dimensionless), ``c > 0``.
    p : float, optional
        Viscous strengthening (dimensionless), ``p >= 0``. Default 0 (F1).

    """

    c: float
    p: float = 0.0
    name: ClassVar[str] = "weakening"
    core_id: ClassVar[int] = LAW_WEAKENING

    def __post_init__(self) -> None:
        object.__setattr__(self, "c", check_number(self.c, "c"))
        object.__setattr__(
            self, "p", check_number(self.p, "p", allow_zero=True, what="a non-negative number")
        )

    def forward(self, w: npt.NDArray[np.float64], order: int = 0) -> npt.NDArray[np.float64]:
        """Return the ``order``-th derivative of ``1/(1 + c w) + p w``."""
        w = np.asarray(w, dtype=float)
        q = 1.0 + self.c * w
        d = (-1.0) ** order * math.factorial(order) * self.c**order / q ** (order + 1)
        if order == 0:
            return d + self.p * w
        if order == 1:
            return d + self.p
        return d

    def core_params(self) -> npt.NDArray[np.float64]:
        """Return ``(c, p, 0)`` for the compiled core."""
        return np.array([self.c, self.p])

    def to_physical(self, beta: pint.Quantity, static_coefficient: float) -> PhysicalWeakeningLaw:
        """Return the physical law: ``a = c beta``, ``b = p beta``, ``mu0 = static_coefficient``."""
        return PhysicalWeakeningLaw(mu0=static_coefficient, a=self.c * beta, b=self.p * beta)


@dataclass(frozen=True)
class CubicLaw(_LawMixin):
    r"""Cubic law of Thomsen and Fidlin, dimensionless.

    .. math:: f(w) = \operatorname{sgn}(w) - \alpha w + \gamma w^3

    with ``alpha = k1 / (mu_s beta)`` and ``gamma = k3 / (mu_s beta**3)``.

    Source: J. J. Thomsen and A. Fidlin, "Analytical approximations for
    stick-slip vibration amplitudes", Int. J. Non-Linear Mech. 38 (2003)
    389-403 (mass on a moving belt).

    Parameters
    ----------
    alpha : float
        Linear weakening coefficient (dimensionless), ``alpha > 0``.
    gamma : float
        Cubic strengthening coefficient (dimensionless), ``gamma > 0``.

    """

    alpha: float
    gamma: float
    name: ClassVar[str] = "cubic"
    core_id: ClassVar[int] = LAW_CUBIC

    def __post_init__(self) -> None:
        object.__setattr__(self, "alpha", check_number(self.alpha, "alpha"))
        object.__setattr__(self, "gamma", check_number(self.gamma, "gamma"))
        w_min = math.sqrt(self.alpha / (3.0 * self.gamma))
        f_min = 1.0 - 2.0 * self.alpha * w_min / 3.0
        if f_min < 0.0:
            warnings.warn(
                f"CubicLaw(alpha={self.alpha!r}, gamma={self.gamma!r}): the friction turns negative "
                f"(minimum {f_min:.3g} at w = {w_min:.3g}; it stays positive for "
                "alpha**3 < 27 gamma / 4): it drives the block there",
                UserWarning,
                stacklevel=3,
            )

    def forward(self, w: npt.NDArray[np.float64], order: int = 0) -> npt.NDArray[np.float64]:
        """Return the ``order``-th derivative of ``1 - alpha w + gamma w**3``."""
        w = np.asarray(w, dtype=float)
        a, g = self.alpha, self.gamma
        if order == 0:
            return 1.0 - a * w + g * w**3
        if order == 1:
            return -a + 3.0 * g * w**2
        if order == 2:
            return 6.0 * g * w
        if order == 3:
            return np.full_like(w, 6.0 * g)
        return np.zeros_like(w)

    def core_params(self) -> npt.NDArray[np.float64]:
        """Return ``(alpha, gamma, 0)`` for the compiled core."""
        return np.array([self.alpha, self.gamma])

    def to_physical(self, beta: pint.Quantity, static_coefficient: float) -> PhysicalCubicLaw:
        """Return the physical law: ``k1 = alpha mu_s beta``, ``k3 = gamma mu_s beta**3``."""
        mu = static_coefficient
        return PhysicalCubicLaw(mu_s=mu, k1=self.alpha * mu * beta, k3=self.gamma * mu * beta**3)


@dataclass(frozen=True)
class CoulombLaw(_LawMixin):
    r"""Coulomb friction with distinct static and kinetic coefficients, dimensionless.

    .. math:: f(w) = f_k \operatorname{sgn}(w), \qquad 0 < f_k = \mu_k / \mu_s < 1.

    Source: C. A. Coulomb, *Théorie des machines simples* (1785); the
    static/kinetic form as in B. N. J. Persson, *Sliding Friction* (Springer,
    2000), ch. 1.

    Parameters
    ----------
    kinetic : float
        Kinetic friction in units of static friction, ``0 < kinetic < 1``.

    """

    kinetic: float
    name: ClassVar[str] = "coulomb"
    core_id: ClassVar[int] = LAW_COULOMB

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "kinetic",
            check_number(
                self.kinetic, "kinetic", upper=1.0, what="a kinetic/static friction ratio in (0, 1)"
            ),
        )

    def forward(self, w: npt.NDArray[np.float64], order: int = 0) -> npt.NDArray[np.float64]:
        """Return ``kinetic`` (order 0) or 0 (derivatives)."""
        w = np.asarray(w, dtype=float)
        return np.full_like(w, self.kinetic if order == 0 else 0.0)

    def core_params(self) -> npt.NDArray[np.float64]:
        """Return ``(kinetic, 0, 0)`` for the compiled core."""
        return np.array([self.kinetic])

    def to_physical(self, beta: pint.Quantity, static_coefficient: float) -> PhysicalCoulombLaw:
        """Return the physical law: ``mu_k = kinetic mu_s``."""
        return PhysicalCoulombLaw(mu_s=static_coefficient, mu_k=self.kinetic * static_coefficient)


# ---------------------------------------------------------------------------
# physical laws


class PhysicalLaw(Protocol):
    """Interface of a friction law in physical units (coefficient against velocity)."""

    name: ClassVar[str]

    @property
    def static_coefficient(self) -> float:
        """Static friction coefficient ``mu_s`` (the threshold at rest)."""
        ...

    def coefficient(self, v: Any) -> npt.NDArray[np.float64]:
        """Return the friction coefficient at slip velocity ``v`` (odd in ``v``)."""
        ...

    def value(self, v: Any) -> npt.NDArray[np.float64]:
        """Return the friction coefficient at slip velocity ``v`` (as :meth:`coefficient`)."""
        ...

    def derivative(self, v: Any, order: int = 1) -> pint.Quantity:
        """Return the ``order``-th derivative of the coefficient with respect to ``v``."""
        ...

    def nondimensionalize(self, beta: pint.Quantity) -> DimensionlessLaw:
        """Return the dimensionless law for ``beta = sqrt(k m) / (mu_s W)``."""
        ...

    def si_parameters(self) -> dict[str, float]:
        """Return the law's physical parameters (other than ``mu_s``) as SI numbers."""
        ...


class _PhysicalLawMixin:
    """Value and derivatives of a physical law, through its dimensionless form.

    ``mu(v) = mu_s f(beta v)`` for any ``beta``; with ``beta = 1 s/m`` the
    derivatives are ``d^n mu / dv^n = mu_s f^(n)(v)`` in units of ``(s/m)**n``.
    """

    @property
    def static_coefficient(self) -> float:
        raise NotImplementedError

    def nondimensionalize(self, beta: pint.Quantity) -> Any:
        raise NotImplementedError

    @property
    def static_threshold(self) -> float:
        """Static friction coefficient: the threshold of ``|mu|`` at rest."""
        return self.static_coefficient

    def value(self, v: Any) -> npt.NDArray[np.float64]:
        """Return the friction coefficient at slip velocity ``v`` (0 at ``v = 0``)."""
        x = _velocity_magnitude(v)
        return self.static_coefficient * self.nondimensionalize(_ONE_S_PER_M).value(x)

    def derivative(self, v: Any, order: int = 1) -> pint.Quantity:
        """Return ``d^n mu / dv^n`` at ``v != 0``, in units of ``(s/m)**order``."""
        x = _velocity_magnitude(v)
        d = self.nondimensionalize(_ONE_S_PER_M).derivative(x, order)
        return Q_(self.static_coefficient * d, f"(s/m)**{order}")


def _velocity_magnitude(v: Any) -> npt.NDArray[np.float64]:
    if isinstance(v, str):
        v = parse_quantity(v, "v", "[length] / [time]", "5 um/s", allow_zero=True)
    if not isinstance(v, pint.Quantity) or not v.check("[length] / [time]"):
        raise ValueError(f"v={v!r}: expected a velocity with units, such as '5 um/s'")
    return np.asarray(v.to("m/s").magnitude, dtype=float)


@dataclass(frozen=True)
class PhysicalWeakeningLaw(_PhysicalLawMixin):
    r"""The paper's law in physical units: ``mu(v) = mu0 [1/(1 + a v) + b v]``.

    ``b = 0`` is F1, ``b > 0`` is F2 normalised as in PHYSICS.md §1 (the linear
    term in units of ``mu0 W``). Source: Szkutnik and Kułakowski,
    arXiv cond-mat/0506435, eq. (1).

    Parameters
    ----------
    mu0 : float
        Static friction coefficient (dimensionless), ``mu0 > 0``.
    a : pint.Quantity or str
        Weakening rate (time/length), e.g. ``"160 s/m"``.
    b : pint.Quantity or str, optional
        Strengthening rate (time/length), e.g. ``"100 s/m"``. Default ``"0 s/m"``.

    """

    mu0: float
    a: Any
    b: Any = "0 s/m"
    name: ClassVar[str] = "weakening"

    def __post_init__(self) -> None:
        object.__setattr__(self, "mu0", check_number(self.mu0, "mu0"))
        object.__setattr__(self, "a", parse_quantity(self.a, "a", "[time] / [length]", "160 s/m"))
        object.__setattr__(
            self, "b", parse_quantity(self.b, "b", "[time] / [length]", "100 s/m", allow_zero=True)
        )

    @property
    def static_coefficient(self) -> float:
        """Static friction coefficient ``mu0``."""
        return self.mu0

    def coefficient(self, v: Any) -> npt.NDArray[np.float64]:
        """Return ``mu(v)`` for a velocity with units (0 at ``v = 0``)."""
        x = _velocity_magnitude(v)
        ax = np.abs(x)
        a = self.a.to("s/m").magnitude
        b = self.b.to("s/m").magnitude
        return np.where(x == 0, 0.0, np.sign(x) * self.mu0 * (1.0 / (1.0 + a * ax) + b * ax))

    def si_parameters(self) -> dict[str, float]:
        """Return ``a`` and ``b`` in s/m."""
        return {"a": float(self.a.to("s/m").magnitude), "b": float(self.b.to("s/m").magnitude)}

    def nondimensionalize(self, beta: pint.Quantity) -> WeakeningLaw:
        """Return ``WeakeningLaw(c = a/beta, p = b/beta)``."""
        return WeakeningLaw(
            c=float((self.a / beta).to("").magnitude), p=float((self.b / beta).to("").magnitude)
        )


def f1(mu0: float, a: Any) -> PhysicalWeakeningLaw:
    """Return the paper's F1 law, ``F = mu0 W / (1 + a v)``."""
    return PhysicalWeakeningLaw(mu0=mu0, a=a, b="0 s/m")


def f2(mu0: float, a: Any, b: Any) -> PhysicalWeakeningLaw:
    """Return the paper's F2 law, ``F = mu0 W [1/(1 + a v) + b v]``."""
    return PhysicalWeakeningLaw(mu0=mu0, a=a, b=b)


@dataclass(frozen=True)
class PhysicalCubicLaw(_PhysicalLawMixin):
    r"""Thomsen–Fidlin cubic law: ``mu(v) = mu_s sgn(v) - k1 v + k3 v**3``.

    Source: J. J. Thomsen and A. Fidlin, Int. J. Non-Linear Mech. 38 (2003)
    389-403.

    Parameters
    ----------
    mu_s : float
        Static friction coefficient, ``mu_s > 0``.
    k1 : pint.Quantity or str
        Linear coefficient (time/length), e.g. ``"0.5 s/m"``.
    k3 : pint.Quantity or str
        Cubic coefficient (time**3/length**3), e.g. ``"0.01 s**3/m**3"``.

    """

    mu_s: float
    k1: Any
    k3: Any
    name: ClassVar[str] = "cubic"

    def __post_init__(self) -> None:
        object.__setattr__(self, "mu_s", check_number(self.mu_s, "mu_s"))
        object.__setattr__(self, "k1", parse_quantity(self.k1, "k1", "[time] / [length]", "0.5 s/m"))
        object.__setattr__(
            self, "k3", parse_quantity(self.k3, "k3", "[time] ** 3 / [length] ** 3", "0.01 s**3/m**3")
        )

    @property
    def static_coefficient(self) -> float:
        """Static friction coefficient ``mu_s``."""
        return self.mu_s

    def coefficient(self, v: Any) -> npt.NDArray[np.float64]:
        """Return ``mu(v)`` for a velocity with units (0 at ``v = 0``)."""
        x = _velocity_magnitude(v)
        k1 = self.k1.to("s/m").magnitude
        k3 = self.k3.to("s**3/m**3").magnitude
        return np.where(x == 0, 0.0, self.mu_s * np.sign(x) - k1 * x + k3 * x**3)

    def si_parameters(self) -> dict[str, float]:
        """Return ``k1`` in s/m and ``k3`` in s**3/m**3."""
        return {"k1": float(self.k1.to("s/m").magnitude), "k3": float(self.k3.to("s**3/m**3").magnitude)}

    def nondimensionalize(self, beta: pint.Quantity) -> CubicLaw:
        """Return ``CubicLaw(alpha = k1/(mu_s beta), gamma = k3/(mu_s beta**3))``."""
        return CubicLaw(
            alpha=float((self.k1 / (self.mu_s * beta)).to("").magnitude),
            gamma=float((self.k3 / (self.mu_s * beta**3)).to("").magnitude),
        )


@dataclass(frozen=True)
class PhysicalCoulombLaw(_PhysicalLawMixin):
    """Coulomb law with static ``mu_s`` and kinetic ``mu_k < mu_s`` coefficients.

    Parameters
    ----------
    mu_s : float
        Static friction coefficient, ``mu_s > 0``.
    mu_k : float
        Kinetic friction coefficient, ``0 < mu_k < mu_s``.

    """

    mu_s: float
    mu_k: float
    name: ClassVar[str] = "coulomb"

    def __post_init__(self) -> None:
        object.__setattr__(self, "mu_s", check_number(self.mu_s, "mu_s"))
        object.__setattr__(
            self,
            "mu_k",
            check_number(
                self.mu_k, "mu_k", upper=self.mu_s, what=f"a kinetic coefficient below mu_s={self.mu_s}"
            ),
        )

    @property
    def static_coefficient(self) -> float:
        """Static friction coefficient ``mu_s``."""
        return self.mu_s

    def coefficient(self, v: Any) -> npt.NDArray[np.float64]:
        """Return ``mu_k sgn(v)`` for a velocity with units (0 at ``v = 0``)."""
        x = _velocity_magnitude(v)
        return self.mu_k * np.sign(x)

    def si_parameters(self) -> dict[str, float]:
        """Return ``mu_k``."""
        return {"mu_k": self.mu_k}

    def nondimensionalize(self, beta: pint.Quantity) -> CoulombLaw:
        """Return ``CoulombLaw(kinetic = mu_k / mu_s)``."""
        return CoulombLaw(kinetic=self.mu_k / self.mu_s)


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
            "WeakeningLaw(c=3.8), CubicLaw(alpha=0.5, gamma=0.17) or CoulombLaw(kinetic=0.5); "
            "PhysicalParameters(...).dimensionless().law converts a physical set-up"
        )
    return law
