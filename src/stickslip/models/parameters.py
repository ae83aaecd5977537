"""Parameter sets of the one-block model: physical (with units) and dimensionless.

The physical model (PHYSICS.md §1) is ``m x'' = -k (x - v0 t) - W mu(x')``.
With the static friction force ``mu_s W`` as force unit and ``sqrt(m/k)`` as
time unit it becomes ``u'' = nu tau - u - f(u')`` with

    beta = sqrt(k m) / (mu_s W),   nu = beta v0,

and the law's own dimensionless parameters (``c = a/beta``, ``p = b/beta`` for
the paper's law).
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import numpy.typing as npt
import pint

from ..core.checks import NU_MAX, driving_velocity
from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw, PhysicalLaw, PhysicalWeakeningLaw, require_physical_law
from ..laws.spec import STATIC, LawSpec
from ..units import Q_, check_number, parse_quantity
from .scales import Scales

__all__ = [
    "DimensionlessParameters",
    "PhysicalParameters",
    "Scales",
    "as_dimensionless",
    "beta_of",
    "dimensionless_from_si",
    "mass_for_beta",
    "zv_parameters",
]


def beta_of(stiffness: npt.ArrayLike, mass: npt.ArrayLike, load: npt.ArrayLike, mu_s: npt.ArrayLike) -> Any:
    """Return ``beta = sqrt(k m)/(mu_s W)`` (s/m) from SI values (scalars or arrays)."""
    k, m = np.asarray(stiffness, dtype=float), np.asarray(mass, dtype=float)
    return np.sqrt(k * m) / (np.asarray(mu_s, dtype=float) * np.asarray(load, dtype=float))


def mass_for_beta(
    beta: npt.ArrayLike, stiffness: npt.ArrayLike, load: npt.ArrayLike, mu_s: npt.ArrayLike
) -> Any:
    """Return the mass (kg) that gives ``beta`` (s/m): ``m = (beta mu_s W)**2 / k`` (SI, vectorised)."""
    b = np.asarray(beta, dtype=float)
    force = np.asarray(mu_s, dtype=float) * np.asarray(load, dtype=float)
    return (b * force) ** 2 / np.asarray(stiffness, dtype=float)


def mass_of_beta(given: Any, beta: pint.Quantity, stiffness: Any, load: Any, mu_s: float) -> float:
    """Return the mass (kg) that gives one ``beta``, refusing one that is zero or infinite.

    ``given`` is ``beta`` as the user gave it, for the message: 'mass=0 kg must be
    positive' named a mass never typed.
    """
    mass = float(
        mass_for_beta(beta.to("s/m").magnitude, stiffness.to("N/m").magnitude, load.to("N").magnitude, mu_s)
    )
    if not 0.0 < mass < np.inf:
        raise ValueError(f"beta={given!r} makes the mass {mass:g} kg: expected a beta whose mass is positive")
    return mass


@dataclass(frozen=True)
class DimensionlessParameters:
    """The dimensionless model: driving velocity ``nu`` and a dimensionless law.

    Parameters
    ----------
    nu : float
        Dimensionless driving velocity ``beta v0`` (> 0).
    law : DimensionlessLaw
        Any dimensionless law: :class:`~stickslip.laws.WeakeningLaw`,
        :class:`~stickslip.laws.CubicLaw`, :class:`~stickslip.laws.CoulombLaw`,
        :class:`~stickslip.laws.ExpressionLaw`, a registered law's class.

    """

    nu: float
    law: DimensionlessLaw

    def __post_init__(self) -> None:
        # a pint quantity or a numpy number as a float, then the range every driving velocity has
        nu = check_number(self.nu, "nu", what=f"a positive driving velocity (at most {NU_MAX:g})")
        object.__setattr__(self, "nu", driving_velocity("nu", nu))
        if not isinstance(self.law, DimensionlessLaw):
            raise ArgumentTypeError(
                f"law={self.law!r}: expected a dimensionless law (WeakeningLaw, CubicLaw, CoulombLaw, "
                "ExpressionLaw, ...); convert a physical law with PhysicalParameters"
            )

    def with_nu(self, nu: float) -> DimensionlessParameters:
        """Return a copy with another driving velocity."""
        return replace(self, nu=nu)

    def law_arrays_at(self, values: Mapping[str, Any], n: int) -> tuple[Any, dict[str, Any]]:
        """Return ``nu`` and the law's parameters at ``n`` points: ``values`` (arrays) where given."""
        nu = values["nu"] if "nu" in values else np.full(n, self.nu)
        nd = {k: values[k] if k in values else np.full(n, v) for k, v in self.law.params.items()}
        return nu, nd


@dataclass(frozen=True)
class PhysicalParameters:
    """A physical spring-block set-up.

    The dimensionless form (``nu``, the dimensionless law, the scales) is computed
    once, on first use, and kept.

    Parameters
    ----------
    mass : pint.Quantity or str
        Mass of the moving part, e.g. ``"231 g"``.
    stiffness : pint.Quantity or str
        Spring constant, e.g. ``"62 N/m"``.
    load : pint.Quantity or str
        Normal load ``W``, e.g. ``"196 mN"``.
    v0 : pint.Quantity or str
        Driving velocity, e.g. ``"5 um/s"``.
    law : PhysicalLaw
        Friction law in physical units, e.g.
        ``PhysicalWeakeningLaw(mu_s=0.46, a="160 s/m")``.

    Raises
    ------
    ArgumentTypeError
        For a value of the wrong type (a plain number, ``None``, a law that is not a
        physical law); the message names the argument.
    ValueError
        For a value with the wrong dimension, a string that is not a quantity, or a
        zero, negative, infinite or NaN magnitude; the message names the argument.

    """

    mass: Any
    stiffness: Any
    load: Any
    v0: Any
    law: PhysicalLaw

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", parse_quantity(self.mass, "mass", "[mass]", "1 kg"))
        object.__setattr__(
            self, "stiffness", parse_quantity(self.stiffness, "stiffness", "[mass] / [time] ** 2", "62 N/m")
        )
        object.__setattr__(self, "load", parse_quantity(self.load, "load", "[force]", "196 mN"))
        object.__setattr__(self, "v0", parse_quantity(self.v0, "v0", "[length] / [time]", "5 um/s"))
        require_physical_law(self.law)

    @functools.cached_property
    def _form(self) -> tuple[float, DimensionlessLaw, Scales]:
        """``nu``, the dimensionless law and the scales: computed once."""
        k = float(self.stiffness.to("N/m").magnitude)
        m = float(self.mass.to("kg").magnitude)
        force = self.law.mu_s * float(self.load.to("N").magnitude)
        beta = float(beta_of(k, m, self.load.to("N").magnitude, self.law.mu_s))
        scales = Scales(
            force=Q_(force, "N"),
            time=Q_(float(np.sqrt(m / k)), "s"),
            length=Q_(force / k, "m"),
            velocity=Q_(1.0 / beta, "m/s"),
        )
        nu = beta * float(self.v0.to("m/s").magnitude)
        with self._named():
            return nu, self.law.nondimensionalize(Q_(beta, "s/m")), scales

    @contextlib.contextmanager
    def _named(self) -> Iterator[None]:
        """Name the physical inputs in an error of the dimensionless numbers made from them.

        ``--mass "1e-320 kg"`` makes ``c = 1.8e+160``, a number the user never typed: the
        message names the mass it came from.
        """
        try:
            yield
        except ValueError as exc:
            given = ", ".join(f"{k}={getattr(self, k):~P}" for k in ("mass", "stiffness", "load", "v0"))
            raise type(exc)(f"{exc} (made from {given}: check their units and magnitudes)") from None

    @property
    def scales(self) -> Scales:
        """Return the force, time, length and velocity units of the dimensionless model."""
        return self._form[2]

    @property
    def beta(self) -> pint.Quantity:
        """``beta = sqrt(k m)/(mu_s W)`` (s/m)."""
        return self._form[2].beta

    @property
    def nu(self) -> float:
        """Dimensionless driving velocity ``beta v0``."""
        return self._form[0]

    def dimensionless(self) -> DimensionlessParameters:
        """Return the dimensionless parameter set (``nu`` and the dimensionless law)."""
        nu, law, _ = self._form
        with self._named():
            return DimensionlessParameters(nu=nu, law=law)

    def dimensionless_at(
        self, values: Mapping[str, Any], n: int
    ) -> tuple[Any, dict[str, Any], dict[str, Any]]:
        """Return the dimensionless form at ``n`` points whose SI ``values`` (arrays) replace this set's.

        ``values`` may hold ``stiffness`` (N/m), ``load`` (N), ``mass`` (kg) or ``beta``
        (s/m, which sets the mass), ``v0`` (m/s) and the law's physical parameters (SI).
        Returns ``nu``, the law's dimensionless parameters and the scales per point
        (:func:`dimensionless_from_si`).

        Raises
        ------
        ValueError
            For ``mass`` and ``beta`` both, or a point where the law's values are not valid.

        """

        def arr(name: str, default: float) -> Any:
            return values[name] if name in values else np.full(n, default)

        law: PhysicalLaw = self.law
        spec = law.spec
        law_si = {key: arr(key, v) for key, v in law.si_parameters().items()}
        mu = spec.static_from(law_si) if spec.static_from is not None else arr("mu_s", law.mu_s)
        k = arr("stiffness", self.stiffness.to("N/m").magnitude)
        w = arr("load", self.load.to("N").magnitude)
        if "beta" in values:
            if "mass" in values:
                raise ValueError("sweep either 'beta' or 'mass', not both: beta sets the mass")
            m = mass_for_beta(values["beta"], k, w, mu)
        else:
            m = arr("mass", self.mass.to("kg").magnitude)
        PhysicalLaw._validate(spec, mu, law_si)
        v0 = arr("v0", self.v0.to("m/s").magnitude)
        return dimensionless_from_si(spec, stiffness=k, mass=m, load=w, v0=v0, mu_s=mu, law_si=law_si)

    def with_v0(self, v0: Any) -> PhysicalParameters:
        """Return a copy with another driving velocity."""
        return replace(self, v0=v0)

    @classmethod
    def from_dimensionless(
        cls,
        params: DimensionlessParameters,
        *,
        mass: Any,
        stiffness: Any,
        load: Any,
        mu_s: float,
    ) -> PhysicalParameters:
        """Return the physical set that has the given dimensionless form.

        Parameters
        ----------
        params : DimensionlessParameters
            ``nu`` and a dimensionless law.
        mass, stiffness, load : pint.Quantity or str
            The scales that the dimensionless form does not fix.
        mu_s : float
            The static friction coefficient.

        """
        if not isinstance(params, DimensionlessParameters):
            raise ArgumentTypeError(f"params={params!r}: expected DimensionlessParameters")
        mu = STATIC.check(mu_s)
        m = parse_quantity(mass, "mass", "[mass]", "1 kg")
        k = parse_quantity(stiffness, "stiffness", "[mass] / [time] ** 2", "62 N/m")
        w = parse_quantity(load, "load", "[force]", "196 mN")
        beta = Q_(float(beta_of(k.to("N/m").magnitude, m.to("kg").magnitude, w.to("N").magnitude, mu)), "s/m")
        return cls(
            mass=m,
            stiffness=k,
            load=w,
            v0=(params.nu / beta).to("um/s"),
            law=params.law.to_physical(beta, mu),
        )


# The zv experiment (PHYSICS.md §4): W = 196 mN, mu0 = 0.46, a = 160 s/m, k = 62 N/m.
# The paper computes with beta = 42 s/m, which with k = 62 N/m needs m = (beta mu0 W)**2 / k.
ZV_BETA = Q_(42.0, "s/m")
ZV_LOAD = Q_(196.0, "mN")
ZV_MU0 = 0.46
ZV_A = Q_(160.0, "s/m")
ZV_STIFFNESS = Q_(62.0, "N/m")


def zv_parameters(v0: Any = "10 um/s", *, b: Any = "0 s/m", beta: Any = ZV_BETA) -> PhysicalParameters:
    """Return the paper's zv set-up with the mass chosen so that ``beta = 42 s/m``.

    The paper states ``m`` "of order 1000 g" but computes with ``beta = 42 s/m``;
    from ``k = 62 N/m`` and ``mu0 W = 0.0902 N`` that needs ``m = 0.231 kg``
    (PHYSICS.md §4). We reproduce the stated ``beta``.

    Parameters
    ----------
    v0 : pint.Quantity or str, optional
        Driving velocity. Default ``"10 um/s"``.
    b : pint.Quantity or str, optional
        Strengthening rate of F2 (``"100 s/m"`` in the paper's Fig. 2). Default 0 (F1).
    beta : pint.Quantity or str, optional
        The scale ``sqrt(k m)/(mu_s W)``; the mass follows from it. Default 42 s/m.

    """
    beta_q = parse_quantity(beta, "beta", "[time] / [length]", "42 s/m")
    mass = mass_of_beta(beta, beta_q, ZV_STIFFNESS, ZV_LOAD, ZV_MU0)
    return PhysicalParameters(
        mass=Q_(float(mass), "kg"),
        stiffness=ZV_STIFFNESS,
        load=ZV_LOAD,
        v0=v0,
        law=PhysicalWeakeningLaw(mu_s=ZV_MU0, a=ZV_A, b=b),
    )


def as_dimensionless(
    params: DimensionlessParameters | PhysicalParameters,
) -> tuple[DimensionlessParameters, Scales | None]:
    """Return the dimensionless form of a parameter set and its SI scales (None if none).

    Raises
    ------
    ArgumentTypeError
        If ``params`` is neither kind of parameter set.

    """
    if isinstance(params, PhysicalParameters):
        return params.dimensionless(), params.scales
    if isinstance(params, DimensionlessParameters):
        return params, None
    raise ArgumentTypeError(f"params={params!r}: expected DimensionlessParameters or PhysicalParameters")


def dimensionless_from_si(
    spec: LawSpec,
    *,
    stiffness: npt.ArrayLike,
    mass: npt.ArrayLike,
    load: npt.ArrayLike,
    v0: npt.ArrayLike,
    mu_s: npt.ArrayLike,
    law_si: Mapping[str, npt.ArrayLike],
) -> tuple[Any, dict[str, Any], dict[str, Any]]:
    """Convert SI values (scalars or arrays) to the dimensionless form; one formula for every law.

    Parameters
    ----------
    spec : LawSpec
        The law (its map from physical to dimensionless parameters).
    stiffness, mass, load, v0 : array_like
        In N/m, kg, N and m/s.
    mu_s : array_like
        Static friction coefficient.
    law_si : dict
        The law's physical parameters in SI.

    Returns
    -------
    nu : array_like
        ``beta v0``.
    law_params : dict
        The dimensionless law parameters.
    scales : dict
        ``force`` (N), ``time`` (s), ``length`` (m), ``velocity`` (m/s).

    """
    k = np.asarray(stiffness, dtype=float)
    m = np.asarray(mass, dtype=float)
    mu = np.asarray(mu_s, dtype=float)
    force = mu * np.asarray(load, dtype=float)
    beta = beta_of(k, m, load, mu)
    nu = beta * np.asarray(v0, dtype=float)
    nd = spec.dimensionless_values(law_si, beta, mu)
    scales = {"force": force, "time": np.sqrt(m / k), "length": force / k, "velocity": 1.0 / beta}
    return nu, nd, scales
