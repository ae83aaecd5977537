"""Periodic orbits by shooting and with saltation: :mod:`stickslip.orbits.periodic`, re-exported."""

from ..orbits.periodic import *  # noqa: F403
from ..orbits.periodic import __all__ as __all__
from ..userwarnings import moved

moved("stickslip.bifurcation.orbits", "stickslip.orbits.periodic")
