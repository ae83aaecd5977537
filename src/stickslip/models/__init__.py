"""Model layer: the one-block set-ups with units and validation, their scales, and named presets.

- :mod:`~stickslip.models.parameters`: physical and dimensionless parameter sets, and the map
  between them (one formula for every law of the registry);
- :mod:`~stickslip.models.scales`: the scales of the dimensionless model in SI
  (:class:`Scales`, with ``to_si``/``from_si``) and the one table of unit labels;
- :mod:`~stickslip.models.presets`: named set-ups (the paper's ``zv``).

The laws themselves are in :mod:`stickslip.laws`.
"""

from .parameters import DimensionlessParameters, PhysicalParameters, zv_parameters
from .presets import PRESETS, Preset
from .scales import UNITS, Scales, unit_attrs, unit_label

__all__ = [
    "PRESETS",
    "UNITS",
    "DimensionlessParameters",
    "PhysicalParameters",
    "Preset",
    "Scales",
    "unit_attrs",
    "unit_label",
    "zv_parameters",
]
