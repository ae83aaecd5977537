"""Friction laws: each declared once, in a module of its own, and registered.

Built-in: :mod:`~.weakening` (the paper's F1 and F2), :mod:`~.cubic` (Thomsen and
Fidlin) and :mod:`~.coulomb`. A user's own law: :class:`~.expression.ExpressionLaw`
(a formula) or :class:`~.table.TabulatedLaw` (a measured table). To add a law to
the package, write one module like :mod:`~.coulomb` (a :class:`~.spec.LawSpec` and
:func:`~.registry.register`) and import it here; see ``docs/laws.md``.
"""

from . import coulomb, cubic, weakening
from .base import DimensionlessLaw, PhysicalLaw, require_dimensionless_law, require_physical_law
from .coulomb import CoulombLaw, PhysicalCoulombLaw
from .cubic import CubicLaw, PhysicalCubicLaw
from .expression import ExpressionLaw, PhysicalExpressionLaw
from .registry import get, names, register
from .spec import LawSpec, Parameter
from .table import TabulatedDimensionlessLaw, TabulatedLaw
from .weakening import PhysicalWeakeningLaw, WeakeningLaw, f1, f2

#: the laws that ship with stickslip (others may be registered at run time)
BUILTIN_LAWS = ("weakening", "cubic", "coulomb")

__all__ = [
    "BUILTIN_LAWS",
    "CoulombLaw",
    "CubicLaw",
    "DimensionlessLaw",
    "ExpressionLaw",
    "LawSpec",
    "Parameter",
    "PhysicalCoulombLaw",
    "PhysicalCubicLaw",
    "PhysicalExpressionLaw",
    "PhysicalLaw",
    "PhysicalWeakeningLaw",
    "TabulatedDimensionlessLaw",
    "TabulatedLaw",
    "WeakeningLaw",
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
