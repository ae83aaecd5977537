"""Non-sticking orbits from the return map on ``w = nu``: :mod:`stickslip.orbits.return_map`, re-exported."""

from ..orbits.return_map import *  # noqa: F403
from ..orbits.return_map import __all__ as __all__
from ..userwarnings import moved

moved("stickslip.dynamics.return_map", "stickslip.orbits.return_map")
