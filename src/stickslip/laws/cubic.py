"""The cubic law of Thomsen and Fidlin: ``f(w) = 1 - alpha w + gamma w**3``.

Physically ``mu(v) = mu_s sgn(v) - k1 v + k3 v**3`` (a mass on a moving belt), so
``alpha = k1 / (mu_s beta)`` and ``gamma = k3 / (mu_s beta**3)``. Its averaging
analysis gives closed forms for the Hopf point, the pure-slip amplitude and the
pure-slip / stick-slip border (:mod:`stickslip.bifurcation.averaging`).

Source: J. J. Thomsen and A. Fidlin, "Analytical approximations for stick-slip
vibration amplitudes", Int. J. Non-Linear Mech. 38 (2003) 389-403.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import numpy.typing as npt

from ..core.laws import LAW_CUBIC
from ..userwarnings import warn
from .base import DimensionlessLaw, PhysicalLaw
from .registry import register
from .spec import LawSpec, Parameter

__all__ = ["CUBIC", "CubicLaw", "PhysicalCubicLaw"]


def _warn_negative(values: Mapping[str, npt.NDArray[np.float64]]) -> None:
    """Warn where the friction turns negative (``alpha**3 > 27 gamma / 4``): it drives the block."""
    a, g = values["alpha"], values["gamma"]
    w_min = np.sqrt(a / (3.0 * g))
    f_min = 1.0 - 2.0 * a * w_min / 3.0
    bad = np.flatnonzero(np.ravel(f_min) < 0.0)
    if bad.size:
        i = int(bad[0])
        where = f" (at {bad.size} of {f_min.size} points, the first shown)" if f_min.size > 1 else ""
        warn(
            f"cubic law alpha={float(np.ravel(a)[i])!r}, gamma={float(np.ravel(g)[i])!r}: the friction turns "
            f"negative (minimum {float(np.ravel(f_min)[i]):.3g} at w = {float(np.ravel(w_min)[i]):.3g}; "
            "it stays "
            f"positive for alpha**3 < 27 gamma / 4): it drives the block there{where}",
        )


CUBIC = LawSpec(
    name="cubic",
    title="cubic law of Thomsen and Fidlin, 1 - alpha w + gamma w^3",
    f="1 - alpha*w + gamma*w**3",
    parameters=(
        Parameter("alpha", "linear weakening alpha = k1/(mu_s beta)"),
        Parameter("gamma", "cubic strengthening gamma = k3/(mu_s beta^3)"),
    ),
    physical=(
        Parameter("k1", "linear coefficient k1", unit="s/m", example="0.5 s/m"),
        Parameter("k3", "cubic coefficient k3", unit="s**3/m**3", example="0.01 s**3/m**3"),
    ),
    to_dimensionless={"alpha": "k1/(mu_s*beta)", "gamma": "k3/(mu_s*beta**3)"},
    source="J. J. Thomsen and A. Fidlin, Int. J. Non-Linear Mech. 38 (2003) 389-403",
    core_id=LAW_CUBIC,
    check=_warn_negative,
    example={"alpha": 0.5, "gamma": 1 / 6},
    notes="Friction stays positive for alpha^3 < 27 gamma / 4; a warning says where it does not.",
)


class CubicLaw(DimensionlessLaw):
    r"""Cubic law of Thomsen and Fidlin, dimensionless.

    .. math:: f(w) = \operatorname{sgn}(w) - \alpha w + \gamma w^3

    Parameters
    ----------
    alpha : float
        Linear weakening coefficient (dimensionless), ``alpha > 0``.
    gamma : float
        Cubic strengthening coefficient (dimensionless), ``gamma > 0``.

    """

    __slots__ = ()
    _spec = CUBIC


class PhysicalCubicLaw(PhysicalLaw):
    """Thomsen–Fidlin cubic law: ``mu(v) = mu_s sgn(v) - k1 v + k3 v**3``.

    Parameters
    ----------
    mu_s : float
        Static friction coefficient, ``mu_s > 0``.
    k1 : pint.Quantity or str
        Linear coefficient (time/length), e.g. ``"0.5 s/m"``.
    k3 : pint.Quantity or str
        Cubic coefficient (time**3/length**3), e.g. ``"0.01 s**3/m**3"``.

    """

    __slots__ = ()
    _spec = CUBIC


register(CUBIC, CubicLaw, PhysicalCubicLaw)
