"""The forced oscillator's parameters: dimensionless, and in physical units with their scaling.

The one-block model (PHYSICS.md §1) with three harmonic excitations and viscous
damping::

    m x'' = k (y(t) - x) + F0 cos(Omega t) - c x' - F(x')
    y'(t) = V0 + V1 cos(Omega t + phi)          (the spring's far end)

A support (base) displacement ``Y sin(Omega t + phi)`` on top of the steady drive
is ``V1 = Omega Y``. Forces are measured in units of the static friction
``mu_s W``, times in ``sqrt(m/k)``, lengths in ``mu_s W / k`` (as for the
autonomous model), so that::

    nu0 = beta V0,  nu1 = beta V1,  omega = Omega sqrt(m/k),
    q = F0 / (mu_s W),  delta = c / sqrt(k m),  beta = sqrt(k m) / (mu_s W)

and the state is the spring force ``s = k (y - x) / (mu_s W)`` and the velocity
``w = beta x'``. With ``nu1 = q = 0`` and ``delta = 0`` this is the model of
:func:`stickslip.cycle`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import ArgumentTypeError
from ..laws import DimensionlessLaw, PhysicalLaw, require_physical_law
from ..models import PhysicalParameters, Scales
from ..units import Q_, check_number, parse_quantity

__all__ = ["ForcedSystem", "PhysicalForcedSystem", "as_forced"]

#: the largest forcing frequency, amplitude and damping accepted (dimensionless)
LIMIT = 1e6


def _real(value: Any, name: str, what: str, *, zero: bool = True) -> float:
    return check_number(value, name, allow_zero=zero, upper=LIMIT, upper_inclusive=True, what=what)


def _phase(value: Any, name: str) -> float:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float | np.floating)
        or not math.isfinite(value)
    ):
        raise ArgumentTypeError(f"{name}={value!r}: expected a finite phase in rad")
    return float(value)


@dataclass(frozen=True)
class ForcedSystem:
    """A forced one-block oscillator in dimensionless form.

    Parameters
    ----------
    law : DimensionlessLaw
        Any law of the registry (:class:`~stickslip.laws.WeakeningLaw`, an
        :class:`~stickslip.laws.ExpressionLaw`, a table).
    omega : float
        Forcing frequency ``Omega sqrt(m/k)`` (> 0).
    q : float
        External force amplitude over the static friction, ``F0 / (mu_s W)`` (>= 0).
    nu0 : float
        Mean driving velocity ``beta V0`` (>= 0; 0: the spring's far end is fixed, as in
        Den Hartog's oscillator).
    nu1 : float
        Driving velocity amplitude ``beta V1`` (>= 0; a support displacement of
        amplitude ``Y`` in units of ``mu_s W / k`` is ``nu1 = omega Y``).
    phi : float
        Phase of the drive's modulation against the force (rad).
    delta : float
        Viscous damping ``c / sqrt(k m)`` (>= 0).

    """

    law: DimensionlessLaw
    omega: float
    q: float = 0.0
    nu0: float = 0.0
    nu1: float = 0.0
    phi: float = 0.0
    delta: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.law, DimensionlessLaw):
            raise ArgumentTypeError(
                f"law={self.law!r}: expected a dimensionless law (WeakeningLaw, CoulombLaw, ...); "
                "give a physical set-up as PhysicalForcedSystem"
            )
        object.__setattr__(
            self,
            "omega",
            _real(self.omega, "omega", "a positive forcing frequency Omega sqrt(m/k)", zero=False),
        )
        object.__setattr__(self, "q", _real(self.q, "q", "a force amplitude F0/(mu_s W) >= 0"))
        object.__setattr__(self, "nu0", _real(self.nu0, "nu0", "a mean driving velocity beta V0 >= 0"))
        object.__setattr__(self, "nu1", _real(self.nu1, "nu1", "a driving velocity amplitude beta V1 >= 0"))
        object.__setattr__(self, "delta", _real(self.delta, "delta", "a damping c/sqrt(k m) >= 0"))
        object.__setattr__(self, "phi", _phase(self.phi, "phi"))

    @property
    def period(self) -> float:
        """The forcing period ``2 pi / omega`` (units of ``sqrt(m/k)``)."""
        return 2.0 * math.pi / self.omega

    @property
    def unforced(self) -> bool:
        """Whether nothing varies in time (``q = nu1 = 0``)."""
        return self.q == 0.0 and self.nu1 == 0.0

    def forcing_vector(self) -> np.ndarray:
        """Return the engine's forcing vector ``(nu0, nu1, omega, phi, q, delta)``."""
        return np.array([self.nu0, self.nu1, self.omega, self.phi, self.q, self.delta])

    def arrays(self) -> tuple[Any, np.ndarray, np.ndarray]:
        """Return the law's kernel, its parameter vector and the forcing vector."""
        kernel, lp = self.law.arrays()
        return kernel, lp, self.forcing_vector()

    def with_(self, **changes: Any) -> ForcedSystem:
        """Return a copy with some parameters changed (``omega``, ``q``, ... or a law parameter)."""
        own = {k: v for k, v in changes.items() if k in _FIELDS}
        law_changes = {k: v for k, v in changes.items() if k not in _FIELDS}
        law = self.law.replace(**law_changes) if law_changes else self.law
        unknown = set(law_changes) - set(self.law.params)
        if unknown:
            raise ValueError(
                f"{sorted(unknown)}: not a parameter of the forced system ({', '.join(_FIELDS)}) "
                f"or of the law ({', '.join(self.law.params)})"
            )
        return replace(self, law=law, **own)

    def describe(self) -> str:
        """Return the parameters in one line."""
        law = ", ".join(f"{k}={v:g}" for k, v in self.law.params.items())
        parts = [f"omega={self.omega:g}", f"q={self.q:g}"]
        parts += [
            f"{k}={getattr(self, k):g}" for k in ("nu0", "nu1", "phi", "delta") if getattr(self, k) != 0.0
        ]
        return f"{self.law.name} ({law}), " + ", ".join(parts)


_FIELDS = ("omega", "q", "nu0", "nu1", "phi", "delta")


@dataclass(frozen=True)
class PhysicalForcedSystem:
    """A forced spring-block set-up in physical units.

    Parameters
    ----------
    mass, stiffness, load : pint.Quantity or str
        As for :class:`~stickslip.PhysicalParameters` (``"1 kg"``, ``"100 N/m"``, ``"5 N"``).
    law : PhysicalLaw
        The friction law in physical units.
    frequency : pint.Quantity or str
        Forcing frequency: ``"2 Hz"`` (cycles per second) or ``"12.6 rad/s"``.
    force : pint.Quantity or str
        Amplitude ``F0`` of the external force ``F0 cos(Omega t)`` (``"0 N"`` for none).
    v0 : pint.Quantity or str
        Mean driving velocity of the spring's far end (``"0 m/s"``: fixed).
    drive_amplitude : pint.Quantity or str
        Amplitude ``V1`` of the drive's velocity modulation ``V1 cos(Omega t + phase)``.
    base_amplitude : pint.Quantity or str
        Amplitude ``Y`` of a support displacement ``Y sin(Omega t + phase)`` (``V1 = Omega Y``;
        give one of ``drive_amplitude`` and ``base_amplitude``).
    phase : float or pint.Quantity or str
        Phase of the drive's modulation (rad, or ``"90 deg"``).
    damping : pint.Quantity or str
        Viscous damping coefficient ``c`` (``"0.5 N*s/m"``).

    """

    mass: Any
    stiffness: Any
    load: Any
    law: PhysicalLaw
    frequency: Any
    force: Any = "0 N"
    v0: Any = "0 m/s"
    drive_amplitude: Any = None
    base_amplitude: Any = None
    phase: Any = 0.0
    damping: Any = "0 N*s/m"

    def __post_init__(self) -> None:
        require_physical_law(self.law)
        set_ = object.__setattr__
        set_(self, "mass", parse_quantity(self.mass, "mass", "[mass]", "1 kg"))
        set_(
            self, "stiffness", parse_quantity(self.stiffness, "stiffness", "[mass] / [time] ** 2", "100 N/m")
        )
        set_(self, "load", parse_quantity(self.load, "load", "[force]", "5 N"))
        freq = self.frequency
        if (isinstance(freq, str) and freq.strip().endswith("Hz")) or (
            hasattr(freq, "units") and str(getattr(freq, "units", "")) == "hertz"
        ):
            hz = parse_quantity(freq, "frequency", "1 / [time]", "2 Hz")
            set_(self, "frequency", Q_(2.0 * math.pi * hz.to("Hz").magnitude, "rad/s"))
        else:
            set_(self, "frequency", parse_quantity(freq, "frequency", "1 / [time]", "2 Hz"))
        set_(self, "force", parse_quantity(self.force, "force", "[force]", "0.5 N", allow_zero=True))
        set_(self, "v0", parse_quantity(self.v0, "v0", "[length] / [time]", "0.1 m/s", allow_zero=True))
        set_(
            self,
            "damping",
            parse_quantity(self.damping, "damping", "[mass] / [time]", "0.5 N*s/m", allow_zero=True),
        )
        if self.drive_amplitude is not None and self.base_amplitude is not None:
            raise ValueError(
                f"drive_amplitude={self.drive_amplitude!r}, base_amplitude={self.base_amplitude!r}: give one "
                "(a support displacement Y sin(Omega t) is a drive velocity Omega Y cos(Omega t))"
            )
        if self.base_amplitude is not None:
            set_(
                self,
                "base_amplitude",
                parse_quantity(self.base_amplitude, "base_amplitude", "[length]", "1 mm", allow_zero=True),
            )
        if self.drive_amplitude is not None:
            set_(
                self,
                "drive_amplitude",
                parse_quantity(
                    self.drive_amplitude, "drive_amplitude", "[length] / [time]", "0.05 m/s", allow_zero=True
                ),
            )
        ph = self.phase
        if isinstance(ph, str) or hasattr(ph, "units"):
            set_(
                self,
                "phase",
                float(
                    parse_quantity(ph, "phase", "[]", "90 deg", allow_zero=True, allow_negative=True)
                    .to("rad")
                    .magnitude
                ),
            )
        else:
            set_(self, "phase", _phase(ph, "phase"))

    @functools.cached_property
    def _block(self) -> PhysicalParameters:
        # the autonomous set-up with the same mass, spring, load and law: its scales and its law's
        # dimensionless form (a driving velocity it needs is any positive one: the scales do not use it)
        return PhysicalParameters(self.mass, self.stiffness, self.load, "1 m/s", self.law)

    @property
    def scales(self) -> Scales:
        """The force, time, length and velocity units of the dimensionless model."""
        return self._block.scales

    @property
    def drive_velocity_amplitude(self) -> Any:
        """``V1`` (m/s): the drive's modulation, or ``Omega Y`` of a support displacement."""
        if self.base_amplitude is not None:
            omega = float(self.frequency.to("rad/s").magnitude)
            return Q_(omega * float(self.base_amplitude.to("m").magnitude), "m/s")
        return self.drive_amplitude if self.drive_amplitude is not None else Q_(0.0, "m/s")

    def dimensionless(self) -> ForcedSystem:
        """Return the dimensionless system (module docstring: the scaling)."""
        sc = self.scales
        beta = float(sc.beta.to("s/m").magnitude)
        k = float(self.stiffness.to("N/m").magnitude)
        m = float(self.mass.to("kg").magnitude)
        return ForcedSystem(
            law=self._block.dimensionless().law,
            omega=float(self.frequency.to("rad/s").magnitude) * math.sqrt(m / k),
            q=float(self.force.to("N").magnitude) / float(sc.force.to("N").magnitude),
            nu0=beta * float(self.v0.to("m/s").magnitude),
            nu1=beta * float(self.drive_velocity_amplitude.to("m/s").magnitude),
            phi=float(self.phase),
            delta=float(self.damping.to("kg/s").magnitude) / math.sqrt(k * m),
        )


def as_forced(system: Any) -> tuple[ForcedSystem, Scales | None]:
    """Return the dimensionless system and, for a physical one, its scales."""
    if isinstance(system, ForcedSystem):
        return system, None
    if isinstance(system, PhysicalForcedSystem):
        return system.dimensionless(), system.scales
    raise ArgumentTypeError(f"system={system!r}: expected a ForcedSystem or a PhysicalForcedSystem")
