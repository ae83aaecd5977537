"""Chains of blocks: the Burridge-Knopoff model with N blocks, every block's stick exact.

* :mod:`.model`: the set-up (:class:`ChainParameters`), thresholds, initial positions;
* :mod:`.run`: :func:`chain`, events streamed to a NetCDF catalogue;
* :mod:`.catalog`: the catalogue on disk;
* :mod:`.statistics`: b-value, recurrence, and the names of the three below;
* :mod:`.magnitudes`: magnitude-frequency counts, completeness, the maximum-likelihood slope;
* :mod:`.powerlaw`: the range of magnitudes that is a power law, and its tests;
* :mod:`.ruptures`: connected ruptures, and events whose slips are in pieces;
* :mod:`.lyapunov`: the event map and its largest Lyapunov exponent;
* :mod:`.ensemble`: many seeds of one set-up (:func:`chain_ensemble`), on Dask and in a store.
"""

from .catalog import open_catalog
from .ensemble import chain_ensemble
from .model import Boundary, ChainParameters, Init, initial_positions, static_thresholds
from .run import ChainResult, chain
from .statistics import (
    BValue,
    b_value,
    block_length,
    completeness_magnitude,
    connected_ruptures,
    magnitude_frequency,
    power_law_range,
    recurrence_times,
    slope_change,
)

__all__ = [
    "BValue",
    "Boundary",
    "ChainParameters",
    "ChainResult",
    "Init",
    "b_value",
    "block_length",
    "chain",
    "chain_ensemble",
    "completeness_magnitude",
    "connected_ruptures",
    "initial_positions",
    "magnitude_frequency",
    "open_catalog",
    "power_law_range",
    "recurrence_times",
    "slope_change",
    "static_thresholds",
]
