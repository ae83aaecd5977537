"""Model layer: friction laws and parameter sets with units and validation."""

from .friction import (
    CoulombLaw,
    CubicLaw,
    DimensionlessLaw,
    PhysicalCoulombLaw,
    PhysicalCubicLaw,
    PhysicalLaw,
    PhysicalWeakeningLaw,
    WeakeningLaw,
    f1,
    f2,
)
from .parameters import DimensionlessParameters, PhysicalParameters, Scales, zv_parameters
from .units import Q_, ureg

__all__ = [
    "Q_",
    "CoulombLaw",
    "CubicLaw",
    "DimensionlessLaw",
    "DimensionlessParameters",
    "PhysicalCoulombLaw",
    "PhysicalCubicLaw",
    "PhysicalLaw",
    "PhysicalParameters",
    "PhysicalWeakeningLaw",
    "Scales",
    "WeakeningLaw",
    "f1",
    "f2",
    "ureg",
    "zv_parameters",
]
