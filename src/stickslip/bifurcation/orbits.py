"""Periodic orbits by shooting and with saltation: :mod:`stickslip.orbits.periodic`, re-exported."""

from ..orbits.periodic import *  # noqa: F403
from ..orbits.periodic import __all__ as __all__
