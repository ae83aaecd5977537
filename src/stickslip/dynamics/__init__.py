"""Dynamics: the motion from given starts, its steady oscillation, and sweeps of it.

:mod:`~stickslip.dynamics.cycle` (the attractors reached from rest and from
probes, polished into periodic orbits), :mod:`~stickslip.dynamics.trajectory`
(time series with events) and :mod:`~stickslip.dynamics.sweep` (grids of
parameter sets, streamed in chunks). The polish of attractors and the return map
are one layer down, in :mod:`stickslip.orbits`, shared with :mod:`stickslip.bifurcation`,
which sits beside this package and imports nothing of it
(:mod:`~stickslip.dynamics.attractors` and :mod:`~stickslip.dynamics.return_map`, deprecated, name
them here too).
"""

from typing import TYPE_CHECKING

from ..lazy import exports
from .cycle import Attractor, CycleResult, cycle
from .trajectory import Trajectory, simulate

if TYPE_CHECKING:  # loaded on first use (xarray) by __getattr__
    from .sweep import load_sweep

# the function sweep is stickslip.sweep: here the name is its module's (importing a
# submodule sets the package's attribute of that name)
_HOME = {"load_sweep": "sweep"}


__getattr__, __dir__ = exports(__name__, _HOME)

__all__ = ["Attractor", "CycleResult", "Trajectory", "cycle", "load_sweep", "simulate"]
