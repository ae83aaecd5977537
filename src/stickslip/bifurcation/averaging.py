"""First-order averaging for the Thomsen-Fidlin cubic law, against the numerics.

For ``f(w) = sgn(w) - alpha w + gamma w^3`` (J. J. Thomsen and A. Fidlin,
Int. J. Non-Linear Mech. 38 (2003) 389-403; PHYSICS.md §3) the slip dynamics
near steady sliding is ``x'' + f'(nu + x) x' + x = 0`` with ``x = w - nu`` and
``f'(nu + x) = f'(nu) + 6 gamma nu x + 3 gamma x^2``. Averaging ``x = a cos t``
over one period gives ``a' = -(a/2) (f'(nu) + (3/4) gamma a^2)``, hence

- Hopf point: ``f'(nu_H) = 0``, ``nu_H = sqrt(alpha / (3 gamma))``;
- pure-slip cycle: ``a^2 = 4 (alpha - 3 gamma nu^2) / (3 gamma)`` for ``nu < nu_H``,
  a spring-force range ``2a`` (at unit frequency ``s - f(nu)`` has amplitude ``a``);
- pure-slip/stick-slip border: the cycle touches ``w = 0`` when ``a = nu``:
  ``nu_b = sqrt(4 alpha / (15 gamma))``.

All three depend on ``alpha / gamma`` only; the error of first-order averaging is
of the order of the nonlinearity, so scaling ``alpha = eps a0``,
``gamma = eps g0`` keeps the formulas fixed while the numerics converge to them
as ``eps -> 0`` (:func:`averaging_table`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import ArgumentTypeError
from ..laws import CubicLaw
from ..models.parameters import DimensionlessParameters
from ..orbits.periodic import pure_slip_orbit
from ..orbits.stability import hopf_points
from .continuation import continue_pure_slip

__all__ = ["ThomsenFidlin", "averaging_table", "thomsen_fidlin"]


@dataclass(frozen=True)
class ThomsenFidlin:
    """First-order averaging results for the cubic law (dimensionless).

    Attributes
    ----------
    alpha, gamma : float
        Law parameters.
    nu_hopf : float
        ``sqrt(alpha / (3 gamma))``.
    nu_border : float
        ``sqrt(4 alpha / (15 gamma))``: pure slip above, stick-slip below.

    """

    alpha: float
    gamma: float
    nu_hopf: float
    nu_border: float

    def amplitude(self, nu: float) -> float:
        """Spring-force range ``2a`` of the pure-slip cycle at ``nu`` (NaN where there is none)."""
        a2 = 4.0 * (self.alpha - 3.0 * self.gamma * nu * nu) / (3.0 * self.gamma)
        return 2.0 * math.sqrt(a2) if a2 > 0 else math.nan


def thomsen_fidlin(law: CubicLaw) -> ThomsenFidlin:
    """Return the averaging predictions for ``law``."""
    if not isinstance(law, CubicLaw):
        raise ArgumentTypeError(f"law={law!r}: the Thomsen-Fidlin formulas are for the cubic law")
    a, g = law.alpha, law.gamma
    return ThomsenFidlin(a, g, math.sqrt(a / (3.0 * g)), math.sqrt(4.0 * a / (15.0 * g)))


@dataclass(frozen=True)
class AveragingRow:
    """One row of :func:`averaging_table` (numerics against averaging)."""

    eps: float
    alpha: float
    gamma: float
    nu_hopf: float
    nu_hopf_formula: float
    nu_border: float
    nu_border_formula: float
    nu: float
    amplitude: float
    amplitude_formula: float

    @property
    def border_error(self) -> float:
        """Relative error of the averaged border."""
        return abs(self.nu_border_formula / self.nu_border - 1.0)

    @property
    def amplitude_error(self) -> float:
        """Relative error of the averaged amplitude at ``nu``."""
        return abs(self.amplitude_formula / self.amplitude - 1.0)


def averaging_table(
    eps: Sequence[float] = (1.0, 0.5, 0.25, 0.125, 0.0625),
    *,
    alpha: float = 0.5,
    gamma: float = 0.5 / 3.0,
    nu_fraction: float = 0.5,
) -> list[AveragingRow]:
    """Compare the averaging formulas with shooting and continuation for ``(eps alpha, eps gamma)``.

    The numerical border is the grazing point of the continued pure-slip branch;
    the amplitude is compared at ``nu = nu_b + nu_fraction (nu_H - nu_b)`` (formula values).
    """
    rows = []
    for e in eps:
        law = CubicLaw(alpha=e * alpha, gamma=e * gamma)
        tf = thomsen_fidlin(law)
        (h,) = hopf_points(law, 0.5 * tf.nu_hopf, 2.0 * tf.nu_hopf)
        _branch, points = continue_pure_slip(law, h, 0.1 * tf.nu_border, 2.0 * tf.nu_hopf)
        graze = [p.nu for p in points if p.kind == "grazing"]
        if not graze:
            raise RuntimeError(f"eps={e}: the pure-slip branch did not graze")
        nu = tf.nu_border + nu_fraction * (tf.nu_hopf - tf.nu_border)
        o = pure_slip_orbit(DimensionlessParameters(nu=nu, law=law))
        rows.append(
            AveragingRow(
                eps=e,
                alpha=law.alpha,
                gamma=law.gamma,
                nu_hopf=h.nu,
                nu_hopf_formula=tf.nu_hopf,
                nu_border=graze[0],
                nu_border_formula=tf.nu_border,
                nu=nu,
                amplitude=o.amplitude,
                amplitude_formula=tf.amplitude(nu),
            )
        )
    return rows
