"""stickslip: friction oscillators, exact and fast.

The one-block Burridge–Knopoff (spring-block) model with velocity-dependent
friction, integrated event by event without smoothing the friction law.

Layers, each importing only from those below it (checked by import-linter):

* :mod:`stickslip.core`: compiled kernels and their array API (numbers only);
* :mod:`stickslip.units`, :mod:`stickslip.io`: units, files;
* :mod:`stickslip.laws`: friction laws, each declared once and registered;
* :mod:`stickslip.models`: parameter sets with units;
* :mod:`stickslip.orbits`: steady sliding's stability, periodic orbits, attractors polished into them;
* :mod:`stickslip.bifurcation`, :mod:`stickslip.dynamics`: branches and regimes, cycles and sweeps;
* :mod:`stickslip.data`, :mod:`stickslip.ratestate`, :mod:`stickslip.chains`, :mod:`stickslip.forced`:
  measured records, rate and state, chains of blocks, forced oscillators;
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
    from .bifurcation.regime_map import regime_map
    from .bifurcation.regimes import confirm, regimes
    from .chains import ChainParameters, chain, chain_ensemble
    from .data.criterion import classify
    from .data.fitting import fit_record
    from .data.records import analyze_records
    from .dynamics.cycle import Attractor, CycleResult, cycle
    from .dynamics.sweep import load_sweep, sweep
    from .dynamics.trajectory import Trajectory, simulate
    from .errors import ArgumentTypeError
    from .io.netcdf import load_dataset, save_dataset
    from .io.records import read_record, read_records
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
    from .ratestate.fitting import fit_rate_state
    from .ratestate.model import RateStateParameters
    from .ratestate.protocols import linear_stability, simulate_rate_state, slide_hold_slide, velocity_steps
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
    # the analyses, each from its family
    **dict.fromkeys(("load_sweep", "sweep"), "dynamics.sweep"),
    **dict.fromkeys(("confirm", "regimes"), "bifurcation.regimes"),
    "regime_map": "bifurcation.regime_map",
    **dict.fromkeys(("ChainParameters", "chain", "chain_ensemble"), "chains"),
    "analyze_records": "data.records",
    "classify": "data.criterion",
    "fit_record": "data.fitting",
    **dict.fromkeys(("read_record", "read_records"), "io.records"),
    **dict.fromkeys(("load_dataset", "save_dataset"), "io.netcdf"),
    "RateStateParameters": "ratestate.model",
    "fit_rate_state": "ratestate.fitting",
    **dict.fromkeys(
        ("linear_stability", "simulate_rate_state", "slide_hold_slide", "velocity_steps"),
        "ratestate.protocols",
    ),
}
_SUBPACKAGES = frozenset(
    {"bifurcation", "chains", "cli", "core", "data", "defaults", "dynamics", "explore", "io", "laws"}
    | {"errors", "models", "orbits", "paper", "plots", "ratestate", "scale", "units"}
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
    "ChainParameters",
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
    "RateStateParameters",
    "Scales",
    "TabulatedLaw",
    "Trajectory",
    "WeakeningLaw",
    "__version__",
    "analyze_records",
    "chain",
    "chain_ensemble",
    "classify",
    "confirm",
    "cycle",
    "f1",
    "f2",
    "fit_rate_state",
    "fit_record",
    "linear_stability",
    "load_dataset",
    "load_sweep",
    "read_record",
    "read_records",
    "regime_map",
    "regimes",
    "save_dataset",
    "simulate",
    "simulate_rate_state",
    "slide_hold_slide",
    "sweep",
    "ureg",
    "velocity_steps",
    "zv_parameters",
]
