"""The friction law of Carlson and Langer's chain: a drop at the onset of slip, then weakening.

``f(w) = (1 - sigma) / (1 + 2 alpha w / (1 - sigma))`` for ``w > 0``, friction in
units of the static friction force (the threshold at rest is 1, so ``sigma`` is
the drop at the onset of slip). With the block velocity ``w`` in units of
``F_s / sqrt(k_p m)`` this is Carlson and Langer's ``phi(2 alpha w)`` with
``phi(y) = (1 - sigma) / (1 + y / (1 - sigma))``. Physically
``mu(v) = mu_s (1 - drop) / (1 + v / ((1 - drop) v_c))`` with ``v_c`` the
velocity scale of the weakening: ``alpha = 1 / (2 beta v_c)``, ``sigma = drop``.

In Carlson and Langer's model a block cannot slip backward (friction at rest is
bounded only from above); the chain engine follows that convention for this law
unless told otherwise (``backslip``).

Source: J. M. Carlson and J. S. Langer, "Mechanical model of an earthquake
fault", Phys. Rev. A 40, 6470 (1989), eqs. (2.4)-(2.6).
"""

from __future__ import annotations

from ..core.laws import LAW_CARLSON_LANGER
from .base import DimensionlessLaw, PhysicalLaw
from .registry import register
from .spec import LawSpec, Parameter

__all__ = ["CARLSON_LANGER", "CarlsonLangerLaw", "PhysicalCarlsonLangerLaw"]

CARLSON_LANGER = LawSpec(
    name="carlson-langer",
    title="Carlson-Langer law (1 - sigma)/(1 + 2 alpha w/(1 - sigma)): a drop sigma, then weakening",
    f="(1 - sigma)/(1 + 2*alpha*w/(1 - sigma))",
    parameters=(
        Parameter("alpha", "velocity weakening alpha = 1/(2 beta v_c)"),
        Parameter(
            "sigma",
            "drop of friction at the onset of slip, in units of static friction",
            lower=0.0,
            lower_inclusive=True,
            upper=1.0,
        ),
    ),
    physical=(
        Parameter("v_c", "velocity scale of the weakening v_c", unit="m/s", example="0.01 m/s"),
        Parameter(
            "drop",
            "drop of friction at the onset of slip, a fraction of mu_s (the dimensionless sigma)",
            lower=0.0,
            lower_inclusive=True,
            upper=1.0,
        ),
    ),
    to_dimensionless={"alpha": "1/(2*beta*v_c)", "sigma": "drop"},
    source="J. M. Carlson and J. S. Langer, Phys. Rev. A 40, 6470 (1989), eqs. (2.4)-(2.6)",
    core_id=LAW_CARLSON_LANGER,
    example={"alpha": 2.5, "sigma": 0.01},
    notes=(
        "The law of Carlson and Langer's Burridge-Knopoff chain (`stickslip chain`). "
        "In their model blocks never slip backward; the chain follows that convention for this law."
    ),
)


class CarlsonLangerLaw(DimensionlessLaw):
    r"""Carlson and Langer's law, dimensionless.

    .. math:: f(w) = \frac{1 - \sigma}{1 + 2 \alpha w / (1 - \sigma)}, \qquad w > 0,

    with the static threshold 1 (a drop ``sigma`` at the onset of slip).

    Parameters
    ----------
    alpha : float
        Velocity weakening (dimensionless), ``alpha > 0``.
    sigma : float
        Drop at the onset of slip (units of static friction), ``0 <= sigma < 1``.

    """

    __slots__ = ()
    _spec = CARLSON_LANGER


class PhysicalCarlsonLangerLaw(PhysicalLaw):
    """Carlson and Langer's law in physical units: ``mu(v) = mu_s (1 - drop)/(1 + v/((1 - drop) v_c))``.

    Parameters
    ----------
    mu_s : float
        Static friction coefficient, ``mu_s > 0``.
    v_c : pint.Quantity or str
        Velocity scale of the weakening, e.g. ``"0.01 m/s"``.
    drop : float
        Drop at the onset of slip, a fraction of ``mu_s``, ``0 <= drop < 1``.

    """

    __slots__ = ()
    _spec = CARLSON_LANGER


register(CARLSON_LANGER, CarlsonLangerLaw, PhysicalCarlsonLangerLaw)
