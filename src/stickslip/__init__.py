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

Beside the layers, :mod:`stickslip.errors` holds :class:`ArgumentTypeError`, raised by
every layer for an argument of the wrong type (a :class:`TypeError` that is also a
:class:`ValueError`); a wrong value raises :class:`ValueError`.

The package imports lazily: ``import stickslip`` is quick, and the names below load
their layer on first use (``stickslip.cycle``, ``from stickslip import simulate``), as
SciPy's subpackages do. So the command line can start, and answer Ctrl-C during its
start, before numba's compiled kernels are loaded.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .lazy import load_attribute

if TYPE_CHECKING:  # the names for type checkers and for readers; loaded by __getattr__
    from .dynamics.cycle import Attractor, CycleResult, cycle
    from .dynamics.trajectory import Trajectory, simulate
    from .errors import ArgumentTypeError
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

_HOME = {
    **dict.fromkeys(("Attractor", "CycleResult", "Trajectory", "cycle", "simulate"), "dynamics"),
    "ArgumentTypeError": "errors",
    **dict.fromkeys(
        (
            "CoulombLaw",
            "CubicLaw",
            "DimensionlessLaw",
            "ExpressionLaw",
            "PhysicalCoulombLaw",
            "PhysicalCubicLaw",
            "PhysicalLaw",
            "PhysicalWeakeningLaw",
            "TabulatedLaw",
            "WeakeningLaw",
            "f1",
            "f2",
        ),
        "laws",
    ),
    **dict.fromkeys(("DimensionlessParameters", "PhysicalParameters", "Scales", "zv_parameters"), "models"),
    **dict.fromkeys(("Q_", "ureg"), "units"),
}
_SUBPACKAGES = frozenset(
    {"bifurcation", "chains", "cli", "core", "data", "defaults", "dynamics", "explore", "io", "laws"}
    | {"errors", "models", "paper", "plots", "ratestate", "scale", "units"}
)


def __getattr__(name: str) -> Any:
    """Load an exported name, a subpackage or ``__version__`` on first use (PEP 562)."""
    if name == "__version__":
        from .io.output import package_version

        value: Any = package_version()
    else:
        value = load_attribute(__name__, name, _HOME, _SUBPACKAGES)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_HOME, *_SUBPACKAGES, "__version__"})


__all__ = [
    "Q_",
    "ArgumentTypeError",
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
