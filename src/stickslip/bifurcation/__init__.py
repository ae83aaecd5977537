"""Bifurcation analysis: the branches of steady states and periodic orbits, and the regimes.

:mod:`~stickslip.bifurcation.regimes` (every branch over a range of ``nu`` and the
intervals of each set of attractors, checked by direct simulation), assembled from
:mod:`~stickslip.bifurcation.branches` (the branch, interval and diagram types),
:mod:`~stickslip.bifurcation.continuation` (the pure-slip branches born at Hopf points)
and :mod:`~stickslip.bifurcation.probes` (the stick-slip branch and the attractors the
engine reaches); :mod:`~stickslip.bifurcation.regime_map` (two-parameter maps and the
criterion on trial) and :mod:`~stickslip.bifurcation.averaging` (Thomsen and Fidlin's
closed forms). Steady sliding's stability, the periodic orbits and the polish of
attractors are one layer down, in :mod:`stickslip.orbits`, shared with
:mod:`stickslip.dynamics`, which sits beside this package and imports nothing of it
(:mod:`~stickslip.bifurcation.stability` and :mod:`~stickslip.bifurcation.orbits`, deprecated, name
them here too).
"""

from typing import TYPE_CHECKING

from ..lazy import exports

if TYPE_CHECKING:  # loaded on first use by __getattr__
    from .branches import Branch, Interval, SpecialPoint
    from .regimes import RegimeDiagram, confirm

# the functions regimes and regime_map are stickslip.regimes and stickslip.regime_map: here
# those names are their modules' (importing a submodule sets the package's attribute)
_HOME = {
    "RegimeDiagram": "regimes",
    "confirm": "regimes",
    "Branch": "branches",
    "Interval": "branches",
    "SpecialPoint": "branches",
}


__getattr__, __dir__ = exports(__name__, _HOME)

__all__ = [
    "Branch",
    "Interval",
    "RegimeDiagram",
    "SpecialPoint",
    "confirm",
]
