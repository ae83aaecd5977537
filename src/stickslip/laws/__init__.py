"""Friction laws: each declared once, in a module of its own, and registered.

Built-in: :mod:`~.weakening` (the paper's F1 and F2), :mod:`~.cubic` (Thomsen and
Fidlin), :mod:`~.coulomb` and :mod:`~.carlson_langer` (the chain's law). A user's
own law: :class:`~.expression.ExpressionLaw` (a formula) or
:class:`~.table.TabulatedLaw` (a measured table). To add a law to the package,
write one module like :mod:`~.coulomb` (a :class:`~.spec.LawSpec` and
:func:`~.registry.register`) and import it here; see ``docs/laws.md``.
"""

from typing import TYPE_CHECKING, Any

from ..lazy import load_attribute
from . import carlson_langer, coulomb, cubic, weakening
from .base import DimensionlessLaw, PhysicalLaw, law_arrays, require_dimensionless_law, require_physical_law
from .carlson_langer import CarlsonLangerLaw, PhysicalCarlsonLangerLaw
from .coulomb import CoulombLaw, PhysicalCoulombLaw
from .cubic import CubicLaw, PhysicalCubicLaw
from .registry import get, names, register
from .spec import LawSpec, Parameter
from .weakening import PhysicalWeakeningLaw, WeakeningLaw, f1, f2

if TYPE_CHECKING:
    from .expression import ExpressionLaw, PhysicalExpressionLaw
    from .table import TabulatedDimensionlessLaw, TabulatedLaw

#: the laws a user writes, loaded on first use: a formula's and a table's need sympy
#: (0.3 s of every command's start)
_HOME = {
    "ExpressionLaw": "expression",
    "PhysicalExpressionLaw": "expression",
    "TabulatedDimensionlessLaw": "table",
    "TabulatedLaw": "table",
}


def __getattr__(name: str) -> Any:
    """Return a user's law (:data:`_HOME`) or its module, loaded on first use (PEP 562)."""
    return load_attribute(__name__, name, _HOME, ("expression", "table", "formula", "series", "compiler"))


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
    "law_arrays",
    "names",
    "register",
    "require_dimensionless_law",
    "require_physical_law",
    "weakening",
]
