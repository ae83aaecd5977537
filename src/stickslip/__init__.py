"""stickslip: friction oscillators, exact and fast.

The one-block Burridge–Knopoff (spring-block) model with velocity-dependent
friction, integrated event by event without smoothing the friction law.

Layers (each imports only downward): :mod:`stickslip.core` (compiled numbers),
:mod:`stickslip.models` (laws and parameters with units),
:mod:`stickslip.dynamics` (cycles, regimes, trajectories), :mod:`stickslip.io`
and :mod:`stickslip.plots`, and the command line :mod:`stickslip.cli`.
"""

from .dynamics import Attractor, CycleResult, Trajectory, cycle, simulate
from .models import (
    Q_,
    CoulombLaw,
    CubicLaw,
    DimensionlessParameters,
    PhysicalCoulombLaw,
    PhysicalCubicLaw,
    PhysicalParameters,
    PhysicalWeakeningLaw,
    Scales,
    WeakeningLaw,
    f1,
    f2,
    ureg,
    zv_parameters,
)

__version__ = "0.1.0"

__all__ = [
    "Q_",
    "Attractor",
    "CoulombLaw",
    "CubicLaw",
    "CycleResult",
    "DimensionlessParameters",
    "PhysicalCoulombLaw",
    "PhysicalCubicLaw",
    "PhysicalParameters",
    "PhysicalWeakeningLaw",
    "Scales",
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
