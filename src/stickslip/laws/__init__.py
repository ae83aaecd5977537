"""Friction laws: each declared once, in a module of its own, and registered.

Built-in: :mod:`~.weakening` (the paper's F1 and F2), :mod:`~.cubic` (Thomsen and
Fidlin), :mod:`~.coulomb` and :mod:`~.carlson_langer` (the chain's law). A user's
own law: :class:`~.expression.ExpressionLaw` (a formula) or
:class:`~.table.TabulatedLaw` (a measured table). To add a law to the package,
write one module like :mod:`~.coulomb` (a :class:`~.spec.LawSpec` and
:func:`~.registry.register`) and import it here; see ``docs/laws.md``.
"""

from . import carlson_langer, coulomb, cubic, weakening
from .base import DimensionlessLaw, PhysicalLaw, require_dimensionless_law, require_physical_law
from .carlson_langer import CarlsonLangerLaw, PhysicalCarlsonLangerLaw
from .coulomb import CoulombLaw, PhysicalCoulombLaw
from .cubic import CubicLaw, PhysicalCubicLaw
from .expression import ExpressionLaw, PhysicalExpressionLaw
from .registry import get, names, register
from .spec import LawSpec, Parameter
from .table import TabulatedDimensionlessLaw, TabulatedLaw
from .weakening import PhysicalWeakeningLaw, WeakeningLaw, f1, f2

#: the laws that ship with stickslip (others may be registered at run time)
BUILTIN_LAWS = ("weakening", "cubic", "coulomb", "carlson-langer")

__all__ = [
    "BUILTIN_LAWS",
    "CarlsonLangerLaw",
    "CoulombLaw",
    "CubicLaw",
    "DimensionlessLaw",
    "ExpressionLaw",
    "LawSpec",
    "Parameter",
    "PhysicalCarlsonLangerLaw",
    "PhysicalCoulombLaw",
    "PhysicalCubicLaw",
    "PhysicalExpressionLaw",
    "PhysicalLaw",
    "PhysicalWeakeningLaw",
    "TabulatedDimensionlessLaw",
    "TabulatedLaw",
    "WeakeningLaw",
    "carlson_langer",
    "coulomb",
    "cubic",
    "f1",
    "f2",
    "get",
    "names",
    "register",
    "require_dimensionless_law",
    "require_physical_law",
    "weakening",
]
