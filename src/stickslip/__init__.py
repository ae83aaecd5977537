"""stickslip: friction oscillators, exact and fast.

The one-block Burridge–Knopoff (spring-block) model with velocity-dependent
friction, integrated event by event without smoothing the friction law.

Layers, each importing only from those below it (checked by import-linter):

* :mod:`stickslip.core`: compiled kernels and their array API (numbers only);
* :mod:`stickslip.units`, :mod:`stickslip.io`: units, files;
* :mod:`stickslip.laws`: friction laws, each declared once and registered;
* :mod:`stickslip.models`: parameter sets with units;
* :mod:`stickslip.bifurcation`, :mod:`stickslip.dynamics`: orbits and regimes, cycles and sweeps;
* :mod:`stickslip.data`, :mod:`stickslip.ratestate`: measured records, rate and state;
* :mod:`stickslip.plots`, :mod:`stickslip.paper`: figures, the paper's reproduction;
* :mod:`stickslip.cli`: the command line.
"""

from .dynamics import Attractor, CycleResult, Trajectory, cycle, simulate
from .io.output import package_version
from .laws import (
    CoulombLaw,
    CubicLaw,
    DimensionlessLaw,
    ExpressionLaw,
    PhysicalCoulombLaw,
    PhysicalCubicLaw,
    PhysicalLaw,
    PhysicalWeakeningLaw,
    TabulatedLaw,
    WeakeningLaw,
    f1,
    f2,
)
from .models import DimensionlessParameters, PhysicalParameters, Scales, zv_parameters
from .units import Q_, ureg

__version__ = package_version()

__all__ = [
    "Q_",
    "Attractor",
    "CoulombLaw",
    "CubicLaw",
    "CycleResult",
    "DimensionlessLaw",
    "DimensionlessParameters",
    "ExpressionLaw",
    "PhysicalCoulombLaw",
    "PhysicalCubicLaw",
    "PhysicalLaw",
    "PhysicalParameters",
    "PhysicalWeakeningLaw",
    "Scales",
    "TabulatedLaw",
    "Trajectory",
    "WeakeningLaw",
    "__version__",
    "cycle",
    "f1",
    "f2",
    "simulate",
    "ureg",
    "zv_parameters",
]
