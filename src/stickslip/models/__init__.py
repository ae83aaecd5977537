"""Model layer: parameter sets with units and validation (the laws are in :mod:`stickslip.laws`)."""

from .parameters import DimensionlessParameters, PhysicalParameters, Scales, zv_parameters

__all__ = ["DimensionlessParameters", "PhysicalParameters", "Scales", "zv_parameters"]
