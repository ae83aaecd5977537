"""Coulomb friction with a static and a lower kinetic level.

``f(w) = kinetic`` for ``w > 0`` (``0 < kinetic = mu_k / mu_s <= 1``): friction
drops at the onset of slip and is constant while sliding. ``kinetic = 1`` is
friction without a drop (Den Hartog's forced oscillator, :mod:`stickslip.forced`);
driven at a constant velocity it has no stick-slip, only the neutral oscillation
that touches zero velocity once a period. Its stick-slip cycle
has a closed form (PHYSICS.md §2), which the tests check the engine against.

Source: C. A. Coulomb, *Théorie des machines simples* (1785); the static/kinetic
form as in B. N. J. Persson, *Sliding Friction* (Springer, 2000), ch. 1.
"""

from __future__ import annotations

from ..core.laws import LAW_COULOMB
from .base import DimensionlessLaw, PhysicalLaw
from .registry import register
from .spec import LawSpec, Parameter

__all__ = ["COULOMB", "CoulombLaw", "PhysicalCoulombLaw"]

COULOMB = LawSpec(
    name="coulomb",
    title="Coulomb friction: static level 1, kinetic level below it",
    f="kinetic",
    parameters=(
        Parameter(
            "kinetic", "kinetic/static friction ratio mu_k/mu_s", lower=0.0, upper=1.0, upper_inclusive=True
        ),
    ),
    physical=(Parameter("mu_k", "kinetic friction coefficient, below mu_s"),),
    to_dimensionless={"kinetic": "mu_k/mu_s"},
    source="C. A. Coulomb (1785); B. N. J. Persson, Sliding Friction (Springer, 2000), ch. 1",
    core_id=LAW_COULOMB,
    map_parameters=(),
    example={"kinetic": 0.6},  # stick-slip wherever it moves: a map shows nothing
    notes="Friction drops from 1 to the kinetic level at the onset of slip; the cycle has a closed form.",
)


class CoulombLaw(DimensionlessLaw):
    r"""Coulomb friction with distinct static and kinetic coefficients, dimensionless.

    .. math:: f(w) = f_k \operatorname{sgn}(w), \qquad 0 < f_k = \mu_k / \mu_s \le 1.

    Parameters
    ----------
    kinetic : float
        Kinetic friction in units of static friction, ``0 < kinetic <= 1``.

    """

    __slots__ = ()
    _spec = COULOMB


class PhysicalCoulombLaw(PhysicalLaw):
    """Coulomb law with static ``mu_s`` and kinetic ``mu_k < mu_s`` coefficients.

    Parameters
    ----------
    mu_s : float
        Static friction coefficient, ``mu_s > 0``.
    mu_k : float
        Kinetic friction coefficient, ``0 < mu_k <= mu_s``.

    """

    __slots__ = ()
    _spec = COULOMB


register(COULOMB, CoulombLaw, PhysicalCoulombLaw)
