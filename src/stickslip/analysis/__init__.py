"""Analysis on top of the engine: steady cycles, regimes, trajectories."""

from .cycle import Attractor, CycleResult, cycle
from .trajectory import Trajectory, simulate

__all__ = ["Attractor", "CycleResult", "Trajectory", "cycle", "simulate"]
