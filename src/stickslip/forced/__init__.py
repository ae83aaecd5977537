"""Forced friction oscillators: harmonic drive, base and force excitation, with exact stick.

The model and its scaling are in :mod:`.system`; the compiled engine in
:mod:`stickslip.core.forced`. Periodic responses, their Floquet multipliers and
response curves are in :mod:`.response`; trajectories, stroboscopic sections
and Lyapunov exponents in :mod:`.motion`; brute-force bifurcation diagrams in
:mod:`.diagram`; Den Hartog's closed form in :mod:`.denhartog`.
"""

from __future__ import annotations

from .denhartog import DenHartog, den_hartog
from .motion import (
    ForcedTrajectory,
    Lyapunov,
    Section,
    lyapunov,
    lyapunov_two_trajectories,
    poincare_section,
    trajectory,
)
from .response import ForcedOrbit, ResponseBifurcation, ResponseCurve, periodic_response, response_curve
from .system import ForcedSystem, PhysicalForcedSystem

__all__ = [
    "DenHartog",
    "ForcedOrbit",
    "ForcedSystem",
    "ForcedTrajectory",
    "Lyapunov",
    "PhysicalForcedSystem",
    "ResponseBifurcation",
    "ResponseCurve",
    "Section",
    "den_hartog",
    "lyapunov",
    "lyapunov_two_trajectories",
    "periodic_response",
    "poincare_section",
    "response_curve",
    "trajectory",
]
