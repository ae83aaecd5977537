"""The polish of attractors into their orbits: :mod:`stickslip.orbits.attractors` at this path too.

This path names that very module (the same object in ``sys.modules``), not a copy of its
names: a setting changed here, such as ``COMPILED_RETURN_MAPS`` (from how many
slip-reversal rows on the return maps run compiled), is the one :func:`polish_rows` reads.
"""

import sys

from ..orbits import attractors as _attractors
from ..orbits.attractors import *  # noqa: F403
from ..orbits.attractors import __all__ as __all__
from ..userwarnings import moved

sys.modules[__name__] = _attractors

moved("stickslip.dynamics.attractors", "stickslip.orbits.attractors")
