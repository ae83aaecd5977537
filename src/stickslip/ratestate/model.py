"""Rate-and-state friction parameters with units (Dieterich–Ruina laws).

Friction ``mu = mu0 + A ln(v/V_r) + B ln(Phi V_r / D0)`` with the state
``Phi`` (a time) evolving by the aging law ``Phi' = 1 - v Phi / D0`` (Dieterich)
or the slip law ``Phi' = -(v Phi / D0) ln(v Phi / D0)`` (Ruina). Sources:
J. H. Dieterich, J. Geophys. Res. 84 (1979) 2161; A. Ruina, J. Geophys. Res. 88
(1983) 10359; J. R. Rice and A. L. Ruina, J. Appl. Mech. 50 (1983) 343.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pint

from ..units import check_number, parse_quantity

__all__ = ["RateStateParameters"]

STATE_LAWS = ("aging", "slip")


@dataclass(frozen=True)
class RateStateParameters:
    """A rate-and-state spring-slider.

    Parameters
    ----------
    a, b : float
        Direct and evolution effects ``A > 0`` and ``B >= 0`` (dimensionless).
    dc : pint.Quantity or str
        Characteristic slip distance ``D0``, e.g. ``"10 um"``.
    v_ref : pint.Quantity or str
        Reference velocity ``V_r`` at which steady friction is ``mu0``, e.g. ``"1 um/s"``.
    mu0 : float
        Steady-state friction at ``V_r``.
    stiffness : pint.Quantity or str, optional
        Spring constant ``k`` (force/length), with ``load``; or give ``stiffness_per_load``.
    load : pint.Quantity or str, optional
        Normal load ``W``.
    stiffness_per_load : pint.Quantity or str, optional
        ``k/W`` as friction per length (1/length), e.g. ``"0.5 1/mm"``.
    mass : pint.Quantity or str, optional
        Mass of the slider: the inertial model (needs ``load``). Default: quasi-static.
    state_law : str, optional
        ``"aging"`` (default) or ``"slip"``.

    Raises
    ------
    ValueError
        For a missing, conflicting, non-physical or wrongly dimensioned value.

    """

    a: float
    b: float
    dc: Any
    v_ref: Any
    mu0: float
    stiffness: Any = None
    load: Any = None
    stiffness_per_load: Any = None
    mass: Any = None
    state_law: str = "aging"

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "a", check_number(self.a, "a", what="a positive direct effect A"))
        set_(self, "b", check_number(self.b, "b", allow_zero=True, what="a non-negative evolution effect B"))
        set_(self, "mu0", check_number(self.mu0, "mu0", what="a positive reference friction"))
        set_(self, "dc", parse_quantity(self.dc, "dc", "[length]", "10 um"))
        set_(self, "v_ref", parse_quantity(self.v_ref, "v_ref", "[length] / [time]", "1 um/s"))
        if self.state_law not in STATE_LAWS:
            raise ValueError(f"state_law={self.state_law!r}: expected 'aging' or 'slip'")
        if self.load is not None:
            set_(self, "load", parse_quantity(self.load, "load", "[force]", "10 N"))
        if self.stiffness_per_load is not None:
            if self.stiffness is not None:
                raise ValueError("give stiffness (with load) or stiffness_per_load, not both")
            set_(
                self,
                "stiffness_per_load",
                parse_quantity(self.stiffness_per_load, "stiffness_per_load", "1 / [length]", "0.5 1/mm"),
            )
        elif self.stiffness is not None:
            if self.load is None:
                raise ValueError("stiffness needs load (or give stiffness_per_load = k/W)")
            set_(
                self,
                "stiffness",
                parse_quantity(self.stiffness, "stiffness", "[mass] / [time] ** 2", "1e6 N/m"),
            )
        else:
            raise ValueError("give stiffness and load, or stiffness_per_load (k/W, 1/length)")
        if self.mass is not None:
            if self.load is None:
                raise ValueError("mass needs load: the inertial model is m x'' = k (x_lp - x) - W mu")
            set_(self, "mass", parse_quantity(self.mass, "mass", "[mass]", "1 kg"))

    @property
    def kw(self) -> pint.Quantity:
        """``k/W`` (1/m)."""
        if self.stiffness_per_load is not None:
            return self.stiffness_per_load.to("1/m")
        return (self.stiffness / self.load).to("1/m")

    @property
    def inertial(self) -> bool:
        """Whether the slider has a mass (inertial model)."""
        return self.mass is not None

    @property
    def critical_kw(self) -> pint.Quantity:
        """Critical ``k/W = (B - A)/D0`` (1/m): steady sliding is unstable below it (quasi-static)."""
        return ((self.b - self.a) / self.dc).to("1/m")

    @property
    def critical_stiffness(self) -> pint.Quantity:
        """Critical stiffness ``k_c = (B - A) W / D0`` (N/m); needs ``load``."""
        if self.load is None:
            raise ValueError("critical_stiffness needs load; use critical_kw for k/W")
        return (self.critical_kw * self.load).to("N/m")

    def kappa(self) -> float:
        """Return the appendix's ``kappa = k D0 / W``."""
        return float((self.kw * self.dc).to("").magnitude)

    def steady_state_friction(self, v: Any) -> npt.NDArray[np.float64]:
        """Return ``mu_ss = mu0 + (A - B) ln(v/V_r)`` at slip velocity ``v`` (> 0)."""
        if isinstance(v, str):
            v = parse_quantity(v, "v", "[length] / [time]", "1 um/s", allow_zero=True)
        if not isinstance(v, pint.Quantity) or not v.check("[length] / [time]"):
            raise ValueError(f"v={v!r}: expected a velocity with units such as '1 um/s'")
        x = np.asarray((v / self.v_ref).to("").magnitude, dtype=float)
        if np.any(~(x > 0)):
            raise ValueError(f"v={v!r}: mu_ss has ln(v/V_r), the logarithm needs a positive velocity")
        return self.mu0 + (self.a - self.b) * np.log(x)

    def core_params(self) -> npt.NDArray[np.float64]:
        """Return ``(A, B, D0, V_r, mu0, k/W, W/m)`` in SI for the compiled core."""
        wm = (self.load / self.mass).to("m/s**2").magnitude if self.mass is not None else 0.0
        return np.array(
            [
                self.a,
                self.b,
                self.dc.to("m").magnitude,
                self.v_ref.to("m/s").magnitude,
                self.mu0,
                self.kw.to("1/m").magnitude,
                wm,
            ]
        )

    @property
    def law_id(self) -> int:
        """0 for the aging law, 1 for the slip law."""
        return STATE_LAWS.index(self.state_law)

    def dimensionless(self, v0: Any) -> dict[str, float]:
        """Return the appendix's ``omega = v0/V_r``, ``gamma = exp(-mu0/A)``, ``kappa = k D0/W``."""
        v = (
            parse_quantity(v0, "v0", "[length] / [time]", "1 um/s")
            if not isinstance(v0, pint.Quantity)
            else v0
        )
        return {
            "omega": float((v / self.v_ref).to("").magnitude),
            "gamma": math.exp(-self.mu0 / self.a),
            "kappa": self.kappa(),
            "A": self.a,
            "B": self.b,
        }
