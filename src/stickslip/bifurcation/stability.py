"""Steady sliding's stability and Hopf points: :mod:`stickslip.orbits.stability`, re-exported."""

from ..orbits.stability import *  # noqa: F403
from ..orbits.stability import __all__ as __all__
from ..userwarnings import moved

moved("stickslip.bifurcation.stability", "stickslip.orbits.stability")
