"""Orbits: steady sliding and its stability, periodic orbits, and attractors polished into them.

The layer under both :mod:`stickslip.dynamics` (the motion from given starts, sweeps) and
:mod:`stickslip.bifurcation` (continuation, regimes), which build on it side by side:

* :mod:`~stickslip.orbits.stability`: the eigenvalues of steady sliding, its Hopf points
  and their criticality, the averaged amplitude of the small cycle;
* :mod:`~stickslip.orbits.periodic`: the pure-slip orbit by Newton shooting and the
  stick-slip orbit through breakaway with saltation matrices, with Floquet multipliers;
* :mod:`~stickslip.orbits.return_map`: non-sticking orbits (slip reversal too) as fixed
  points of the return map on ``w = nu``, computed by the exact non-smooth engine;
* :mod:`~stickslip.orbits.attractors`: what identifies an attractor (its kind and orbit),
  and the polish of the engine's rows into periodic orbits.
"""

from typing import TYPE_CHECKING

from ..lazy import exports

if TYPE_CHECKING:  # loaded on first use by __getattr__
    from .attractors import polish_rows
    from .periodic import PeriodicOrbit, StickSlipOrbit, pure_slip_orbit, stick_slip_orbit
    from .stability import Hopf, hopf_points, steady_sliding_eigenvalues

_HOME = {
    "PeriodicOrbit": "periodic",
    "StickSlipOrbit": "periodic",
    "pure_slip_orbit": "periodic",
    "stick_slip_orbit": "periodic",
    "Hopf": "stability",
    "hopf_points": "stability",
    "steady_sliding_eigenvalues": "stability",
    "polish_rows": "attractors",
}


__getattr__, __dir__ = exports(__name__, _HOME)

__all__ = [
    "Hopf",
    "PeriodicOrbit",
    "StickSlipOrbit",
    "hopf_points",
    "polish_rows",
    "pure_slip_orbit",
    "steady_sliding_eigenvalues",
    "stick_slip_orbit",
]
