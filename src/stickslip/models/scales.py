"""The units of the dimensionless model: the scales in SI, and the one table of unit labels.

With the static friction force ``mu_s W`` as force unit and ``sqrt(m/k)`` as time
unit (PHYSICS.md §1), every result of the dimensionless model is of one of five
kinds -- force, time, length, velocity, energy -- and :class:`Scales` turns each
into SI and back. :data:`UNITS` names each kind's unit: the SI one, and the
dimensionless one as CF's ``scale`` attribute and a column header say it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pint

__all__ = ["KINDS", "UNITS", "Scales", "UnitLabel", "unit_attrs", "unit_label"]


@dataclass(frozen=True)
class UnitLabel:
    """How a kind of quantity's unit is written.

    Attributes
    ----------
    si : str
        The SI unit, as UDUNITS (CF) and pint read it (``"m/s"``).
    scale : str
        The dimensionless unit in words, CF's ``scale`` attribute (``"static friction
        force mu_s W"``).
    short : str
        The dimensionless unit in a column header's brackets (``"mu_s W"``).

    """

    si: str
    scale: str
    short: str


#: the unit of each kind of result, physical and dimensionless
UNITS: dict[str, UnitLabel] = {
    "force": UnitLabel("N", "static friction force mu_s W", "mu_s W"),
    "time": UnitLabel("s", "sqrt(m/k)", "sqrt(m/k)"),
    "length": UnitLabel("m", "mu_s W / k", "mu_s W / k"),
    "velocity": UnitLabel("m/s", "mu_s W / sqrt(k m)", "mu_s W / sqrt(k m)"),
    "energy": UnitLabel("J", "(mu_s W)**2 / k", "(mu_s W)**2 / k"),
}
#: the kinds of dimensional result, in :data:`UNITS`' order
KINDS = tuple(UNITS)


def unit_label(kind: str, physical: bool) -> str:
    """Return the unit of ``kind`` for a column header: SI, or the dimensionless scale ("1" a pure number)."""
    if kind == "1":
        return "1"
    return UNITS[kind].si if physical else UNITS[kind].short


def unit_attrs(kind: str, physical: bool) -> dict[str, str]:
    """Return CF attributes of a value of ``kind``: ``units`` (UDUNITS; "1" for a dimensionless one).

    A dimensionless value's ``units`` is "1", as CF asks of a pure number, and its
    ``scale`` says of what (``"static friction force mu_s W"``): a CF reader parses
    ``units`` and would not parse a scale written there.
    """
    if kind == "1":
        return {"units": "1"}
    if physical:
        return {"units": UNITS[kind].si}
    return {"units": "1", "scale": UNITS[kind].scale}


@dataclass(frozen=True)
class Scales:
    """Units of the dimensionless model in SI.

    Attributes
    ----------
    force : pint.Quantity
        Static friction force ``mu_s W`` (N).
    time : pint.Quantity
        ``sqrt(m/k)`` (s).
    length : pint.Quantity
        ``mu_s W / k`` (m).
    velocity : pint.Quantity
        ``mu_s W / sqrt(k m) = 1/beta`` (m/s).

    """

    force: pint.Quantity
    time: pint.Quantity
    length: pint.Quantity
    velocity: pint.Quantity

    @property
    def beta(self) -> pint.Quantity:
        """``beta = sqrt(k m)/(mu_s W)`` (s/m)."""
        return (1.0 / self.velocity).to("s/m")

    @property
    def energy(self) -> pint.Quantity:
        """``(mu_s W)**2 / k`` (J)."""
        return (self.force * self.length).to("J")

    def factor(self, kind: str) -> float:
        """Return the SI size of the dimensionless unit of ``kind`` (one of :data:`KINDS`), a float."""
        if kind not in UNITS:
            raise ValueError(f"kind={kind!r}: expected one of {', '.join(KINDS)}")
        return float(getattr(self, kind).to(UNITS[kind].si).magnitude)

    def to_si(self, kind: str, x: Any) -> Any:
        """Return dimensionless values of ``kind`` in SI: a float for a scalar, an array for an array."""
        f = self.factor(kind)
        return float(x) * f if np.ndim(x) == 0 else np.asarray(x, dtype=float) * f

    def from_si(self, kind: str, q: Any) -> Any:
        """Return a quantity of ``kind`` (pint, or a number in SI) in the model's units."""
        if isinstance(q, pint.Quantity):
            v = (q / getattr(self, kind)).to("").magnitude
            return float(v) if np.ndim(v) == 0 else np.asarray(v, dtype=float)
        f = self.factor(kind)
        return float(q) / f if np.ndim(q) == 0 else np.asarray(q, dtype=float) / f
