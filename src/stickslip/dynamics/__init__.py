"""Dynamics: the motion from given starts, its steady oscillation, and sweeps of it.

:mod:`~stickslip.dynamics.cycle` (the attractors reached from rest and from
probes, polished into periodic orbits), :mod:`~stickslip.dynamics.trajectory`
(time series with events) and :mod:`~stickslip.dynamics.sweep` (grids of
parameter sets, streamed in chunks). The polish of attractors and the return map
are one layer down, in :mod:`stickslip.orbits`, shared with :mod:`stickslip.bifurcation`,
which sits beside this package and imports nothing of it
(:mod:`~stickslip.dynamics.attractors` and :mod:`~stickslip.dynamics.return_map` name
them here too).
"""

from .cycle import Attractor, CycleResult, cycle
from .trajectory import Trajectory, simulate

__all__ = ["Attractor", "CycleResult", "Trajectory", "cycle", "simulate"]
