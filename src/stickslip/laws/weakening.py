"""The paper's law: friction that weakens with velocity, with optional viscous strengthening.

``f(w) = 1/(1 + c w) + p w`` for ``w > 0``: ``p = 0`` is the paper's F1, ``p > 0``
its F2 (normalised as in PHYSICS.md §1: the linear term in units of ``mu_s W``).
Physically ``mu(v) = mu_s [1/(1 + a v) + b v]`` with ``c = a/beta``, ``p = b/beta``.

Source: J. Szkutnik and K. Kułakowski, "How to distinguish between stick-slip and
pure slip oscillations", arXiv cond-mat/0506435, eqs. (1)-(2); the ``1/(1 + a v)``
form after M. de Sousa Vieira.
"""

from __future__ import annotations

from typing import Any

from ..core.laws import LAW_WEAKENING
from .base import DimensionlessLaw, PhysicalLaw
from .registry import register
from .spec import LawSpec, Parameter

__all__ = ["WEAKENING", "PhysicalWeakeningLaw", "WeakeningLaw", "f1", "f2"]

WEAKENING = LawSpec(
    name="weakening",
    title="velocity weakening 1/(1 + c w) with viscous strengthening p w (the paper's F1, F2)",
    f="1/(1 + c*w) + p*w",
    parameters=(
        Parameter("c", "weakening rate c = a/beta", lower=0.0),
        Parameter(
            "p", "viscous strengthening p = b/beta (0: F1)", lower=0.0, lower_inclusive=True, default=0.0
        ),
    ),
    physical=(
        Parameter("a", "weakening rate a", unit="s/m", example="160 s/m"),
        Parameter(
            "b",
            "strengthening rate b, in units of mu_s W per velocity (0: F1)",
            unit="s/m",
            example="100 s/m",
            lower_inclusive=True,
            default=0.0,
        ),
    ),
    to_dimensionless={"c": "a/beta", "p": "b/beta"},
    source="J. Szkutnik and K. Kułakowski, arXiv cond-mat/0506435, eqs. (1)-(2)",
    core_id=LAW_WEAKENING,
    static_aliases=("mu0",),
    example={"c": 3.8, "p": 0.5},
    notes="The paper's F1 (b = 0) and F2. mu0 is the paper's name of mu_s.",
)


class WeakeningLaw(DimensionlessLaw):
    r"""Velocity-weakening law of the paper, dimensionless.

    .. math:: f(w) = \frac{1}{1 + c w} + p w, \qquad w > 0,

    with ``c = a / beta`` and ``p = b / beta``. ``p = 0`` is the paper's F1,
    ``p > 0`` its F2.

    Parameters
    ----------
    c : float
        Weakening rate (dimensionless), ``c > 0``.
    p : float, optional
        Viscous strengthening (dimensionless), ``p >= 0``. Default 0 (F1).

    """

    __slots__ = ()
    _spec = WEAKENING


class PhysicalWeakeningLaw(PhysicalLaw):
    """The paper's law in physical units: ``mu(v) = mu_s [1/(1 + a v) + b v]``.

    Parameters
    ----------
    mu_s : float
        Static friction coefficient (the paper's ``mu0``; ``mu0=`` is accepted), ``mu_s > 0``.
    a : pint.Quantity or str
        Weakening rate (time/length), e.g. ``"160 s/m"``.
    b : pint.Quantity or str, optional
        Strengthening rate (time/length), e.g. ``"100 s/m"``. Default 0 (F1).

    """

    __slots__ = ()
    _spec = WEAKENING


register(WEAKENING, WeakeningLaw, PhysicalWeakeningLaw)


def f1(mu_s: float, a: Any) -> PhysicalWeakeningLaw:
    """Return the paper's F1 law, ``F = mu_s W / (1 + a v)``."""
    return PhysicalWeakeningLaw(mu_s=mu_s, a=a, b="0 s/m")


def f2(mu_s: float, a: Any, b: Any) -> PhysicalWeakeningLaw:
    """Return the paper's F2 law, ``F = mu_s W [1/(1 + a v) + b v]``."""
    return PhysicalWeakeningLaw(mu_s=mu_s, a=a, b=b)
